# A partial written before the residual_rms observable existed still resumes: the run goes on without that column, and every other dataset is the same as a run never interrupted.
# ctest: slow, timeout 120
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
opts=(--to 4 --rate 0.001 --checkpoint-every 500 --frame-every 400 --quiet)
tilt-cd pile.h5 -o ref.h5 "${opts[@]}"
tilt-cd pile.h5 -o run.h5 "${opts[@]}" & pid=$!
for _ in $(seq 100); do [[ -e run.h5.partial ]] && break; sleep 0.02; done  # started
sleep 0.1
kill -INT "$pid"
rc=0; wait "$pid" || rc=$?
expect_eq 130 "$rc"
# Make the partial what an earlier version wrote: no residual_rms column.
"$PY" - <<'PY'
import h5py
with h5py.File("run.h5.partial", "a") as f:
    assert "residual_rms" in f["observables"]
    assert f["checkpoint"].attrs["step"] < 4000, "the run ended before the interrupt; lengthen it"
    del f["observables/residual_rms"]
PY
tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}"
test ! -e run.h5.partial
"$PY" -c 'import h5py, sys; sys.exit("residual_rms" in h5py.File("run.h5", "r")["observables"])'
h5diff --exclude-path /provenance --exclude-path /observables/residual_rms ref.h5 run.h5
