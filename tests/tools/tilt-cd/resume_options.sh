# A resume takes the interrupted run's options: one that is left out is the run's (not
# tilt-cd's default), and one given with another value is a usage error naming the option
# given, not a derived parameter.
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
opts=(--to 6 --rate 0.002 --frame-every-deg 0.2 --checkpoint-every 100)
tilt-cd pile.h5 -o run.h5 "${opts[@]}" --quiet & pid=$!
for _ in $(seq 500); do [[ -e run.h5.partial ]] && break; sleep 0.02; done
kill -9 "$pid"; wait "$pid" || true
test -e run.h5.partial && test ! -e run.h5
expect_fail 2 "tilt-cd: --rate 0.003: tilt_rate_deg_per_step 0.003 instead of the run's 0.002 in the interrupted run run.h5.partial; resume with its options (leave --rate out) (see 'tilt-cd --help')" \
  tilt-cd pile.h5 -o run.h5 --resume --rate 0.003
expect_fail 2 "tilt-cd: --mu 0.3: mu_grain 0.3 instead of the run's 0.5 in the interrupted run run.h5.partial; resume with its options (leave --mu out) (see 'tilt-cd --help')" \
  tilt-cd pile.h5 -o run.h5 --resume --mu 0.3
test -e run.h5.partial
# --rate, --to and the frame interval forgotten: the run's
tilt-cd pile.h5 -o run.h5 --resume --quiet
test ! -e run.h5.partial
tilt-cd pile.h5 -o ref.h5 "${opts[@]}" --quiet
h5diff --exclude-path /provenance ref.h5 run.h5
