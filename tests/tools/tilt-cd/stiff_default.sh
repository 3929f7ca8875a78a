# The default solver (pcg, tolerance 1e-6, sub-steps after 1000 sweeps) at k = 1e8 m g / D, where Gauss-Seidel alone is as slow as for rigid contacts (docs/method.md, "The pcg solver"): a small pile tilted through its avalanche, a rearranging window, has every step converged, its contact law satisfied to 1e-4 g h at every step, and the rescue split some steps.
deposit --grains 60 --width 8 --seed 3 --stiffness 0 --solver nsgs --max-substeps 1 --tolerance 1e-4 -o pile.h5 --quiet
tilt-cd pile.h5 --rate 0.05 --stiffness 1e8 -o run.h5 --quiet 2> stderr.txt
expect_eq 0 "$(wc -c < stderr.txt)" "(bytes on stderr)"
"$PY" - <<'PY'
import h5py, numpy as np
with h5py.File("run.h5", "r") as f:
    r, o = f["results"].attrs, f["observables"]
    assert f["parameters"].attrs["solver"] == b"pcg"
    assert int(r["avalanche_detected"]) == 1, dict(r)
    assert int(r["unconverged_steps"]) == 0, dict(r)
    assert o["converged/value"][:].min() == 1
    law = o["law_residual/value"][:]
    assert np.all(np.isfinite(law)) and law.max() < 1e-4, law.max()
    assert o["substeps/value"][:].max() > 1, "no step needed the rescue: no test of it"
PY
