# critical, localnu, correlate and clusterfit make from summaries the products they make from the runs, table by table and every bit; maps kept at the angles asked for.
for s in 1 2; do
  deposit --grains 60 --width 10 --seed $s --quiet -o pile-$s.h5
  tilt-cd pile-$s.h5 --rate 0.05 --frame-every-deg 0.5 --quiet -o run-$s.h5
  summarise run-$s.h5 --map-theta 3,6 --quiet -o run-$s.summary.h5
done
# every line but the provenance, every bit (--digits 0) (tools, commands, inputs)
same() { diff <(grep -v '^# \(tool\|command\|input\|provenance\):' "$1") <(grep -v '^# \(tool\|command\|input\|provenance\):' "$2"); }
critical run-1.h5 run-2.h5 --quiet --digits 0 > c-runs.tsv
critical run-1.summary.h5 run-2.summary.h5 --quiet --digits 0 > c-sums.tsv
same c-runs.tsv c-sums.tsv
[[ $(tsv_rows c-sums.tsv steps) -gt 100 && $(tsv_rows c-sums.tsv frames) -gt 10 ]]
# the runs keep their names: the summaries stand for them
expect_eq "run-1.h5" "$(tsv_value c-sums.tsv runs name 1)"
for opts in "" "--map-run 1 --map-theta 6 --nu c-runs.tsv" "--map-theta 3 --nu-c 0.1"; do
  localnu run-1.h5 run-2.h5 $opts --quiet --digits 0 > l-runs.tsv
  localnu run-1.summary.h5 run-2.summary.h5 $opts --quiet --digits 0 > l-sums.tsv
  same l-runs.tsv l-sums.tsv
done
[[ $(tsv_rows l-sums.tsv map) -gt 10 ]]
localnu run-1.h5 run-2.h5 --quiet -o l-runs.h5
localnu run-1.summary.h5 run-2.summary.h5 --quiet -o l-sums.h5
correlate l-runs.h5 --quiet -o co-runs.h5
correlate l-sums.h5 --quiet -o co-sums.h5
correlate l-runs.h5 --quiet --digits 0 > co-runs.tsv
correlate l-sums.h5 --quiet --digits 0 > co-sums.tsv
same co-runs.tsv co-sums.tsv
clusterfit co-runs.h5 --nu c-runs.tsv --quiet --digits 0 > f-runs.tsv 2> /dev/null
clusterfit co-sums.h5 --nu c-sums.tsv --quiet --digits 0 > f-sums.tsv 2> /dev/null
same f-runs.tsv f-sums.tsv
[[ $(tsv_rows f-sums.tsv fits) -gt 0 ]]
# the summary names the commit that made its run and itself
critical run-1.summary.h5 --quiet > c1.tsv
grep -q "^# provenance: tilt-cd	0\.1\.0+[0-9a-f]*" c1.tsv
grep -q "^# provenance: summarise	0\.1\.0+[0-9a-f]*" c1.tsv
# the summary keeps what the solver did at each step: the run's sweeps and sub-steps, value by value
values() { h5dump -y -w 0 -d "$1" "$2" | sed -n '/^   DATA {/,/^   }/p' | grep -v '[{}]' | tr -d ' \n'; }
for k in sweeps substeps; do
  r=$(values /observables/$k/value run-1.h5)
  [[ $(tr -cd , <<< "$r" | wc -c) -gt 100 ]]  # a value per step
  expect_eq "$r" "$(values /tables/steps/$k run-1.summary.h5)"
done
