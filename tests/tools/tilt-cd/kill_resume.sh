# kill -9 at random moments, then --resume, gives the same file as a run never
# interrupted: h5diff finds every dataset and attribute equal (provenance aside).
# ctest: slow, timeout 120
deposit --grains 100 --width 12 --seed 2 -o pile.h5 --quiet
opts=(--to 3 --rate 0.002 --checkpoint-every 30 --frame-every 40 --quiet)
tilt-cd pile.h5 -o ref.h5 "${opts[@]}"
RANDOM=$$
for attempt in 1 2 3; do
  delay=$(printf '0.%02d' $(( RANDOM % 30 + 5 )))
  echo "kill -9 after ${delay} s" >&2
  tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}" & pid=$!
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" || true
  if [[ -e run.h5.partial ]]; then cli-demo run.h5.partial > /dev/null; fi  # always a valid file
  # The run takes over a second: the first kill (at most 0.35 s) is always mid-run.
  if [[ $attempt == 1 ]]; then test ! -e run.h5; fi
done
tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}"
test ! -e run.h5.partial
h5diff --exclude-path /provenance ref.h5 run.h5
expect_eq "" "$(ls -A | grep tmp || true)" "(temporary files left)"
# --resume on a finished run does nothing.
tilt-cd pile.h5 -o run.h5 --resume "${opts[@]}"
h5diff --exclude-path /provenance ref.h5 run.h5
