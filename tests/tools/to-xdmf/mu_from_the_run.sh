# to-xdmf takes mu from the run (mu_grain, mu_wall) unless --mu is given; a run without mu_grain is an error naming the file and what is missing, with no file left, not a silent mu = 0.5; with --mu its critical flags and mobilisation are those of the run with that mu recorded.
deposit --grains 20 --width 5 --seed 4 --quiet -o pile.h5
tilt-cd pile.h5 --rate 2 --to 4 --frame-every 1 --quiet -o run.h5
cp run.h5 nomu.h5
"$PY" - <<'PY'
import h5py
with h5py.File("nomu.h5", "r+") as f:
    p = f["parameters"].attrs
    assert p["mu_grain"] == 0.5 and p["mu_wall"] == 0.5
    del p["mu_grain"], p["mu_wall"]
PY
expect_fail 1 "to-xdmf: nomu.h5: /parameters: no mu_grain; give --mu" to-xdmf nomu.h5
test ! -e nomu.xdmf && test ! -e nomu.xdmf.hdf5 && test ! -e nomu.network.xdmf && test ! -e nomu.paraview.py
# an analysis refuses mu = 0 (every active contact would be critical), in --mu's one range [0, 1000]
expect_fail 2 "to-xdmf: --mu must be > 0 (mu = 0 makes every active contact critical), got 0 (see 'to-xdmf --help')" \
  to-xdmf nomu.h5 --mu 0
expect_fail 2 "to-xdmf: --mu: expected a finite number in [0, 1000], got '1e4' (out of range) (see 'to-xdmf --help')" \
  to-xdmf nomu.h5 --mu 1e4
to-xdmf nomu.h5 --mu 0.5 --quiet
to-xdmf run.h5 --quiet
"$PY" - <<'PY'
import h5py, numpy as np
a, b = h5py.File("run.xdmf.hdf5", "r"), h5py.File("nomu.xdmf.hdf5", "r")
assert len(a["frames"]) == len(b["frames"]) == 3
for k in a["frames"]:
    for name in ("contacts/critical", "contacts/mobilisation", "nu"):
        if name in a["frames"][k]:
            assert np.array_equal(a["frames"][k][name][:], b["frames"][k][name][:], equal_nan=True), (k, name)
PY
