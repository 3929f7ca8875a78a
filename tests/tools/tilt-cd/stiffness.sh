# --stiffness K (in m g / D) is recorded in SI as contact_stiffness_N_m2 = K m g / D, m the pile's mean grain mass and D its mean diameter; 0 is rigid, and a negative K is a usage error.
deposit --grains 60 --width 10 --seed 2 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.05 --rate 0.01 --stiffness 1e6 -o soft.h5 --quiet
tilt-cd pile.h5 --to 0.05 --rate 0.01 --stiffness 0 -o rigid.h5 --quiet
"$PY" - <<'PY'
import h5py, numpy as np
with h5py.File("pile.h5", "r") as p, h5py.File("soft.h5", "r") as s, h5py.File("rigid.h5", "r") as r:
    g = p["particles/grains"]
    species = g["species/value"][0] if "value" in g["species"] else g["species"][:]
    free = species == 0
    mass = g["mass/value"][0] if "value" in g["mass"] else g["mass"][:]
    D = float(p["parameters"].attrs["diameter_mean_m"])
    gravity = float(p["parameters"].attrs["gravity_m_s2"])
    want = 1e6 * mass[free].mean() * gravity / D
    got = float(s["parameters"].attrs["contact_stiffness_N_m2"])
    assert abs(got - want) <= 1e-12 * want, (got, want)
    assert float(r["parameters"].attrs["contact_stiffness_N_m2"]) == 0.0
    for f in (s, r):
        law = f["observables/law_residual/value"][:] if "value" in f["observables/law_residual"] else f["observables/law_residual"][:]
        assert law.size > 0 and np.all(np.isfinite(law)) and np.all(law >= 0)
PY
expect_fail 2 "tilt-cd: --stiffness: expected a finite number in [0, 1e+300], got '-1' (out of range) (see 'tilt-cd --help')" \
  tilt-cd pile.h5 --stiffness -1 -o out.h5
test ! -e out.h5
