# critical, to-xdmf and to-lammps read a run while tilt-cd computes it (given OUTPUT, they read OUTPUT.partial; given the partial, the same), say on stderr that it is partial and how far it goes, show its frames up to its last checkpoint, and do not disturb it: the finished run equals one computed with no reader.
deposit --grains 30 --width 6 --seed 2 --quiet -o pile.h5
run_args=(--rate 0.01 --to 30 --frame-every 100 --checkpoint-every 200 --quiet)
tilt-cd pile.h5 "${run_args[@]}" -o alone.h5
tilt-cd pile.h5 "${run_args[@]}" -o run.h5 &
pid=$!
# on a failure, end the run before the scratch folder goes
trap 'kill -TERM "$pid" 2> /dev/null; kill -CONT "$pid" 2> /dev/null; wait "$pid" 2> /dev/null || true' EXIT
# hold tilt-cd still (SIGSTOP) once its partial has a checkpoint with steps and two frames:
# mid-run, with its files as they are while the readers work
ready() {
  "$PY" -c 'import h5py, sys; f = h5py.File("run.h5.partial", "r")
sys.exit(not ("observables" in f and f["particles/grains/position/step"].shape[0] >= 2))' 2> /dev/null
}
for _ in $(seq 500); do
  kill -STOP "$pid"
  [[ -e run.h5.partial ]] && ready && break
  kill -CONT "$pid"
  sleep 0.01
done
frames=$("$PY" -c 'import h5py; print(h5py.File("run.h5.partial", "r")["particles/grains/position/step"].shape[0])')
last=$("$PY" -c 'import h5py; print(h5py.File("run.h5.partial", "r")["particles/grains/position/step"][-1])')
critical run.h5 --table runs > runs.tsv 2> critical.err
grep -q "^critical: warning: run.h5.partial: a partial run (tilt-cd has not finished it: still running, or stopped): read up to its last checkpoint, $frames frames, the last at step $last, tilt " critical.err
expect_eq "$frames" "$(tsv_value runs.tsv runs frames 1)"
expect_eq run.h5.partial "$(tsv_value runs.tsv runs name 1)"
critical run.h5.partial --table runs 2> partial.err > runs2.tsv
cmp runs.tsv runs2.tsv
to-lammps run.h5 -o run.dump --contacts run.contacts.dump 2> lammps.err
grep -q '^to-lammps: warning: run.h5.partial: a partial run' lammps.err
expect_eq "$frames" "$(grep -c '^ITEM: TIMESTEP$' run.dump)"
expect_eq "$frames" "$(grep -c '^ITEM: TIMESTEP$' run.contacts.dump)"
to-xdmf run.h5 -o run.xdmf 2> xdmf.err
grep -q '^to-xdmf: warning: run.h5.partial: a partial run.*; the views name the partial: run to-xdmf again on the finished run$' xdmf.err
expect_eq "$frames" "$(grep -c '<Grid Name="grains_' run.xdmf)"
kill -CONT "$pid"
wait "$pid"
trap - EXIT
test -e run.h5 && test ! -e run.h5.partial
# undisturbed: the same frames, contacts and observables as the run no one read
for g in /particles /contacts /observables; do h5diff run.h5 alone.h5 "$g" "$g"; done
