# Under a real Slurm (munged, slurmctld and slurmd on localhost, started here from a temporary configuration): a 2-seed study with its analysis, one task requeued mid-run and one cancelled, completes with one command to resubmit; the requeued run resumes from the checkpoint of the step it was signalled at, both runs equal uninterrupted ones, and report.md is written.
# ctest: slow, timeout 600
skip() { echo "skipped: $*" >&2; exit 77; }
say() { echo "[${SECONDS} s] $*" >&2; }  # where the time goes, in the test's log
[[ $(id -u) -eq 0 ]] || skip "needs root to start munged, slurmctld and slurmd (CI runs as root)"
for d in munged mungekey slurmctld slurmd sbatch scontrol; do
  command -v "$d" > /dev/null || PATH=$PATH:/usr/sbin command -v "$d" > /dev/null ||
    skip "$d not found: install Debian's slurm-wlm and munge (scripts/install-deps.sh does)"
done
export PATH=$PATH:/usr/sbin

# --- a one-node cluster in this folder ----------------------------------------------
here=$PWD
chmod 755 "$here"  # munged wants its socket's folder reachable by every user
mkdir -p munge state spool logs
chmod 700 munge
pids=()
# Processes of this cluster only: started with its configuration in their environment.
ours() {
  local d
  for d in /proc/[0-9]*; do
    { tr '\0' '\n' < "$d/environ"; } 2> /dev/null | grep -qx "SLURM_CONF=$here/slurm.conf" && echo "${d#/proc/}"
  done
}
stop_daemons() {
  local p
  # The jobs first: a job step (slurmstepd and what it runs) outlives slurmd.
  squeue -h -o %A 2> /dev/null | xargs -r scancel 2> /dev/null || true
  for _ in $(seq 100); do [[ -z $(squeue -h 2> /dev/null) ]] && break; sleep 0.2; done
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  sleep 1
  for p in $(ours); do [[ $p == "$$" || $p == "$BASHPID" ]] || pids+=("$p"); done  # steps left behind
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2> /dev/null || break; sleep 0.1; done
    kill -9 "$p" 2> /dev/null || true
  done
}
trap stop_daemons EXIT
# pid_of FILE: the process id a daemon wrote, once it has.
pid_of() { for _ in $(seq 100); do [[ -s $1 ]] && { cat "$1"; return; }; sleep 0.1; done; return 1; }
# Two free ports (a port nobody answers on), so that a cluster of the machine is left alone.
free_port() {
  local p
  while :; do
    p=$(( 20000 + RANDOM % 20000 ))
    (exec 3<> "/dev/tcp/127.0.0.1/$p") 2> /dev/null || { echo "$p"; return; }
  done
}
ctld_port=$(free_port); slurmd_port=$(free_port)
[[ $ctld_port != "$slurmd_port" ]] || slurmd_port=$(( ctld_port + 1 ))

mungekey --create --keyfile="$here/munge/munge.key" > /dev/null 2>&1 || skip "mungekey cannot make a key"
chmod 400 munge/munge.key
munged --force --key-file="$here/munge/munge.key" --socket="$here/munge/socket" --pid-file="$here/munge/munged.pid" \
  --log-file="$here/munge/munged.log" --seed-file="$here/munge/seed" 2> munge-start.txt ||
  skip "munged does not start: $(tail -1 munge-start.txt)"
pids+=("$(pid_of munge/munged.pid)")
cat > slurm.conf <<CONF
ClusterName=cdpiletest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
# cred_expire: also how long a requeued job waits before it may start again (120 s by default)
AuthInfo=socket=$here/munge/socket,cred_expire=10
CredType=cred/munge
StateSaveLocation=$here/state
SlurmdSpoolDir=$here/spool
SlurmctldPidFile=$here/slurmctld.pid
SlurmdPidFile=$here/slurmd.pid
SlurmctldLogFile=$here/slurmctld.log
SlurmdLogFile=$here/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
# A pending job whose begin time has passed waits for the main scheduling loop (60 s by default).
SchedulerParameters=sched_interval=2
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
KillWait=30
MinJobAge=600
# config_overrides: the node is used as configured even on a machine with fewer CPUs.
SlurmdParameters=config_overrides
NodeName=cdpiletest NodeHostname=$(hostname) NodeAddr=127.0.0.1 CPUs=2 RealMemory=500 State=UNKNOWN
PartitionName=test Nodes=cdpiletest Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$here/slurm.conf
slurmctld -i 2> ctld-start.txt || skip "slurmctld does not start: $(tail -1 ctld-start.txt)"
pids+=("$(pid_of slurmctld.pid)") || skip "slurmctld does not start: $(tail -2 slurmctld.log)"
slurmd -N cdpiletest 2> slurmd-start.txt || skip "slurmd does not start: $(tail -1 slurmd-start.txt)"
pids+=("$(pid_of slurmd.pid)") || skip "slurmd does not start: $(tail -2 slurmd.log)"
for _ in $(seq 100); do [[ $(sinfo -h -o %t 2> /dev/null) == idle ]] && break; sleep 0.2; done
[[ $(sinfo -h -o %t) == idle ]] || skip "the node does not come up: $(tail -2 slurmd.log)"
say "a one-node cluster is up (ports $ctld_port, $slurmd_port)"

# --- the study -------------------------------------------------------------------------
# A checkpoint only at step 0: a later one in the partial can only be the signal's.
vars=(NAME=cluster GRAINS=100 WIDTH=12 RATE=0.0005 FRAME_EVERY_DEG=1 MAP_THETAS=5 "TILT_OPTIONS=--checkpoint-every 1000000"
      STUDIES="$here/studies" SUMMARY_ROOT="$here/summaries" CDPILE_BIN="$CDPILE_BIN")
study=$here/studies/cluster-N100-R1.5-mu0.5-rate0.0005-pcg
# job_state JOB: its state (the records stay MinJobAge seconds).
job_state() { scontrol -o show job "$1" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -1; }
# wait_for SECONDS WHAT COMMAND...: polls COMMAND until it succeeds.
wait_for() {
  local s=$1 what=$2; shift 2
  for _ in $(seq $(( s * 5 ))); do "$@" && return; sleep 0.2; done
  echo "waited $s s for $what" >&2; squeue >&2; tail -n 5 "$study"/logs/*.log >&2 || true; return 1
}
partial_started() { [[ -e $study/run-$1.h5.partial ]]; }

make -s -C "$CDPILE_SOURCE/pipelines" slurm-paper "${vars[@]}" SEEDS="1 2" SLURM_TIME=00:10:00 > submit.txt 2> submit.log
read -r array analysis < submit.txt
say "submitted: array $array, analysis $analysis"
grep -q "pipelines $CDPILE_SOURCE/pipelines" submit.log  # the path the jobs run, printed
# Both runs under way (some thousands of steps of the 48 000, a few seconds each): requeue
# seed 1 (held, to read its checkpoint before it runs again) and cancel seed 2.
wait_for 120 "both runs to start" eval 'partial_started 1 && partial_started 2'
sleep 0.5
say "both runs under way"
scontrol requeuehold "${array}_0"
scancel "${array}_1"
wait_for 60 "the requeued task to stop" eval '[[ $(job_state "${array}_0") == PENDING ]]'
log1=$(ls "$study"/logs/run-"${array}"_0.log)
wait_for 60 "the signalled tilt-cd to say where it stopped" grep -q "interrupted at step" "$log1"
step=$(sed -n 's/.*interrupted at step \([0-9]*\) .*/\1/p' "$log1")
ckpt=$("$PY" -c 'import h5py, sys; print(h5py.File(sys.argv[1], "r")["checkpoint"].attrs["step"])' "$study/run-1.h5.partial")
[[ $step -gt 0 ]] || { cat "$log1" >&2; exit 1; }
expect_eq "$step" "$ckpt" "(checkpoint of the requeued run against the step it stopped at)"
say "requeued at step $step, checkpoint $ckpt"
# Submitting again while the study's jobs are queued is refused (two tilt-cd on one checkpoint).
rc=0; make -s -C "$CDPILE_SOURCE/pipelines" slurm-paper "${vars[@]}" SEEDS="1 2" > /dev/null 2> again.log || rc=$?
[[ $rc -ne 0 ]] && grep -q "slurm.sh: jobs of this study are still queued or running (.*${array}_0" again.log ||
  { cat again.log >&2; exit 1; }
scontrol release "${array}_0"
# Meanwhile (a requeued job waits cred_expire before it starts again), the same runs on
# this host as a workstation's uninterrupted make makes them.
make -s -C "$CDPILE_SOURCE/pipelines" -j2 runs "${vars[@]/#STUDIES=*/STUDIES=$here/reference}" SEEDS="1 2" > reference.log 2>&1 &
reference=$!
wait_for 120 "the requeued task to start again" grep -q "attempt 2 " "$log1"
say "the requeued task started again"
# The analysis runs after the array whatever became of it, and says what is missing.
wait_for 300 "the analysis job to end" eval '[[ $(job_state "$analysis") =~ ^(COMPLETED|FAILED)$ ]]'
say "the analysis ended: $(job_state "$analysis")"
expect_eq FAILED "$(job_state "$analysis")" "(the analysis with seed 2 cancelled)"
expect_eq COMPLETED "$(job_state "${array}_0")" "(the requeued task)"
grep -q "no analysis: the runs of seeds 2 are not summarised" "$study/logs/analysis-$analysis.log"
# Each attempt of the requeued task in the same log, marked.
grep -q "seed 1, job ${array}_0, attempt 1 " "$log1"
grep -q "seed 1, job ${array}_0, attempt 2 " "$log1"
# The one command printed resubmits only seed 2 and a new analysis.
resubmit=$(grep -A1 "resubmit them" "$study/logs/analysis-$analysis.log" | tail -1)
eval "$resubmit" > submit2.txt 2> submit2.log
read -r array2 analysis2 < submit2.txt
say "resubmitted: array $array2, analysis $analysis2"
grep -q "the runs of seeds 2 " submit2.log
wait_for 600 "the second analysis to end" eval '[[ $(job_state "$analysis2") =~ ^(COMPLETED|FAILED)$ ]]'
expect_eq COMPLETED "$(job_state "${array2}_1")" "(the resubmitted task)"
expect_eq COMPLETED "$(job_state "$analysis2")" "(the analysis)" || { cat "$study/logs/analysis-$analysis2.log" >&2; exit 1; }
test -s "$study/report.md"
# the tasks returned the runs' summaries, from which the analysis was made
for s in 1 2; do test -s "$here/summaries/${study##*/}/run-$s.summary.h5"; done
say "the second analysis completed"
# Both runs are those of a workstation's uninterrupted make.
wait "$reference" || { cat reference.log >&2; exit 1; }
for s in 1 2; do
  h5diff --exclude-path /provenance "$here/reference/${study##*/}/run-$s.h5" "$study/run-$s.h5"
done
say "the runs equal uninterrupted ones"
