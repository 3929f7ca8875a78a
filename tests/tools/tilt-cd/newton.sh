# --solver newton (docs/method.md, "The newton solver"): NSGS sweeps alternating with exact Newton steps on the active face. Recorded in /parameters; through a small pile's avalanche at the tools' k = 1e6 m g / D and tolerance 1e-6 every step converges, and a newton run killed and resumed is the run never interrupted, bit for bit.
deposit --grains 60 --width 8 --seed 3 --stiffness 0 --solver nsgs --max-substeps 1 --tolerance 1e-4 -o pile.h5 --quiet
opts=(--rate 0.05 --solver newton --max-sweeps 2000 --checkpoint-every 20 --quiet)
tilt-cd pile.h5 "${opts[@]}" -o ref.h5
"$PY" - <<'PY'
import h5py, numpy as np
with h5py.File("ref.h5", "r") as f:
    assert f["parameters"].attrs["solver"] == b"newton", f["parameters"].attrs["solver"]
    assert int(f["results"].attrs["avalanche_detected"]) == 1
    assert int(f["results"].attrs["unconverged_steps"]) == 0
    law = f["observables/law_residual/value"][:]
    assert np.all(np.isfinite(law)) and law.max() < 1e-3, law.max()
PY
kill_then_resume 2 10 pile.h5 "${opts[@]}" -o run.h5
h5diff --exclude-path /provenance ref.h5 run.h5
