# The stability map at its smallest (60 disks, 2 time steps x 2 tolerances, one low sweep cap): every run classified, the reference is at the smallest h and is ok, the 5-sweep cap is flagged, the figure is drawn, and a second make runs nothing again.
# ctest: slow, timeout 120
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" stability STABILITY_GRAINS=60 STABILITY_WIDTH=10 \
  STABILITY_STEPS="1e-4 4e-4" STABILITY_TOLERANCES="1e-2 1e-4" STABILITY_EXTRA="1e-4:1e-4:5" \
  STABILITY_RATE=50 STABILITY_MAX_ANGLE=45 STUDIES="$PWD/studies" CDPILE_BIN="$CDPILE_BIN" "$@"; }
mk > make1.log 2>&1 || { cat make1.log >&2; exit 1; }
dir=$PWD/studies/stability-N60-R1.5-seed1
[[ -s $dir/figures/stability.png && -s $dir/figures/stability.pdf ]]
expect_eq 5 "$(grep -vc '^#\|^file' "$dir/times.tsv")" "(runs timed)"
col() { awk -F'\t' -v f="$1" -v c="$2" '/^#/ { next } !h { for (i = 1; i <= NF; i++) k[$i] = i; h = 1; next } $1 == f { print $k[c] }' "$dir/stability.tsv"; }
# The reference: a run at the smallest h of the grid that raised no warning, so it is ok.
ref=$(sed -n 's/^# stability map .*reference \([^ ,]*\),.*/\1/p' "$dir/stability.tsv")
[[ $ref == h1e-4-tol*-cap2000.h5 ]] || { echo "reference: '$ref'" >&2; exit 1; }
expect_eq ok "$(col "$ref" outcome)"
# Every run has one of the outcomes of pipelines/stability.py.
bad=$(awk -F'\t' '/^#/ || /^file/ { next } $NF !~ /^(failed|overlap|early|late|unconverged|ok)$/' "$dir/stability.tsv")
[[ -z $bad ]] || { echo "unknown outcomes: $bad" >&2; exit 1; }
# Five sweeps cannot carry a pile's weight: most steps hit the cap, and the map says so.
"$PY" -c "import sys; u = float(sys.argv[1]); assert u > 0.01, u" "$(col h1e-4-tol1e-4-cap5.h5 unconverged)"
[[ $(col h1e-4-tol1e-4-cap5.h5 outcome) != ok ]]
mk > make2.log 2>&1
if grep -q 'stability.sh: h' make2.log; then echo "runs were made again" >&2; cat make2.log >&2; exit 1; fi
