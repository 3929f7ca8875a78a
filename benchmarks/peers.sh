#!/bin/sh
# The peers side by side: cdpile, Siconos and LAMMPS tilt the same pile in one run.
#
#   benchmarks/peers.sh OUTDIR
#
# One pile is made by cdpile's `deposit --smooth-floor` (N grains, WIDTH mean
# diameters wide, D = 1 mm, Dmax/Dmin = 1.5, mu = 0.5 grain-grain and
# grain-wall) and exported to Siconos and LAMMPS (benchmarks/peers/pile_to_peers.py),
# so the three codes tilt the same packing at 10 degrees per second:
#   cdpile   tilt-cd, h = 1e-4 s, 0.001 degree per step, defaults otherwise
#            (CDPILE_OPTIONS adds tilt-cd options, e.g. "--stiffness 1e6");
#   Siconos  Moreau-Jean + 2D NSGS (benchmarks/peers/siconos/siconos_pile.py),
#            h = 1e-4 s, 0.001 degree per step, tolerance 1e-4, cap 1000;
#   LAMMPS   gran/hooke/history soft disks (benchmarks/peers/lammps/), serial,
#            dt = 1.82e-6 s (t_c/25), rate 10 deg/s.
# Each code runs a window of WINDOW tilt steps from 0 degree (cost per step);
# cdpile and LAMMPS also run to the avalanche (theta_c; Siconos is
# extrapolated, see summarize.py). CPU time (user + system, /usr/bin/time) is
# the main figure, wall time beside it.
#
# The regularisation stage (REG=1) tilts the same pile with LAMMPS at three
# stiffnesses and two restitutions, dumps contact frames every REG_EVERY
# degrees up to REG_TO, converts them (from-lammps)
# and counts critical contacts with cdpile's own `localnu`; the same is done on
# cdpile's full run. It runs beside the comparison (PARALLEL_REG=1) on the
# second core, or after it (PARALLEL_REG=0).
#
# SICONOS=0 skips Siconos (its window takes SICONOS_BUDGET s and a package few have).
# Needs: the cdpile tools (BIN, default build/bin of this checkout), Debian's
# python3-siconos, lammps, python3-h5py, python3-numpy, /usr/bin/time.
# Results: OUTDIR/results.tsv, OUTDIR/ratios.tsv, OUTDIR/regularisation.tsv
# (summarize.py prints them too); every log is kept in OUTDIR.
set -eu

[ $# -eq 1 ] || { echo "usage: $0 OUTDIR" >&2; exit 2; }
here=$(cd "$(dirname "$0")" && pwd)
peers=$here/peers
BIN=${BIN:-$here/../build/bin}
BIN=$(cd "$BIN" && pwd)
N=${N:-1000}
WIDTH=${WIDTH:-30}
SEED=${SEED:-1}
WINDOW=${WINDOW:-300}
SICONOS=${SICONOS:-1}
SICONOS_BUDGET=${SICONOS_BUDGET:-420}
CDPILE_OPTIONS=${CDPILE_OPTIONS:-}
MAX_ANGLE=${MAX_ANGLE:-40}
REG=${REG:-1}
PARALLEL_REG=${PARALLEL_REG:-1}
REG_KNHAT=${REG_KNHAT:-"2e4 2e5 2e6"}
REG_EN=${REG_EN:-"0.1 0.7"}
REG_TO=${REG_TO:-6}
REG_EVERY=${REG_EVERY:-1.5}
PY=/usr/bin/python3
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1

mkdir -p "$1"
out=$(cd "$1" && pwd)
cd "$out"
timed() {  # NAME CMD...: CPU user, system, wall (s) and peak RSS (kB) to NAME.time
  name=$1; shift
  /usr/bin/time -f "%U %S %e %M" -o "$name.time" "$@"
}
wind=$(awk -v w="$WINDOW" 'BEGIN { printf "%.6g", w * 0.001 }')

{
  echo "date	$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "host	$(uname -srm), $(grep -c ^processor /proc/cpuinfo) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
  echo "load_at_start	$(cut -d' ' -f1-3 /proc/loadavg)"
  echo "cdpile	$("$BIN/tilt-cd" --version 2>&1 | head -1)"
  for p in python3-siconos lammps; do
    echo "$p	$(dpkg-query -W -f '${Version}' "$p" 2>/dev/null || echo missing)"
  done
  echo "settings	N=$N WIDTH=$WIDTH SEED=$SEED WINDOW=$WINDOW CDPILE_OPTIONS=$CDPILE_OPTIONS SICONOS=$SICONOS SICONOS_BUDGET=$SICONOS_BUDGET REG=$REG REG_KNHAT=$REG_KNHAT REG_EN=$REG_EN REG_TO=$REG_TO REG_EVERY=$REG_EVERY"
} > env.tsv
cat env.tsv

echo "== pile: deposit --grains $N --width $WIDTH --smooth-floor --seed $SEED"
rm -f pile.h5
timed cdpile_deposit "$BIN/deposit" --grains "$N" --width "$WIDTH" --smooth-floor \
  --seed "$SEED" -o pile.h5 --quiet
[ "$SICONOS" = 1 ] && $PY "$peers/pile_to_peers.py" siconos pile.h5 pile.npz
$PY "$peers/pile_to_peers.py" lammps pile.h5 pile.data

lammps_settle() {  # DIR [lmp -var ...]: settle the exported pile with LAMMPS in DIR
  d=$1; shift
  mkdir -p "$d"
  cp "$peers"/lammps/in.params "$peers"/lammps/in.deposit "$peers"/lammps/in.tilt \
     "$peers"/lammps/in.contactdump "$d"/
  (cd "$d" && timed settle lmp -in in.deposit -var N "$N" -var Wd "$WIDTH" \
     -var data ../pile.data -var pile pile.restart -var tmin 10 -var tmax 100 "$@" \
     -log log.settle -screen none)
}

regularisation() {
  for kn in $REG_KNHAT; do
    for en in $REG_EN; do
      d=reg_kn${kn}_en${en}
      echo "== regularisation: LAMMPS knhat $kn en $en to $REG_TO deg, frames every $REG_EVERY deg"
      lammps_settle "$d" -var knhat "$kn" -var en "$en"
      (cd "$d" && timed tilt lmp -in in.tilt -var N "$N" -var Wd "$WIDTH" -var pile pile.restart \
         -var knhat "$kn" -var en "$en" -var rate 10 -var thmax "$REG_TO" -var ekfail 1 \
         -var cdump "$REG_EVERY" -var tag f -var thout 0.05 -var wall 01:00:00 \
         -log log.tilt -screen none)
      dt=$(sed -n 's/.* dt=\([^ ]*\) .*/\1/p' "$d/log.tilt" | grep -v '\$' | head -1)
      (cd "$d" && "$BIN/from-lammps" atoms_f.*.txt contacts_f.*.txt --script in.tilt \
         --pair-style gran/hooke/history --rate 10 --dt "$dt" --check --check-tolerance 1e-3 \
         -o contacts.tsv 2> check.log)
      tail -1 "$d/check.log"
      for eps in 1e-3 1e-2; do
        "$BIN/localnu" "$d/contacts.tsv" --mu 0.5 --diameter 0.001 --eps "$eps" --radii 1 \
          --table frames --quiet > "$d/frames_eps$eps.tsv"
      done
    done
  done
  touch reg.done
}

rm -f reg.done
if [ "$REG" = 1 ] && [ "$PARALLEL_REG" = 1 ]; then
  regularisation > reg.log 2>&1 &
  regpid=$!
fi

echo "== cdpile: tilt-cd, window of $WINDOW steps (to $wind deg)"
rm -f cdpile_window.h5 cdpile_full.h5
# shellcheck disable=SC2086 # CDPILE_OPTIONS is a list of options
timed cdpile_window "$BIN/tilt-cd" pile.h5 --to "$wind" -o cdpile_window.h5 --quiet $CDPILE_OPTIONS

rm -f siconos_window.json siconos_window.csv siconos_window.time
if [ "$SICONOS" = 1 ]; then
  echo "== Siconos: $WINDOW tilt steps (wall budget $SICONOS_BUDGET s)"
  timed siconos_window $PY "$peers/siconos/siconos_pile.py" --load pile.npz --deposit-max-steps 0 \
    --tilt-steps "$WINDOW" --wall-budget "$SICONOS_BUDGET" --report-every 50 \
    --json siconos_window.json --trace siconos_window.csv > siconos_window.log 2>&1
  grep '^tilt step' siconos_window.log | tail -1
fi

echo "== LAMMPS: settle the exported pile, then a window to $wind deg"
lammps_settle lammps
(cd lammps && timed window lmp -in in.tilt -var N "$N" -var Wd "$WIDTH" -var pile pile.restart \
   -var rate 10 -var thmax "$wind" -var thout 0.01 -log log.window -screen none)

echo "== cdpile: tilt-cd to the avalanche (--margin 0, at most $MAX_ANGLE deg)"
# shellcheck disable=SC2086
timed cdpile_full "$BIN/tilt-cd" pile.h5 --margin 0 --max-angle "$MAX_ANGLE" -o cdpile_full.h5 --quiet $CDPILE_OPTIONS

echo "== LAMMPS: tilt to the avalanche (stop at KE/(N m g D) > 0.01 or $MAX_ANGLE deg)"
(cd lammps && timed full lmp -in in.tilt -var N "$N" -var Wd "$WIDTH" -var pile pile.restart \
   -var rate 10 -var thmax "$MAX_ANGLE" -var ekfail 1e-2 -var thout 0.01 -var wall 02:00:00 \
   -log log.full -screen none)

if [ "$REG" = 1 ]; then
  if [ "$PARALLEL_REG" = 1 ]; then
    echo "== waiting for the regularisation stage (log: $out/reg.log)"
    wait "$regpid" || true
  else
    regularisation 2>&1 | tee reg.log
  fi
  [ -f reg.done ] || { echo "regularisation stage failed, see $out/reg.log" >&2; exit 1; }
  for eps in 1e-3 1e-2; do
    "$BIN/localnu" cdpile_full.h5 --eps "$eps" --radii 1 --table frames --quiet \
      > "cdpile_frames_eps$eps.tsv"
  done
fi
echo "load_at_end	$(cut -d' ' -f1-3 /proc/loadavg)" >> env.tsv
$PY "$peers/summarize.py" "$out"
