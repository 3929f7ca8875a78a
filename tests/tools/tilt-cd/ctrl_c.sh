# Ctrl-C stops after the current step with exit 130, leaving OUTPUT.partial a valid run
# of every completed step (no final output yet); --resume finishes the same run.
# ctest: slow, timeout 120
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
opts=(--to 4 --rate 0.001 --checkpoint-every 500 --frame-every 400)
tilt-cd pile.h5 -o run.h5 "${opts[@]}" 2> stderr.txt & pid=$!
for _ in $(seq 100); do [[ -e run.h5.partial ]] && break; sleep 0.02; done  # started
sleep 0.1
kill -INT "$pid"
rc=0; wait "$pid" || rc=$?
expect_eq 130 "$rc"
test ! -e run.h5
grep -q "interrupted at step .* run.h5.partial holds it; run again with --resume to continue" stderr.txt
cli-demo run.h5.partial > /dev/null
"$PY" - <<'PY'
import h5py, numpy as np
f = h5py.File("run.h5.partial", "r")
steps = f["observables/tilt_angle/step"][:]
assert len(steps) > 0 and list(steps) == list(range(1, len(steps) + 1))  # every completed step
assert f["checkpoint"].attrs["step"] == steps[-1]
assert steps[-1] < 4000, "the run ended before the interrupt; lengthen it"
PY
tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}" --quiet
tilt-cd pile.h5 -o ref.h5 "${opts[@]}" --quiet
h5diff --exclude-path /provenance ref.h5 run.h5
# SIGTERM: the same clean stop, with exit 143 (128 + 15) as docs/cli.md says.
rm -f run.h5
tilt-cd pile.h5 -o term.h5 "${opts[@]}" 2> stderr.txt & pid=$!
for _ in $(seq 100); do [[ -e term.h5.partial ]] && break; sleep 0.02; done
sleep 0.1
kill -TERM "$pid"
rc=0; wait "$pid" || rc=$?
expect_eq 143 "$rc"
test ! -e term.h5
grep -q "interrupted at step .* term.h5.partial holds it" stderr.txt
