# --sweep-order strips --threads N: the sweeps in vertical strips that threads share (docs/method.md, "Threads"); the order and the strips are recorded in /parameters (sweep_order, strips), the number of threads is not; --strips gives another path, the same on any number of threads: a run is the same file on 1 and 3 threads, resumes after kill -9 on another number, and branches on any; more than one thread in pair order is a usage error with no output. (The unit tests Threads.* run the threads on scenes small enough to test; here the plumbing.)
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
opts=(--to 0.6 --rate 0.005 --sweep-order strips --checkpoint-every 10 --frame-every 40 --quiet)
tilt-cd pile.h5 -o one.h5 "${opts[@]}" --threads 1
tilt-cd pile.h5 -o three.h5 "${opts[@]}" --threads 3
h5diff --exclude-path /provenance one.h5 three.h5
tilt-cd pile.h5 -o pair.h5 --to 0.6 --rate 0.005 --frame-every 40 --quiet
"$PY" - <<'PY'
import h5py
with h5py.File("one.h5", "r") as f, h5py.File("pair.h5", "r") as p:
    a = f["parameters"].attrs
    assert a["sweep_order"] in (b"strips", "strips"), a["sweep_order"]
    assert "threads" not in a, "the number of threads is recorded"
    assert p["parameters"].attrs["sweep_order"] in (b"pair", "pair")
    assert int(a["strips"]) == 16, a["strips"]
    assert f["observables/converged/value"][:].min() == 1
PY
tilt-cd pile.h5 -o two-strips.h5 "${opts[@]}" --strips 2 --threads 2
tilt-cd pile.h5 -o two-strips-1.h5 "${opts[@]}" --strips 2 --threads 1
h5diff --exclude-path /provenance two-strips.h5 two-strips-1.h5
if h5diff -q --exclude-path /provenance --exclude-path /parameters one.h5 two-strips.h5; then
  echo "--strips 2 gave the run of 16" >&2; exit 1
fi
"$PY" -c "import h5py; assert int(h5py.File('two-strips.h5', 'r')['parameters'].attrs['strips']) == 2"
RANDOM=$$
for attempt in 1 2; do
  delay=$(printf '0.%02d' $(( RANDOM % 20 + 5 )))
  tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}" --threads 2 & pid=$!
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" || true
done
tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}" --threads 1
h5diff --exclude-path /provenance one.h5 run.h5
tilt-cd one.h5 --branch-at 0.4 --to 0.5 --threads 2 -o branch.h5 --quiet 2> branch.err
test ! -s branch.err || { cat branch.err; exit 1; }
expect_fail 2 "tilt-cd: --threads 2: more than one thread needs --sweep-order strips (pair order is sequential; docs/method.md, \"Threads\") (see 'tilt-cd --help')" \
  tilt-cd pile.h5 --threads 2 -o out.h5
test ! -e out.h5
expect_fail 2 "deposit: --threads 4: more than one thread needs --sweep-order strips (pair order is sequential; docs/method.md, \"Threads\") (see 'deposit --help')" \
  deposit --grains 10 --threads 4 -o out.h5
test ! -e out.h5
