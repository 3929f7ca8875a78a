# A small pile tilted through its avalanche at k = 1e8 m g / D (k h^2 / m = 1e4, as hard as rigid contacts for Gauss-Seidel): capped at 100 sweeps, a fifth of the unsplit steps stop at the cap; with sub-steps down to h/256 every step converges, and the pile avalanches.
deposit --grains 60 --width 8 --seed 3 --stiffness 0 --solver nsgs --max-substeps 1 --tolerance 1e-4 -o pile.h5 --quiet
opts=(--rate 0.05 --stiffness 1e8 --solver nsgs --tolerance 1e-4 --max-sweeps 100)
tilt-cd pile.h5 "${opts[@]}" --max-substeps 1 -o unsplit.h5 --quiet 2> unsplit.err
grep -q "hit the sweep cap; their forces are not converged (allow sub-steps, --max-substeps 64; docs/method.md, Sub-steps)" unsplit.err
tilt-cd pile.h5 "${opts[@]}" --max-substeps 256 --substep-after 30 -o split.h5 --quiet 2> split.err
expect_eq "" "$(cat split.err)" "(the split run warned)"
"$PY" - <<'PY'
import h5py, numpy as np
with h5py.File("split.h5", "r") as s, h5py.File("unsplit.h5", "r") as u:
    for f in (s, u):
        assert int(f["results"].attrs["avalanche_detected"]) == 1
    assert int(u["results"].attrs["unconverged_steps"]) > 0.1 * int(u["results"].attrs["steps"])
    assert int(s["results"].attrs["unconverged_steps"]) == 0
    assert s["observables/converged/value"][:].min() == 1
    sub = s["observables/substeps/value"][:]
    assert sub.max() > 16, sub.max()  # the stiff steps split deep
    law = s["observables/law_residual/value"][:]
    assert np.all(np.isfinite(law))
PY
