# A branch starts from the run's stored options, not tilt-cd's defaults: the README's
# branch (--to and --tolerance only) of a 0.01 degree-per-step run tilts at 0.01 degree per
# step, and each option that differs from the run's is said on stderr; at another --rate
# the frame interval stays the run's in degrees.
deposit --grains 60 --width 10 --seed 5 -o pile.h5 --quiet
tilt-cd pile.h5 --to 1 --rate 0.01 --frame-every 20 --eps 0.002 -o run.h5 --quiet
param() { h5dump -a "/parameters/$2" "$1" | sed -n 's/^ *(0): //p'; }
tilt-cd run.h5 --branch-at 0.5 --to 0.7 --tolerance 1e-8 -o b.h5 2> stderr.txt
expect_eq "0.01 20 0.002 1e-08" "$(param b.h5 tilt_rate_deg_per_step) $(param b.h5 frame_every_steps) $(param b.h5 critical_eps) $(param b.h5 tolerance)"
expect_eq "tilt-cd: run.h5: branching from the frame of step 40 at 0.4 deg
tilt-cd: run.h5: branch: --to 0.7: tilt_to_deg 0.7 instead of the run's 1
tilt-cd: run.h5: branch: --tolerance 1e-8: tolerance 1e-08 instead of the run's 1e-06" "$(head -n 3 stderr.txt)"
expect_eq 2 "$(grep -c ': branch: ' stderr.txt)" "(changes said)"
# another rate: 0.2 degree between frames, as in the run
tilt-cd run.h5 --branch-at 0.5 --to 0.7 --rate 0.005 -o r.h5 2> stderr.txt
expect_eq "0.005 40" "$(param r.h5 tilt_rate_deg_per_step) $(param r.h5 frame_every_steps)"
grep -qx "tilt-cd: run.h5: branch: --rate 0.005: tilt_rate_deg_per_step 0.005 instead of the run's 0.01" stderr.txt
grep -qx "tilt-cd: run.h5: branch: frame_every_steps 40 (the run's 20: the same interval in degrees at this --rate)" stderr.txt
# nothing changed: nothing said but the branch and the summary
tilt-cd run.h5 --branch-at 0.5 --rate 0.01 -o same.h5 2> stderr.txt
expect_eq 0 "$(grep -c ': branch: ' stderr.txt || true)" "(changes said)"
