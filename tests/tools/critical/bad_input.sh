# Damaged runs give one line naming the file and the path inside it, exit 1, and no output.
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\n0\t1\t0\t1\t0\t0\t1\t0.5\n0\t1\t1\t2\t1\t0\t1\t0\n1\t2\t0\t1\t0\t0\t1\t0.5\n' > ok.tsv
table-to-run ok.tsv run.h5 1 0.5
# A run (kind "run") without its per-step observables: not a run of zero steps.
cp run.h5 noobs.h5
"$PY" -c "import h5py; f = h5py.File('noobs.h5', 'r+'); del f['observables']"
expect_fail 1 "critical: noobs.h5: /observables: missing group (a run records its per-step observables)" \
  critical noobs.h5 -o out.h5
expect_fail 1 "localnu: noobs.h5: /observables: missing group (a run records its per-step observables)" \
  localnu noobs.h5 -o out.h5
expect_fail 1 "localnu: noobs.h5: /observables: missing group (a run records its per-step observables)" \
  localnu noobs.h5 --theta-c 5 -o out.h5
# ... while a pile may lack them (deposit writes them, another program may not).
cp noobs.h5 pile.h5
"$PY" -c "import h5py; f = h5py.File('pile.h5', 'r+'); f.attrs['kind'] = 'pile'"
critical pile.h5 --quiet > pile.tsv
expect_eq "0 2" "$(tsv_value pile.tsv runs steps 1) $(tsv_rows pile.tsv frames)"
grep -q '^# note: pile.h5: no per-step observables: no steps, events or theta_c from this run$' pile.tsv
# A NaN in a grain position: the schema promises finite values everywhere.
cp run.h5 nan.h5
"$PY" -c "import h5py; f = h5py.File('nan.h5', 'r+'); f['particles/grains/position/value'][1, 2, 0] = float('nan')"
expect_fail 1 "critical: nan.h5: /particles/grains/position/value: non-finite value (NaN) at element 10" \
  critical nan.h5 -o out.h5
expect_fail 1 "localnu: nan.h5: /particles/grains/position/value: non-finite value (NaN) at element 10" \
  localnu nan.h5 -o out.h5
expect_fail 1 "localnu: nan.h5: /particles/grains/position/value: non-finite value (NaN) at element 10" \
  localnu nan.h5 --theta-c 5 -o out.h5
# --series steps on a run without a per-step critical count (this one has none).
expect_fail 1 "critical: --series steps: a run does not record a per-step critical count (observable critical_grain or critical); use --series frames or sliding" \
  critical run.h5 --series steps -o out.h5 --quiet
test ! -e out.h5
expect_eq "" "$(ls -A | grep tmp || true)" "(temporary files left)"
