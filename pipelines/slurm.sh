#!/usr/bin/env bash
# Writes the Slurm jobs of a study, with the same make targets as a workstation
# (docs/cluster.md): a job array of one task per seed, each `make summaries SEEDS=<seed>`
# (the run, then its summary; a task stopped by the scheduler resumes from tilt-cd's
# checkpoint when it runs again), and an analysis job that runs after the whole array,
# whatever became of it, checks that every run is summarised and then makes the analysis
# and figures from the summaries.
#
#   pipelines/slurm.sh [--name NAME] [--seeds "1 2 ..."] [--time HH:MM:SS] [--partition P]
#                      [--analysis | --submit] [--] [MAKE_VARIABLE=VALUE ...]
#
# By default the array job is written on standard output, with --analysis the analysis
# job. --submit writes both into the study folder (STUDY/slurm/) and submits them: the
# tasks of the seeds whose run is not summarised yet (a summary committed from another
# machine counts), then the analysis after them. The same
# command submitted again after a cancel or a failure resubmits what is missing and
# chains a new analysis. --name is the study's NAME (make variable), so it names the
# study folder as well as the jobs; logs go to STUDY/logs/, appended across requeues.
set -euo pipefail
name="" seeds="$(seq -s ' ' 1 15)" time=02:00:00 partition="" mode=runs
usage() { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while [[ $# -gt 0 ]]; do
  case $1 in
    --name) name=${2:?--name needs a value}; shift 2 ;;
    --seeds) seeds=${2:?--seeds needs a value}; shift 2 ;;
    --time) time=${2:?--time needs a value}; shift 2 ;;
    --partition) partition=${2:?--partition needs a value}; shift 2 ;;
    --analysis) mode=analysis; shift ;;
    --submit) mode=submit; shift ;;
    --help|-h) usage ;;
    --) shift; break ;;
    -*) echo "slurm.sh: unknown option '$1' (see 'slurm.sh --help')" >&2; exit 2 ;;
    *) break ;;
  esac
done
vars=()
threads=1
for v in "$@"; do
  [[ $v =~ ^[A-Z_][A-Z0-9_]*=.*$ ]] || { echo "slurm.sh: '$v': expected a make variable NAME=VALUE" >&2; exit 2; }
  case $v in
    SEEDS=*) echo "slurm.sh: '$v': give the seeds with --seeds" >&2; exit 2 ;;
    STUDY=*) echo "slurm.sh: '$v': the study folder is named by its variables (STUDIES=DIR says where the studies are)" >&2; exit 2 ;;
    STUDIES=[^/]*|SUMMARY_ROOT=[^/]*|CDPILE_BIN=[^/]*)  # a relative folder is the caller's, resolved here for the jobs
      v="${v%%=*}=$PWD/${v#*=}" ;;
    NAME=*)  # the same as --name, or in its place
      if [[ -n $name && ${v#NAME=} != "$name" ]]; then
        echo "slurm.sh: '$v' and --name $name disagree: the name is the study's, give it once" >&2; exit 2
      fi
      name=${v#NAME=}; continue ;;
    THREADS=*)  # threads per tilt: the runs' tasks ask for that many cores
      threads=${v#THREADS=}
      [[ $threads =~ ^[1-9][0-9]*$ ]] || { echo "slurm.sh: '$v': expected a positive number of threads" >&2; exit 2; } ;;
  esac
  vars+=("$v")
done
name=${name:-paper}
[[ $name =~ ^[A-Za-z0-9._+-]+$ ]] || { echo "slurm.sh: --name: '$name': use letters, digits and . _ + - (it names a folder)" >&2; exit 2; }
read -r -a seed_list <<< "$seeds"
[[ ${#seed_list[@]} -gt 0 ]] || { echo "slurm.sh: --seeds: no seed given" >&2; exit 2; }
for s in "${seed_list[@]}"; do
  [[ $s =~ ^[0-9]+$ ]] || { echo "slurm.sh: --seeds: '$s' is not a non-negative integer" >&2; exit 2; }
done
[[ $time =~ ^([0-9]+-)?[0-9]{1,2}(:[0-9]{2}){0,2}$ ]] || { echo "slurm.sh: --time: '$time' is not a Slurm time" >&2; exit 2; }

# Resolved now, on the submitting host: the jobs run these absolute paths, so the nodes
# must see the repository and the studies at the same paths (a shared file system).
pipelines=$(cd "$(dirname "$0")" && pwd)
make_vars=("NAME=$name" "${vars[@]}")
study=$(make -s --no-print-directory -C "$pipelines" print-study "${make_vars[@]}") ||
  { echo "slurm.sh: cannot name the study folder (make print-study failed)" >&2; exit 1; }
summaries=$(make -s --no-print-directory -C "$pipelines" print-summaries "${make_vars[@]}") ||
  { echo "slurm.sh: cannot name the summaries' folder (make print-summaries failed)" >&2; exit 1; }
q_summaries=$(printf '%q' "$summaries")
quoted_vars=""
for v in "${make_vars[@]}"; do quoted_vars+=" $(printf '%q' "$v")"; done
q_pipelines=$(printf '%q' "$pipelines")
q_study=$(printf '%q' "$study")
logs="$study/logs"
resubmit="$(printf '%q' "$pipelines/slurm.sh") --submit --name $(printf '%q' "$name") --seeds $(printf '%q' "${seed_list[*]}") --time $time${partition:+ --partition $(printf '%q' "$partition")} --$(for v in "${vars[@]}"; do printf ' %q' "$v"; done)"

runs_job() {  # $1: the array's indices
  cat <<JOB
#!/usr/bin/env bash
#SBATCH --job-name=cdpile-$name
#SBATCH --array=$1
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=$threads
#SBATCH --time=$time
#SBATCH --output=$logs/run-%A_%a.log
#SBATCH --open-mode=append
#SBATCH --requeue
${partition:+#SBATCH --partition=$partition}
# The runs of study $study, one seed per array task (docs/cluster.md). Written by
#   $resubmit
# which also resubmits, after a cancel or a failure, the tasks whose summary is missing, and
# chains the analysis. By hand: jid=\$(sbatch --parsable THIS_FILE), then
#   sbatch --dependency=afterany:\$jid $q_study/slurm/analysis.sbatch
set -euo pipefail
seeds=(${seed_list[*]})
seed=\${seeds[\$SLURM_ARRAY_TASK_ID]}
# One log per task, appended across requeues: each attempt starts with this line.
echo "cdpile: seed \$seed, job \${SLURM_ARRAY_JOB_ID:-?}_\${SLURM_ARRAY_TASK_ID}, attempt \$(( \${SLURM_RESTART_COUNT:-0} + 1 )) on \$(hostname) at \$(date -u +%FT%TZ)"
exec make -C $q_pipelines summaries$quoted_vars SEEDS=\$seed
JOB
}

analysis_job() {
  cat <<JOB
#!/usr/bin/env bash
#SBATCH --job-name=cdpile-$name-analysis
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --time=$time
#SBATCH --output=$logs/analysis-%j.log
#SBATCH --open-mode=append
${partition:+#SBATCH --partition=$partition}
# The analysis and figures of study $study, after its array (afterany: it runs whatever
# became of the tasks, so a cancelled task never strands it) once every run is summarised.
set -euo pipefail
echo "cdpile: analysis of $name, job \${SLURM_JOB_ID:-?}, attempt \$(( \${SLURM_RESTART_COUNT:-0} + 1 )) at \$(date -u +%FT%TZ)"
missing=()
for seed in ${seed_list[*]}; do [[ -e $q_summaries/run-\$seed.summary.h5 ]] || missing+=("\$seed"); done
if [[ \${#missing[@]} -gt 0 ]]; then
  echo "cdpile: no analysis: the runs of seeds \${missing[*]} are not summarised (logs in $logs); resubmit them and a new analysis with:" >&2
  echo "  $resubmit" >&2
  exit 1
fi
exec make -C $q_pipelines study$quoted_vars SEEDS=$(printf '%q' "${seed_list[*]}")
JOB
}

echo "slurm.sh: pipelines $pipelines; study $study (the nodes must see both at these paths)" >&2
# Slurm opens a job's log before the job starts: its folder must exist by then.
mkdir -p "$logs"
case $mode in
  runs) runs_job "0-$(( ${#seed_list[@]} - 1 ))" ;;
  analysis) analysis_job ;;
  submit)
    command -v sbatch > /dev/null || { echo "slurm.sh: --submit: sbatch not found (is this a Slurm login node?)" >&2; exit 1; }
    # Tasks of this study still queued or running would be submitted twice, and two
    # tilt-cd would resume one checkpoint: refuse (their logs are in the study's folder).
    queued=$(squeue -h -u "$(id -un)" -O "JobArrayID:40,StdOut:4000" 2> /dev/null | awk -v d="$logs/" 'index($2, d) == 1 { print $1 }' | paste -sd' ')
    if [[ -n $queued ]]; then
      echo "slurm.sh: jobs of this study are still queued or running ($queued): wait for them, or scancel them, then submit again" >&2
      exit 1
    fi
    mkdir -p "$study/slurm"
    todo=()
    for k in "${!seed_list[@]}"; do [[ -e $summaries/run-${seed_list[$k]}.summary.h5 ]] || todo+=("$k"); done
    dependency=()
    if [[ ${#todo[@]} -gt 0 ]]; then
      runs_job "$(IFS=,; echo "${todo[*]}")" > "$study/slurm/runs.sbatch"
      jid=$(sbatch --parsable "$study/slurm/runs.sbatch")
      jid=${jid%%;*}
      echo "slurm.sh: job $jid: the runs of seeds $(for k in "${todo[@]}"; do printf '%s ' "${seed_list[$k]}"; done)(logs $logs/run-${jid}_*.log)" >&2
      dependency=(--dependency=afterany:"$jid")
    else
      echo "slurm.sh: every run is summarised ($summaries)" >&2
    fi
    analysis_job > "$study/slurm/analysis.sbatch"
    ajid=$(sbatch --parsable "${dependency[@]}" "$study/slurm/analysis.sbatch")
    ajid=${ajid%%;*}
    echo "slurm.sh: job $ajid: the analysis, after them (log $logs/analysis-$ajid.log)" >&2
    echo "${jid:-} $ajid"
    ;;
esac
