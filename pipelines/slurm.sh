#!/usr/bin/env bash
# Writes, on standard output, a Slurm job array that runs the realisations of a study with
# the same make targets as a workstation: one task per seed, each `make runs SEEDS=<seed>`,
# so a task killed by the scheduler resumes from tilt-cd's checkpoint when resubmitted.
# The analysis and figures then run as one job that depends on the array (printed below).
#
#   pipelines/slurm.sh [--name NAME] [--seeds "1 2 ..."] [--time HH:MM:SS] [--partition P]
#                      [--] [MAKE_VARIABLE=VALUE ...] > study.sbatch
#   jid=$(sbatch --parsable study.sbatch)
#   sbatch --dependency=afterok:$jid --wrap "make -C $PIPELINES study MAKE_VARIABLES..."
set -euo pipefail
name=paper seeds="$(seq -s ' ' 1 15)" time=02:00:00 partition=""
usage() { sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while [[ $# -gt 0 ]]; do
  case $1 in
    --name) name=${2:?--name needs a value}; shift 2 ;;
    --seeds) seeds=${2:?--seeds needs a value}; shift 2 ;;
    --time) time=${2:?--time needs a value}; shift 2 ;;
    --partition) partition=${2:?--partition needs a value}; shift 2 ;;
    --help|-h) usage ;;
    --) shift; break ;;
    -*) echo "slurm.sh: unknown option '$1' (see 'slurm.sh --help')" >&2; exit 2 ;;
    *) break ;;
  esac
done
vars=()
for v in "$@"; do
  [[ $v =~ ^[A-Z_][A-Z0-9_]*=.*$ ]] || { echo "slurm.sh: '$v': expected a make variable NAME=VALUE" >&2; exit 2; }
  vars+=("$v")
done
read -r -a seed_list <<< "$seeds"
[[ ${#seed_list[@]} -gt 0 ]] || { echo "slurm.sh: --seeds: no seed given" >&2; exit 2; }
for s in "${seed_list[@]}"; do
  [[ $s =~ ^[0-9]+$ ]] || { echo "slurm.sh: --seeds: '$s' is not a non-negative integer" >&2; exit 2; }
done
[[ $time =~ ^([0-9]+-)?[0-9]{1,2}(:[0-9]{2}){0,2}$ ]] || { echo "slurm.sh: --time: '$time' is not a Slurm time" >&2; exit 2; }
pipelines=$(cd "$(dirname "$0")" && pwd)
quoted_vars=""
for v in "${vars[@]}"; do quoted_vars+=" $(printf '%q' "$v")"; done

cat <<JOB
#!/usr/bin/env bash
#SBATCH --job-name=cdpile-$name
#SBATCH --array=0-$(( ${#seed_list[@]} - 1 ))
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --time=$time
#SBATCH --output=cdpile-$name-%A_%a.log
#SBATCH --requeue
${partition:+#SBATCH --partition=$partition}
# One realisation per array task; the analysis runs after the whole array:
#   jid=\$(sbatch --parsable THIS_FILE)
#   sbatch --dependency=afterok:\$jid --wrap "make -C $pipelines study$quoted_vars SEEDS='${seed_list[*]}'"
set -euo pipefail
seeds=(${seed_list[*]})
seed=\${seeds[\$SLURM_ARRAY_TASK_ID]}
exec make -C $pipelines runs$quoted_vars SEEDS=\$seed
JOB
