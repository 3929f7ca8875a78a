# The tools' solver defaults (docs/method.md, "Defaults and their reasons"): k = 1e6 m g / D, the pcg solver, tolerance 1e-6, sub-steps after 1000 sweeps down to h/64, recorded in /parameters by deposit and tilt-cd alike; a small pile deposited and tilted through its avalanche with no solver option has no step at the cap.
deposit --grains 60 --width 8 --seed 3 -o pile.h5 --quiet
tilt-cd pile.h5 --rate 0.05 -o run.h5 --quiet 2> stderr.txt
expect_eq 0 "$(wc -c < stderr.txt)" "(bytes on stderr)"
"$PY" - <<'PY'
import h5py
for path in ("pile.h5", "run.h5"):
    with h5py.File(path, "r") as f:
        p = f["parameters"].attrs
        g = f["particles/grains"]
        species = g["species/value"][0] if "value" in g["species"] else g["species"][:]
        mass = g["mass/value"][0] if "value" in g["mass"] else g["mass"][:]
        mg_D = mass[species == 0].mean() * float(p["gravity_m_s2"]) / float(p["diameter_mean_m"])
        k = float(p["contact_stiffness_N_m2"])
        # deposit converts with the mean mass of the size distribution, tilt-cd with the
        # pile's own: 1e6 m g / D within the sampling of 60 grains
        assert abs(k - 1e6 * mg_D) <= (1e-12 if path == "run.h5" else 1e-2) * k, (path, k, 1e6 * mg_D)
        assert p["solver"] in (b"pcg", "pcg"), (path, p["solver"])
        assert float(p["tolerance"]) == 1e-6, (path, p["tolerance"])
        assert int(p["max_substeps"]) == 64 and int(p["substep_after"]) == 1000, path
with h5py.File("pile.h5", "r") as f:
    assert int(f["results"].attrs["unconverged_steps"]) == 0
with h5py.File("run.h5", "r") as f:
    r = f["results"].attrs
    assert int(r["avalanche_detected"]) == 1, dict(r)
    assert int(r["unconverged_steps"]) == 0, dict(r)
    assert f["observables/converged/value"][:].min() == 1
PY
