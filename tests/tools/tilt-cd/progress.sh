# Progress (angle, step, steps/s, an estimate of the time left) goes to stderr only when it
# is a terminal, and --quiet silences it; piped stderr gets the one summary line. The line
# is rewritten at most twice a second and once more at the end, so however fast the
# machine, the last progress line shows the last step. It fits the terminal's width
# ($COLUMNS here): fields are dropped, the line never wraps.
command -v script > /dev/null || exit 77
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
COLUMNS=200 script -qec "tilt-cd pile.h5 --to 4 --rate 0.001 -o a.h5" /dev/null > tty.txt
tr '\r' '\n' < tty.txt | grep -aE '^tilt-cd: [0-9.]+ deg  step [0-9]+  [0-9]+ steps/s  .*est\. [0-9]+ s left' > lines.txt
grep -aqE '^tilt-cd: 4\.000 deg  step 4000  [0-9]+ steps/s  .* est\. 0 s left' <(tail -n 1 lines.txt)
# 40 columns: at most 39 characters between two carriage returns, one newline at the end.
COLUMNS=40 script -qec "tilt-cd pile.h5 --to 4 --rate 0.001 -o n.h5" /dev/null > narrow.txt
head -n 1 narrow.txt | tr '\r' '\n' | sed '/^$/d' > narrow_lines.txt
test -s narrow_lines.txt
expect_eq 0 "$(awk 'length($0) > 39' narrow_lines.txt | wc -l)" "(lines wider than 39 characters)"
grep -aqE '^tilt-cd: 4\.000 deg  est\. 0 s left *$' <(tail -n 1 narrow_lines.txt)
script -qec "tilt-cd pile.h5 --to 4 --rate 0.001 -o b.h5 --quiet" /dev/null > quiet.txt
expect_eq 0 "$(wc -c < quiet.txt)" "(--quiet printed something)"
tilt-cd pile.h5 --to 4 --rate 0.001 -o c.h5 2> stderr.txt
expect_eq 1 "$(wc -l < stderr.txt)"
grep -q '^tilt-cd: no avalanche detected; stopped at 4.000 deg (step 4000, to)' stderr.txt
