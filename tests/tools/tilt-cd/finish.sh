# --finish-after N: a step not converged after N sweeps is handed to the active-set Newton on its problem (docs/method.md, "Finishing a step by its active set"); the option is recorded in /parameters, every step's finishes in /observables/finishes, and a run killed and resumed is the run never interrupted, bit for bit. A stiff pile (k = 1e7 m g / D) capped at 60 sweeps unsplit stops short on some steps; with the finish after 20 sweeps every step converges at h, the hard ones finished.
deposit --grains 100 --width 12 --seed 2 --stiffness 0 --solver nsgs --max-substeps 1 --max-sweeps 2000 --tolerance 1e-4 -o pile.h5 --quiet
opts=(--to 1.5 --rate 0.005 --stiffness 1e7 --solver nsgs --tolerance 1e-4 --max-sweeps 60 --max-substeps 1 --finish-after 20
      --checkpoint-every 20 --frame-every 50 --quiet)
tilt-cd pile.h5 -o ref.h5 "${opts[@]}"
tilt-cd pile.h5 -o plain.h5 --to 1.5 --rate 0.005 --stiffness 1e7 --solver nsgs --tolerance 1e-4 --max-substeps 1 --max-sweeps 60 --quiet 2> plain.err || true
"$PY" - <<'PY'
import h5py, numpy as np
with h5py.File("ref.h5", "r") as f, h5py.File("plain.h5", "r") as u:
    assert int(f["parameters"].attrs["finish_after"]) == 20, dict(f["parameters"].attrs)
    assert int(u["parameters"].attrs["finish_after"]) == 0
    fin = f["observables/finishes/value"][:]
    assert fin.min() >= 0 and fin.max() <= 1, (fin.min(), fin.max())
    assert fin.sum() > 0, "no step was finished"
    assert f["observables/converged/value"][:].min() == 1, "a finished run left a step unconverged"
    assert np.all(f["observables/substeps/value"][:] == 1)
    sw = f["observables/sweeps/value"][:]
    assert np.all(sw[fin == 1] > 20), "a step finished before its 20 sweeps"
    assert f["observables/law_residual/value"][:].max() < 1e-2
    assert u["observables/converged/value"][:].min() == 0, "the plain run converged: no test"
    assert np.all(u["observables/finishes/value"][:] == 0)
PY
kill_then_resume 2 20 pile.h5 -o run.h5 "${opts[@]}"
h5diff --exclude-path /provenance ref.h5 run.h5
expect_fail 2 "tilt-cd: --finish-after: expected an integer in [0, 100000000], got '-1' (out of range) (see 'tilt-cd --help')" \
  tilt-cd pile.h5 --finish-after -1 -o out.h5
test ! -e out.h5
