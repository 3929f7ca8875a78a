# benchmarks/per_degree.py: a run's table per degree of tilt holds the run's own per-step
# record, summed by degree: the steps of each degree, the steps at the cap and nu as the
# mean of critical / contacts over the degree's steps, checked here against h5dump's
# reading of the same observables; a pile or a missing file is a one-line error.
deposit --grains 60 --width 10 --seed 2 -o pile.h5 --quiet
# To the avalanche (32 degrees, the last one in part): the contacts vary in some degrees, so
# nu as a mean of ratios differs there from a ratio of sums.
tilt-cd pile.h5 --rate 0.05 -o run.h5 --quiet
per_degree=$CDPILE_SOURCE/benchmarks/per_degree.py
"$per_degree" run.h5 > table.tsv
expect_eq "tilt_from_deg	tilt_to_deg	steps	sweeps_and_iterations_per_step	substeps_per_step	steps_split	steps_capped	nu" \
  "$(head -1 table.tsv)"
col() { awk -F'\t' -v r="$1" -v c="$2" 'NR == 1 { for (i = 1; i <= NF; i++) k[$i] = i; next } NR == r + 1 { print $k[c] }' table.tsv; }
# One value per line: h5dump's raw data of an observable (-o), one per line, the commas off.
values() { h5dump -d "/observables/$1/value" -y -w 1 -o raw.txt run.h5 > /dev/null; tr -d ' ,' < raw.txt | grep .; }
values tilt_angle > angle.txt; values critical > critical.txt; values contacts > contacts.txt
values converged > converged.txt
last=$(tail -1 angle.txt)
rows=$(awk -v a="$last" 'BEGIN { n = int(a); print n < a ? n + 1 : n }')
expect_eq $((rows + 1)) "$(wc -l < table.tsv)" "(the header and a row per degree to $last)"
for ((r = 1; r <= rows; r++)); do
  # Degree r covers (r - 1, r], the first [0, 1].
  want=$(paste angle.txt critical.txt contacts.txt converged.txt | awk -v lo=$((r - 1)) '
    ($1 > lo || lo == 0) && $1 <= lo + 1 { n++; nu += $3 > 0 ? $2 / $3 : 0; capped += $4 == 0 }
    END { printf "%d %d %.4f", n, capped, nu / n }')
  expect_eq "$want" "$(col $r steps) $(col $r steps_capped) $(col $r nu)" "(degree $r)"
done
# -o writes the same table.
"$per_degree" run.h5 -o out.tsv
cmp table.tsv out.tsv
expect_fail 1 "per_degree.py: pile.h5: a pile file, not a tilt-cd run (its /kind is not 'run')" "$per_degree" pile.h5
expect_fail 1 "per_degree.py: none.h5: no such file" "$per_degree" none.h5
[[ ! -e none.tsv ]]
