# A partial written before the solver seam (no solver, check_every or contact_stiffness_N_m2 parameter, no law_residual columns) resumes as the rigid NSGS run it was, and every other dataset is the same as a run never interrupted.
# ctest: slow, timeout 120
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
# the settings of a run made before the seam: rigid NSGS without sub-steps
old=(--solver nsgs --max-substeps 1 --substep-after 100)
opts=(--to 4 --rate 0.001 "${old[@]}" --checkpoint-every 500 --frame-every 400 --quiet)
tilt-cd pile.h5 -o ref.h5 "${opts[@]}" --stiffness 0
tilt-cd pile.h5 -o run.h5 "${opts[@]}" --stiffness 0 & pid=$!
for _ in $(seq 100); do [[ -e run.h5.partial ]] && break; sleep 0.02; done  # started
sleep 0.1
kill -INT "$pid"
rc=0; wait "$pid" || rc=$?
expect_eq 130 "$rc"
"$PY" - <<'PY'
import h5py
with h5py.File("run.h5.partial", "a") as f:
    assert f["checkpoint"].attrs["step"] < 4000, "the run ended before the interrupt; lengthen it"
    for k in ("solver", "check_every", "contact_stiffness_N_m2"):
        del f["parameters"].attrs[k]
    for k in ("law_residual", "law_residual_rms"):
        del f["observables/" + k]
PY
tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}" --stiffness 0
test ! -e run.h5.partial
h5diff --exclude-path /provenance --exclude-path /observables/law_residual \
  --exclude-path /observables/law_residual_rms --exclude-path /parameters ref.h5 run.h5
# A resume with another stiffness than the run's (0) is refused, naming it.
tilt-cd pile.h5 -o two.h5 "${opts[@]}" --stiffness 0 & pid=$!
for _ in $(seq 100); do [[ -e two.h5.partial ]] && break; sleep 0.02; done
sleep 0.1
kill -INT "$pid"; wait "$pid" || true
"$PY" -c '
import h5py
with h5py.File("two.h5.partial", "a") as f: del f["parameters"].attrs["contact_stiffness_N_m2"]'
rc=0; tilt-cd pile.h5 -o two.h5 --resume "${opts[@]}" --stiffness 1e6 2> err.txt || rc=$?
expect_eq 2 "$rc"
grep -q -- "--stiffness 1e6: contact_stiffness_N_m2 .* instead of the run's 0 in the interrupted run" err.txt
