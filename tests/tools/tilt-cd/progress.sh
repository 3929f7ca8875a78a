# Progress (angle, step, steps/s, time left) goes to stderr only when it is a terminal,
# and --quiet silences it; piped stderr gets the one summary line. The line is rewritten
# at most twice a second and once more at the end, so however fast the machine, the last
# progress line shows the last step.
command -v script > /dev/null || exit 77
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
script -qec "tilt-cd pile.h5 --to 12 --rate 0.001 -o a.h5" /dev/null > tty.txt
tr '\r' '\n' < tty.txt | grep -aE '^tilt-cd: [0-9.]+ deg  step [0-9]+  [0-9]+ steps/s  .* s left' > lines.txt
grep -aqE '^tilt-cd: 12\.000 deg  step 12000  [0-9]+ steps/s  .* 0 s left' <(tail -n 1 lines.txt)
script -qec "tilt-cd pile.h5 --to 12 --rate 0.001 -o b.h5 --quiet" /dev/null > quiet.txt
expect_eq 0 "$(wc -c < quiet.txt)" "(--quiet printed something)"
tilt-cd pile.h5 --to 12 --rate 0.001 -o c.h5 2> stderr.txt
expect_eq 1 "$(wc -l < stderr.txt)"
grep -q '^tilt-cd: no avalanche detected; stopped at 12.000 deg (step 12000, to)' stderr.txt
