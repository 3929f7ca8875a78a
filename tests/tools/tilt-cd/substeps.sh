# --max-substeps N --substep-after S: a step not converged after S sweeps is done again as two half steps, down to h / N (docs/method.md, "Sub-steps"); both are recorded in /parameters, every step's sub-steps in /observables/substeps, and a run killed and resumed is the run never interrupted, bit for bit (the sub-step level is in the checkpoint). A stiff pile (k = 1e7 m g / D) capped at 60 sweeps splits and converges every step.
deposit --grains 100 --width 12 --seed 2 --stiffness 0 --solver nsgs --max-substeps 1 --max-sweeps 2000 --tolerance 1e-4 -o pile.h5 --quiet
opts=(--to 1.5 --rate 0.005 --stiffness 1e7 --solver nsgs --tolerance 1e-4 --max-sweeps 60 --max-substeps 16 --substep-after 10
      --checkpoint-every 20 --frame-every 50 --quiet)
tilt-cd pile.h5 -o ref.h5 "${opts[@]}"
tilt-cd pile.h5 -o unsplit.h5 --to 1.5 --rate 0.005 --stiffness 1e7 --solver nsgs --tolerance 1e-4 --max-substeps 1 --max-sweeps 60 --quiet 2> unsplit.err || true
"$PY" - <<'PY'
import h5py, numpy as np
with h5py.File("ref.h5", "r") as f, h5py.File("unsplit.h5", "r") as u:
    p = f["parameters"].attrs
    assert int(p["max_substeps"]) == 16 and int(p["substep_after"]) == 10, dict(p)
    assert int(u["parameters"].attrs["max_substeps"]) == 1
    sub = f["observables/substeps/value"][:]
    assert sub.min() >= 1 and sub.max() <= 16, (sub.min(), sub.max())
    assert (sub > 1).sum() > 0, "no step was split"
    assert f["observables/converged/value"][:].min() == 1, "a split run left a step unconverged"
    assert u["observables/converged/value"][:].min() == 0, "the unsplit run converged: no test"
    assert np.all(u["observables/substeps/value"][:] == 1)
PY
kill_then_resume 2 20 pile.h5 -o run.h5 "${opts[@]}"
h5diff --exclude-path /provenance ref.h5 run.h5
expect_fail 2 "tilt-cd: --max-substeps: expected a power of two in [1, 1024], got '3' (see 'tilt-cd --help')" \
  tilt-cd pile.h5 --max-substeps 3 -o out.h5
test ! -e out.h5
