# --solver pcg (docs/method.md, "The pcg solver"): NSGS sweeps alternating with conjugate-gradient rounds on the active set. Recorded in /parameters; through a small pile's avalanche at k = 1e6 m g / D, capped at 400 sweeps, every pcg step converges where NSGS leaves some at the cap, in fewer sweeps; a pcg run killed and resumed is the run never interrupted, bit for bit.
deposit --grains 60 --width 8 --seed 3 --stiffness 0 --solver nsgs --max-substeps 1 --tolerance 1e-4 -o pile.h5 --quiet
opts=(--rate 0.05 --stiffness 1e6 --tolerance 1e-4 --max-sweeps 400 --max-substeps 1 --checkpoint-every 20 --quiet)
tilt-cd pile.h5 "${opts[@]}" --solver nsgs -o nsgs.h5
tilt-cd pile.h5 "${opts[@]}" --solver pcg -o ref.h5
"$PY" - <<'PY'
import h5py, numpy as np
with h5py.File("ref.h5", "r") as p, h5py.File("nsgs.h5", "r") as n:
    assert p["parameters"].attrs["solver"] == b"pcg", p["parameters"].attrs["solver"]
    assert n["parameters"].attrs["solver"] == b"nsgs"
    for f in (p, n):
        assert int(f["results"].attrs["avalanche_detected"]) == 1
    assert int(n["results"].attrs["unconverged_steps"]) > 0, "NSGS converged: no test"
    assert int(p["results"].attrs["unconverged_steps"]) == 0
    sp, sn = (f["observables/sweeps/value"][:] for f in (p, n))
    assert sp.mean() < 0.6 * sn.mean(), (sp.mean(), sn.mean())
    assert np.all(np.isfinite(p["observables/law_residual/value"][:]))
PY
kill_then_resume 2 10 pile.h5 "${opts[@]}" --solver pcg -o run.h5
h5diff --exclude-path /provenance ref.h5 run.h5
