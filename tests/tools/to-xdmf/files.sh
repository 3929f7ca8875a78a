# to-xdmf writes, beside its output, an XDMF file of the grains naming the data by its path relative to the XDMF, a second one of the force network, gravity and walls, an HDF5 file of each frame's arrays (virtual datasets reading the run's rows in place; critical flags by the run's rule, fn / <fn>, per-grain nu) and a ParaView state; it refuses standard input, an existing output without --force, and files it cannot show.
deposit --grains 20 --width 5 --seed 4 --quiet -o pile.h5
tilt-cd pile.h5 --rate 2 --to 4 --frame-every 1 --quiet -o run.h5
mkdir views
to-xdmf run.h5 -o views/run.xdmf --nu-radius 2 --quiet
for f in views/run.xdmf views/run.network.xdmf views/run.xdmf.hdf5 views/run.paraview.py; do test -s "$f"; done
cd views  # the virtual datasets find the run by its path relative to the derived file
"$PY" - <<'PY'
import xml.etree.ElementTree as ET, h5py, numpy as np
x = ET.parse("run.xdmf").getroot()
grids = {g.get("Name"): g for g in x.find("Domain").findall("Grid")}
assert sorted(grids) == ["grains"], sorted(grids)  # File > Open loads the grains alone
n = ET.parse("run.network.xdmf").getroot()
over = {g.get("Name"): g for g in n.find("Domain").findall("Grid")}
assert sorted(over) == ["contacts", "gravity", "walls"], sorted(over)
f = h5py.File("../run.h5", "r")
F = f["particles/grains/position/step"].shape[0]
assert all(len(g.findall("Grid")) == F for g in list(grids.values()) + list(over.values()))
refs = {e.text.split(":")[0] for e in x.iter("DataItem") if e.get("Format") == "HDF"}
assert refs == {"../run.h5", "run.xdmf.hdf5"}, refs
refs = {e.text.split(":")[0] for e in n.iter("DataItem") if e.get("Format") == "HDF"}
assert refs == {"run.xdmf.hdf5"}, refs
# no hyperslab nor function: ParaView's Xdmf3 reader reads neither (it crashed on them)
assert not [e for e in list(x.iter("DataItem")) + list(n.iter("DataItem")) if e.get("ItemType")]
names = [a.get("Name") for a in grids["grains"].find("Grid").findall("Attribute")]
assert names == ["radius", "species", "mass", "velocity", "angular_velocity", "orientation", "nu", "tilt_angle", "step"], names
# the derived file: the run's rows in place (virtual datasets), critical flags by the run's
# rule, fn / <fn>, nu in [0, 1] or NaN
s = h5py.File("run.xdmf.hdf5", "r")
c, p = f["contacts"], f["parameters"].attrs
g = f["particles/grains"]
mu = np.where(c["j"][:] < 0, p["mu_wall"], p["mu_grain"])
want = (c["fn"][:] > 0) & (np.abs(c["ft"][:]) >= (1 - p["critical_eps"]) * mu * c["fn"][:])
for k, (o, m) in enumerate(zip(c["offset"][:], c["count"][:])):
    fr = s[f"frames/{k}"]
    assert fr["position"].is_virtual and {v.file_name for v in fr["position"].virtual_sources()} == {"../run.h5"}
    assert (fr["position"][:] == g["position/value"][k]).all()
    assert (fr["velocity"][:, :2] == g["velocity/value"][k]).all() and (fr["velocity"][:, 2] == 0).all()
    assert (fr["contacts/fn"][:] == c["fn"][o:o + m]).all() and (fr["contacts/j"][:] == c["j"][o:o + m]).all()
    assert (fr["contacts/critical"][:] == want[o:o + m]).all()
    fn = c["fn"][o:o + m]
    assert np.allclose(fr["contacts/fn_rel"][:] * fn[fn > 0].mean(), fn, rtol=1e-14, atol=0)
    pts, lines = fr["network/points"][:], fr["network/lines"][:]
    N = g["radius"].shape[0]
    assert (pts[:N] == g["position/value"][k]).all() and (pts[N:] == c["point"][o:o + m]).all()
    j = c["j"][o:o + m]
    assert (lines[:, 0] == c["i"][o:o + m]).all()
    assert (lines[:, 1] == np.where(j >= 0, j, N + np.arange(m))).all()
    nu = fr["nu"][:]
    assert nu.shape == (N,) and np.nanmin(nu) >= 0 and np.nanmax(nu) <= 1
PY
cd ..
# not from standard input, not over an existing file, not a product it cannot show
expect_fail 2 "to-xdmf: the input must be a file: an XDMF file refers to its data by file name (see 'to-xdmf --help')" \
  to-xdmf - < run.h5
expect_fail 1 "to-xdmf: views/run.xdmf: exists; not overwritten (use --force to replace it)" \
  to-xdmf run.h5 -o views/run.xdmf
to-xdmf run.h5 -o views/run.xdmf --force --quiet
critical run.h5 --quiet -o crit.h5
expect_fail 1 "to-xdmf: crit.h5: /: is a 'critical' product; to-xdmf shows piles, runs and localnu maps" to-xdmf crit.h5
test ! -e crit.xdmf
localnu run.h5 --quiet --table frames > nu.tsv
expect_fail 1 "to-xdmf: nu.tsv: not an HDF5 file (no HDF5 signature)" to-xdmf nu.tsv
