# SIGTERM ends tilt-cd within a second in any phase (reading its input, stepping, writing), and a second signal, or one sent to make's whole process group as a scheduler does, never cuts the checkpoint of the last completed step: exit 143, and --resume gives the uninterrupted run.
# ctest: slow, timeout 180
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
# Runs of 40 000 steps (seconds) with a periodic checkpoint only at step 0.
opts=(--to 8 --rate 0.0002 --checkpoint-every 100000 --frame-every 2000)
# finished_within SECONDS PID: waits for PID (a child of this shell) and sets status to its
# exit status; fails if it is still running after SECONDS. The bound is generous (a loaded
# machine), the tool's own is a second; before the fix, cases 1 and 2 wait for ever.
finished_within() {
  local k
  for k in $(seq $(( $1 * 10 ))); do kill -0 "$2" 2> /dev/null || break; sleep 0.1; done
  if kill -0 "$2" 2> /dev/null; then kill -9 "$2"; echo "still running $1 s after the signal" >&2; return 1; fi
  status=0; wait "$2" || status=$?
}
# checkpoint_step FILE: the step of a partial run's checkpoint.
checkpoint_step() { "$PY" -c 'import h5py, sys; print(h5py.File(sys.argv[1], "r")["checkpoint"].attrs["step"])' "$1"; }

# 1. Reading the input: a pile that never comes (standard input held open, empty).
mkfifo in.fifo
exec 3<> in.fifo
tilt-cd - -o read.h5 < in.fifo 2> stderr.txt & pid=$!
sleep 0.5
kill -TERM "$pid"
finished_within 10 "$pid"
expect_eq 143 "$status" "(reading)"
exec 3>&-
test ! -e read.h5 && test ! -e read.h5.partial

# 2. Writing a run to standard output that nobody reads (a full pipe).
mkfifo out.fifo
exec 4<> out.fifo
tilt-cd pile.h5 --to 0.2 --rate 0.002 -o - > out.fifo 2> stderr.txt & pid=$!
sleep 3  # 100 steps of 100 grains: done, and blocked on the pipe
kill -TERM "$pid"
finished_within 10 "$pid"
expect_eq 143 "$status" "(writing to a full pipe)"
exec 4>&-

# 3. Two signals in a row while stepping: the second neither ends the tool nor cuts the
# checkpoint; it is the last completed step, not the last periodic one (step 0 here).
tilt-cd pile.h5 -o twice.h5 "${opts[@]}" 2> stderr.txt & pid=$!
for _ in $(seq 200); do [[ -e twice.h5.partial ]] && break; sleep 0.05; done
sleep 0.5
kill -TERM "$pid"; kill -TERM "$pid"
finished_within 10 "$pid"
expect_eq 143 "$status" "(two signals)"
step=$(sed -n 's/.*interrupted at step \([0-9]*\) .*/\1/p' stderr.txt)
[[ -n $step && $step -gt 0 ]] || { cat stderr.txt >&2; echo "no checkpoint of the last step" >&2; exit 1; }
expect_eq "$step" "$(checkpoint_step twice.h5.partial)" "(checkpoint step)"

# 4. make's process group signalled at once, as Slurm signals a job: make forwards its
# SIGTERM to tilt-cd, which thus gets two.
cat > Makefile <<'MK'
group.h5: pile.h5
	tilt-cd $< -o $@ $(OPTS) $(if $(wildcard $@.partial),--resume)
MK
setsid make -s OPTS="${opts[*]}" > make.log 2>&1 & pid=$!
for _ in $(seq 200); do [[ -e group.h5.partial ]] && break; sleep 0.05; done
sleep 0.5
kill -TERM -- "-$pid"
finished_within 10 "$pid"
[[ $status -ne 0 ]] || { echo "make was not interrupted: lengthen the run" >&2; exit 1; }
step=$(sed -n 's/.*interrupted at step \([0-9]*\) .*/\1/p' make.log)
[[ -n $step && $step -gt 0 ]] || { cat make.log >&2; echo "no checkpoint of the last step" >&2; exit 1; }
expect_eq "$step" "$(checkpoint_step group.h5.partial)" "(checkpoint step under make)"
make -s OPTS="${opts[*]} --quiet"
tilt-cd pile.h5 -o ref.h5 "${opts[@]}" --quiet
h5diff --exclude-path /provenance ref.h5 group.h5
tilt-cd pile.h5 -o twice.h5 --resume "${opts[@]}" --quiet
h5diff --exclude-path /provenance ref.h5 twice.h5
expect_eq "" "$(ls -A | grep tmp || true)" "(temporary files left)"
