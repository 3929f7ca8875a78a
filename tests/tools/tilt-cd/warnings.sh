# Run-time warnings: a solver capped far below what the pile needs is reported on stderr,
# even with --quiet, and flagged in the run's /results; a sound run has none.
deposit --grains 60 --width 10 --seed 5 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.5 --rate 0.01 --stiffness 0 --max-substeps 1 --max-sweeps 1 --tolerance 1e-9 -o capped.h5 --quiet 2> stderr.txt
expect_eq 1 "$(wc -l < stderr.txt)"
grep -qE '^tilt-cd: warning: [0-9]+ of 50 steps \([0-9.]+ %\) hit the sweep cap; their forces are not converged \(raise --max-sweeps; docs/performance.md\)$' stderr.txt
h5dump -a /results/warnings capped.h5 | grep -q '(0): 1$'
h5dump -a /results/warning_messages capped.h5 | grep -q 'hit the sweep cap'
tilt-cd pile.h5 --to 0.5 --rate 0.01 -o sound.h5 --quiet 2> stderr.txt
expect_eq 0 "$(wc -c < stderr.txt)"
h5dump -a /results/warnings sound.h5 | grep -q '(0): 0$'
# Settings the stability map found failing are said once, before the run, and recorded:
# h = 4e-4 s is h sqrt(g/D) = 0.0396 at D = 1 mm (this pile's mean diameter is a little
# smaller: D is the pile's own).
tilt-cd pile.h5 --to 0.05 --rate 0.01 --time-step 4e-4 -o big_step.h5 --quiet 2> stderr.txt
expect_eq 1 "$(wc -l < stderr.txt)"
grep -qE '^tilt-cd: warning: h sqrt\(g/D\) = 0\.039[0-9] is above 0\.02; runs of the stability map overlapped beyond 1e-3 D from 0\.04 on \(lower --time-step; docs/performance\.md\)$' stderr.txt
h5dump -a /results/warnings big_step.h5 | grep -q '(0): 1$'
h5dump -a /results/warning_messages big_step.h5 | grep -qE 'h sqrt\(g/D\) = 0\.039[0-9] is above 0\.02'
