# benchmarks/study_costs.py: a row per summary, by folder then seed, holding the run's own
# record: its stiffness, theta_c where the run reached it (NA where it stopped before), the
# tilt's CPU from its provenance (a branch's own record, not its parent's), and the steps,
# sweeps per step, sub-steps, split and capped steps of its per-step observables, checked
# against h5dump's reading of the run files; a missing folder, one without summaries and a
# file that is not a summary are one-line errors with nothing on stdout.
study_costs=$CDPILE_SOURCE/benchmarks/study_costs.py
for s in 1 2; do
  deposit --grains 60 --width 10 --seed $s -o pile-$s.h5 --quiet
done
mkdir -p runs/split runs/rigid runs/branch sum/split sum/rigid sum/branch
summary() {  # folder seed
  (cd "runs/$1" && summarise "run-$2.h5" --radii 1:1:3 --map-theta 1 --quiet -o "../../sum/$1/run-$2.summary.h5")
}
# every step split into 4 sub-steps, to the avalanche; rigid contacts to 2 degrees; a
# branch of seed 1's run from 1 degree to 1.5 at k = 1e5
for s in 1 2; do
  tilt-cd pile-$s.h5 --rate 0.05 --frame-every-deg 1 --stiffness 1e4 --substep-after 1 --max-substeps 4 \
    --quiet -o runs/split/run-$s.h5 2> /dev/null
  summary split $s
done
tilt-cd pile-1.h5 --rate 0.05 --to 2 --frame-every-deg 1 --stiffness 0 --quiet -o runs/rigid/run-1.h5 2> /dev/null
summary rigid 1
tilt-cd runs/split/run-1.h5 --branch-at 1 --to 1.5 --stiffness 1e5 --quiet -o runs/branch/run-1.h5 2> /dev/null
summary branch 1
"$study_costs" sum/split sum/rigid sum/branch > table.tsv
expect_eq "study	seed	stiffness_mgD	theta_c_deg	tilt_cpu_s	steps	sweeps_and_iterations_per_step	substeps_per_step	steps_split	steps_capped" \
  "$(head -1 table.tsv)"
expect_eq "split 1,split 2,rigid 1,branch 1" "$(tail -n +2 table.tsv | cut -f1,2 | tr '\t' ' ' | paste -sd,)"
# One value per line: h5dump's raw data of an observable (-o), the commas off.
values() { h5dump -d "/observables/$2/value" -y -w 1 -o raw.txt "$1" > /dev/null; tr -d ' ,' < raw.txt | grep .; }
attribute() { h5dump -a "$2" "$1" | awk '/\(0\)/ { sub(/.*\(0\): */, ""); print; exit }'; }
row=1
for run in split/run-1 split/run-2 rigid/run-1 branch/run-1; do
  row=$((row + 1))
  cell() { awk -F'\t' -v r=$row -v c="$1" 'NR == 1 { for (i = 1; i <= NF; i++) k[$i] = i; next } NR == r { print $k[c] }' table.tsv; }
  f=runs/$run.h5
  values "$f" sweeps > sweeps.txt; values "$f" substeps > substeps.txt; values "$f" converged > converged.txt
  want=$(paste sweeps.txt substeps.txt converged.txt | awk '
    { n++; w += $1; s += $2; split_ += $2 > 1; capped += $3 == 0 }
    END { printf "%d %d %.2f %d %d", n, int(w / n + 0.5), s / n, split_, capped }')
  expect_eq "$want" "$(cell steps) $(cell sweeps_and_iterations_per_step) $(cell substeps_per_step) $(cell steps_split) $(cell steps_capped)" "($run)"
  # the tilt's CPU: the run file's last provenance record (a branch's own)
  last=$(h5ls "$f/provenance" | awk '{ print $1 }' | sort | tail -1)
  expect_near "$(attribute "$f" "/provenance/$last/cpu_s")" "$(cell tilt_cpu_s)" "w * 1e-3" "($run: tilt CPU, 4 digits)"
done
expect_eq "1e4 4.00" "$(awk -F'\t' 'NR == 2 { print $3, $8 }' table.tsv)"
expect_eq "0 NA" "$(awk -F'\t' 'NR == 4 { print $3, $4 }' table.tsv)"
expect_eq "1e5 NA" "$(awk -F'\t' 'NR == 5 { print $3, $4 }' table.tsv)"
# theta_c: the summary's avalanche angle by the rule, for both runs tilted past it
for s in 1 2; do
  want=$(attribute sum/split/run-$s.summary.h5 /results/loading_theta_c_deg)
  expect_near "$want" "$(awk -F'\t' -v r=$((s + 1)) 'NR == r { print $4 }' table.tsv)" 0.0005 "(theta_c, seed $s)"
done
# the branch's own CPU is less than its parent's whole tilt
awk -F'\t' 'NR == 2 { p = $5 } NR == 5 { b = $5 } END { exit !(b < p) }' table.tsv
# -o writes the same table
"$study_costs" sum/split sum/rigid sum/branch -o out.tsv
cmp table.tsv out.tsv
expect_fail 1 "study_costs.py: none: not a folder of summaries" "$study_costs" sum/split none
[[ ! -s stdout.txt ]]
mkdir empty
expect_fail 1 "study_costs.py: empty: no run-SEED.summary.h5" "$study_costs" empty
cp pile-1.h5 sum/rigid/run-3.summary.h5
expect_fail 1 "study_costs.py: sum/rigid/run-3.summary.h5: not a run summary (summarise's /kind 'summary' with its steps table)" \
  "$study_costs" sum/split sum/rigid
[[ ! -s stdout.txt ]]
