# pipelines/slurm.sh writes a job array mapping task k to the k-th seed's summary with the study's make variables, --name naming the study's folder, logs appended under it with each attempt marked, and an analysis job that names the seeds not summarised and the command that resubmits them; bad arguments are refused; a folder never mixes two studies; the analysis follows its seeds.
# ctest: slow, timeout 120
gen=$CDPILE_SOURCE/pipelines/slurm.sh
studies=$PWD/studies
sums=$PWD/summaries
"$gen" --name variant --seeds "3 5 8" --time 1-00:00:00 -- POLYDISPERSITY=10 GRAINS=500 STUDIES="$studies" SUMMARY_ROOT=summaries > job.sbatch 2> gen.log
study=$studies/variant-N500-R10-mu0.5-rate0.001-pcg
summaries=$sums/variant-N500-R10-mu0.5-rate0.001-pcg
bash -n job.sbatch
grep -qx '#SBATCH --array=0-2' job.sbatch
grep -qx '#SBATCH --job-name=cdpile-variant' job.sbatch
grep -qx '#SBATCH --time=1-00:00:00' job.sbatch
# Logs under the study, appended across requeues (their folder made: Slurm does not).
grep -qx "#SBATCH --output=$study/logs/run-%A_%a.log" job.sbatch
grep -qx '#SBATCH --open-mode=append' job.sbatch
test -d "$study/logs"
# The paths the jobs run, resolved and printed.
grep -qx "slurm.sh: pipelines $CDPILE_SOURCE/pipelines; study $study (the nodes must see both at these paths)" gen.log
# Run the job as Slurm would for tasks 1 and 2 (the second a requeued attempt), with a
# stand-in for make that records its arguments.
mkdir bin
printf '#!/usr/bin/env bash\necho "$@" > "%s/make.args"\n' "$PWD" > bin/make
chmod +x bin/make
PATH="$PWD/bin:$PATH" SLURM_ARRAY_JOB_ID=77 SLURM_ARRAY_TASK_ID=1 bash job.sbatch > task.log
expect_eq "-C $CDPILE_SOURCE/pipelines summaries NAME=variant POLYDISPERSITY=10 GRAINS=500 STUDIES=$studies SUMMARY_ROOT=$sums SEEDS=5" "$(cat make.args)"
grep -q "^cdpile: seed 5, job 77_1, attempt 1 on " task.log
PATH="$PWD/bin:$PATH" SLURM_ARRAY_JOB_ID=77 SLURM_ARRAY_TASK_ID=2 SLURM_RESTART_COUNT=1 bash job.sbatch > task.log
expect_eq "-C $CDPILE_SOURCE/pipelines summaries NAME=variant POLYDISPERSITY=10 GRAINS=500 STUDIES=$studies SUMMARY_ROOT=$sums SEEDS=8" "$(cat make.args)"
grep -q "^cdpile: seed 8, job 77_2, attempt 2 on " task.log
# The analysis job: after any end of the array, it names the seeds whose run is not
# summarised and the one command that resubmits them, or runs the study's make with every
# seed (a run file without its summary does not count; a summary without its run does).
"$gen" --analysis --name variant --seeds "3 5 8" -- POLYDISPERSITY=10 GRAINS=500 STUDIES="$studies" SUMMARY_ROOT="$sums" > analysis.sbatch 2> /dev/null
grep -qx "#SBATCH --output=$study/logs/analysis-%j.log" analysis.sbatch
mkdir -p "$summaries"
touch "$summaries/run-5.summary.h5" "$study/run-3.h5"
rc=0; PATH="$PWD/bin:$PATH" bash analysis.sbatch > analysis.log 2>&1 || rc=$?
expect_eq 1 "$rc"
grep -q "^cdpile: no analysis: the runs of seeds 3 8 are not summarised" analysis.log
grep -q "^  $gen --submit --name variant --seeds 3\\\\ 5\\\\ 8 --time 02:00:00 -- POLYDISPERSITY=10 GRAINS=500 STUDIES=$studies SUMMARY_ROOT=$sums\$" analysis.log
touch "$summaries/run-3.summary.h5" "$summaries/run-8.summary.h5"
PATH="$PWD/bin:$PATH" bash analysis.sbatch > analysis.log
expect_eq "-C $CDPILE_SOURCE/pipelines study NAME=variant POLYDISPERSITY=10 GRAINS=500 STUDIES=$studies SUMMARY_ROOT=$sums SEEDS=3 5 8" "$(cat make.args)"
# --name is the study's name: another name, another folder.
"$gen" --name other --seeds 1 -- STUDIES="$studies" > /dev/null 2> gen.log
grep -q "study $studies/other-N4000-" gen.log
# A relative STUDIES is the caller's folder, made absolute for the jobs (they start elsewhere).
"$gen" --name rel --seeds 1 -- STUDIES=here SUMMARY_ROOT=sums GRAINS=10 2> /dev/null | grep -qx "exec make -C $CDPILE_SOURCE/pipelines summaries NAME=rel STUDIES=$PWD/here SUMMARY_ROOT=$PWD/sums GRAINS=10 SEEDS=\$seed"
test -d "$PWD/here/rel-N10-R1.5-mu0.5-rate0.001-pcg/logs"
# Bad arguments: one line, exit 2, nothing on stdout.
expect_fail 2 "slurm.sh: --seeds: 'x' is not a non-negative integer" "$gen" --seeds "1 x"
expect_eq "" "$(cat stdout.txt)"
expect_fail 2 "slurm.sh: 'grains=3': expected a make variable NAME=VALUE" "$gen" -- grains=3
expect_fail 2 "slurm.sh: --time: 'soon' is not a Slurm time" "$gen" --time soon
expect_fail 2 "slurm.sh: 'NAME=b' and --name a disagree: the name is the study's, give it once" "$gen" --name a -- NAME=b
expect_fail 2 "slurm.sh: 'SEEDS=1': give the seeds with --seeds" "$gen" -- SEEDS=1

# One study per folder: the variables outside the folder's name are recorded by the first
# make there, and a make with others stops; so are the analysis's seeds.
mk() { make -s --no-print-directory -C "$CDPILE_SOURCE/pipelines" NAME=guard STUDIES="$studies" "$@"; }
mk study-variables WIDTH=40
mk study-variables WIDTH=40
guard=$studies/guard-N4000-R1.5-mu0.5-rate0.001-pcg
# stops: make_fails MESSAGE ARGS...: mk ARGS fails, MESSAGE its first line on stderr.
make_fails() {
  local rc=0; mk "${@:2}" 2> err.txt || rc=$?
  [[ $rc -ne 0 ]] || { echo "make ${*:2} did not fail" >&2; return 1; }
  expect_eq "$1" "$(head -1 err.txt)"
}
make_fails "pipelines: $guard/variables.txt: the study was made with WIDTH=40, not WIDTH=30: give this study another NAME" \
  study-variables WIDTH=30
# A study in strips records its strips (a pair-order one does not: guard's file has no
# such line); one begun before they were a variable has none, and make stops on it.
mk study-variables NAME=cut SWEEP_ORDER=strips WIDTH=40
cut=$studies/cut-N4000-R1.5-mu0.5-rate0.001-pcg-strips
grep -qx "STRIPS=16" "$cut/variables.txt"
if grep -q "STRIPS" "$guard/variables.txt"; then echo "a pair-order study records STRIPS" >&2; exit 1; fi
make_fails "pipelines: $cut/variables.txt: the study was made with STRIPS=16, not STRIPS=0: give this study another NAME" \
  study-variables NAME=cut SWEEP_ORDER=strips WIDTH=40 STRIPS=0
# The analysis follows its seeds: a study that grows is analysed again, and make says so.
mk analysis-seeds SEEDS="1 2"
old=$(stat -c %y "$guard/seeds.txt")
sleep 1.1
mk analysis-seeds SEEDS="1 2" > same.log
expect_eq "" "$(cat same.log)"
expect_eq "$old" "$(stat -c %y "$guard/seeds.txt")" "(seeds.txt rewritten without a change)"
mk analysis-seeds SEEDS="1 2 3" > grown.log
expect_eq "pipelines: the analysis of guard-N4000-R1.5-mu0.5-rate0.001-pcg is now of the seeds 1 2 3 (was 1 2)" "$(cat grown.log)"
expect_eq "1 2 3" "$(paste -sd' ' "$guard/seeds.txt")"
# THREADS: a run's task asks Slurm for that many cores (the analysis for one); the sweep
# order names the study, the number of threads does not.
"$gen" --name par --seeds "1" -- SWEEP_ORDER=strips THREADS=4 GRAINS=500 STUDIES="$studies" > par.sbatch 2> par.log
grep -qx '#SBATCH --cpus-per-task=4' par.sbatch
grep -qx "slurm.sh: pipelines $CDPILE_SOURCE/pipelines; study $studies/par-N500-R1.5-mu0.5-rate0.001-pcg-strips (the nodes must see both at these paths)" par.log
"$gen" --analysis --name par --seeds "1" -- SWEEP_ORDER=strips THREADS=4 GRAINS=500 STUDIES="$studies" 2> /dev/null | grep -qx '#SBATCH --cpus-per-task=1'
rc=0; "$gen" --name par --seeds 1 -- THREADS=0 > /dev/null 2> err.txt || rc=$?
expect_eq 2 "$rc"
expect_eq "slurm.sh: 'THREADS=0': expected a positive number of threads" "$(cat err.txt)"
