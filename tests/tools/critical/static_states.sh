# Static and moving states on a real run (80 disks, k = 1e5, tilted at 0.05 deg/step past
# the avalanche): a frame is static exactly when its step is (the engine's per-step
# observables and the frame's grains and contacts agree), static frames meet every part of
# the rule, the avalanche's frames are moving, and the results count them.
deposit --grains 80 --width 10 --seed 2 --quiet -o pile.h5
tilt-cd pile.h5 --rate 0.05 --stiffness 1e5 --frame-every-deg 0.5 --quiet -o run.h5
critical run.h5 --table steps,frames --quiet > c.tsv
critical run.h5 -o c.h5 --quiet
"$PY" - <<'PYEOF'
import h5py, numpy as np
c = h5py.File("c.h5", "r")
st, fr, res = c["tables/steps"], c["tables/frames"], c["results"].attrs
step_static = dict(zip(st["step"][()], st["static"][()]))
fs = fr["static"][()]
checked = 0
for k in range(1, fs.size):  # frame 0 is the pile before the first step
    assert fs[k] == step_static[fr["step"][k]], (k, fs[k], step_static[fr["step"][k]])
    checked += 1
assert checked >= 10, checked
s = fs == 1
assert s.sum() >= 3 and (~s).sum() >= 3, (s.sum(), (~s).sum())
assert np.all(fr["agitation_norm"][()][s] < 1e-6) and np.all(fr["max_speed_norm"][()][s] < 1e-2)
assert np.all(fr["grains_without_contact"][()][s] == 0) and np.all(fr["converged"][()][1:][s[1:]] == 1)
# a moving frame breaks the rule somewhere
m = ~s
assert np.all((fr["agitation_norm"][()][m] >= 1e-6) | (fr["max_speed_norm"][()][m] >= 1e-2)
              | (fr["grains_without_contact"][()][m] > 0) | (fr["converged"][()][m] != 1))
# contacts at rest: neither a fast body nor slip, so never a slipping one, and in a static
# frame (every grain slow) exactly the contacts that do not slip
N, Nr, slip = fr["N"][()], fr["N_rest"][()], fr["slipping"][()]
assert np.all(Nr <= N - slip) and np.all(Nr[s] == N[s] - slip[s]), (N[s], Nr[s], slip[s])
assert np.all(fr["Nc_rest"][()] <= fr["Nc"][()])
# past the avalanche the pile flows: no static frame there
tc = res["theta_c_deg"]
assert not np.any(s & (fr["theta"][()] > tc + 0.5)), tc
loading = st["theta"][()] <= tc
assert res["static_steps"] == int(np.sum(st["static"][()][loading] == 1))
assert res["static_frames"] == int(np.sum(s & (fr["loading"][()] == 1)))
# the mobilisation pdf of each window integrates to 1 over [0, 1]
mob = c["tables/mobilisation"]
for lo in np.unique(mob["theta_lo"][()]):
    w = mob["theta_lo"][()] == lo
    if mob["contacts"][()][w].sum():
        assert abs(np.sum(mob["pdf"][()][w] * 0.05) - 1) < 1e-12
PYEOF
# The TSV says the same as the HDF5 product.
expect_eq "$("$PY" -c "import h5py; print(int(h5py.File('c.h5')['tables/frames']['static'][()][3]))")" "$(tsv_value c.tsv frames static 4)"
