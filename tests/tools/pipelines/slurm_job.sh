# pipelines/slurm.sh writes a job array mapping task k to the k-th seed, passing the study's make variables, and rejects bad arguments.
gen=$CDPILE_SOURCE/pipelines/slurm.sh
"$gen" --name variant --seeds "3 5 8" --time 1-00:00:00 -- POLYDISPERSITY=10 GRAINS=500 > job.sbatch
bash -n job.sbatch
grep -qx '#SBATCH --array=0-2' job.sbatch
grep -qx '#SBATCH --job-name=cdpile-variant' job.sbatch
grep -qx '#SBATCH --time=1-00:00:00' job.sbatch
# Run the job as Slurm would for task 1, with a stand-in for make that records its arguments.
mkdir bin
printf '#!/usr/bin/env bash\necho "$@" > "%s/make.args"\n' "$PWD" > bin/make
chmod +x bin/make
PATH="$PWD/bin:$PATH" SLURM_ARRAY_TASK_ID=1 bash job.sbatch
expect_eq "-C $CDPILE_SOURCE/pipelines runs POLYDISPERSITY=10 GRAINS=500 SEEDS=5" "$(cat make.args)"
PATH="$PWD/bin:$PATH" SLURM_ARRAY_TASK_ID=2 bash job.sbatch
expect_eq "-C $CDPILE_SOURCE/pipelines runs POLYDISPERSITY=10 GRAINS=500 SEEDS=8" "$(cat make.args)"
# The analysis job's command, in the header, names every seed.
grep -q "study POLYDISPERSITY=10 GRAINS=500 SEEDS='3 5 8'" job.sbatch
# Bad arguments: one line, exit 2, nothing on stdout.
expect_fail 2 "slurm.sh: --seeds: 'x' is not a non-negative integer" "$gen" --seeds "1 x"
expect_eq "" "$(cat stdout.txt)"
expect_fail 2 "slurm.sh: 'grains=3': expected a make variable NAME=VALUE" "$gen" -- grains=3
expect_fail 2 "slurm.sh: --time: 'soon' is not a Slurm time" "$gen" --time soon
