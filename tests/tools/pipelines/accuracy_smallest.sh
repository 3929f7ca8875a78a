# The speed-accuracy chart at its smallest: branches of a tiny run at one angle, the errors
# against the reference, the figure. A branch with the reference's own setting must have
# zero error exactly (same state, same solver: the same numbers); the tightly converged
# reference leaves a static pile in force balance; a second make runs no branch again.
# ctest: slow, timeout 120
deposit --grains 60 --width 10 --seed 2 -o pile.h5 --quiet
tilt-cd pile.h5 --to 2 --rate 0.01 --frame-every 50 -o run.h5 --quiet
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" accuracy ACCURACY_RUN="$PWD/run.h5" \
  ACCURACY_DIR="$PWD/acc" ACCURACY_ANGLES=1 ACCURACY_WINDOW=0.3 ACCURACY_FRAME_EVERY=10 \
  ACCURACY_SETTINGS="1e-2:2000 1e-8:100000 1e-4:2000:::qm16" ACCURACY_REFERENCE=1e-8:100000 CDPILE_BIN="$CDPILE_BIN" "$@"; }
mk > make1.log 2>&1 || { cat make1.log >&2; exit 1; }
[[ -s acc/figures/accuracy.png && -s acc/figures/accuracy.pdf ]]
expect_eq 4 "$(grep -vc '^#\|^file' acc/times.tsv)" "(branches timed)"
# The fifth field of a setting is the convergence criterion, recorded in the branch.
expect_eq qm16 "$(h5dump -a /parameters/criterion acc/a1-tol1e-4-cap2000-qm16.h5 | sed -n 's/^ *(0): "\(.*\)"/\1/p')"
row() { awk -F'\t' -v f="$1" -v c="$2" '/^#/ { next } !h { for (i = 1; i <= NF; i++) k[$i] = i; h = 1; next } $1 == f { print $k[c] }' acc/accuracy.tsv; }
expect_eq qm16 "$(row a1-tol1e-4-cap2000-qm16.h5 criterion)"
# The same setting as the reference: identical numbers.
expect_eq 0 "$(row a1-tol1e-8-cap100000.h5 nu_err)"
expect_eq 0 "$(row a1-tol1e-8-cap100000.h5 misclassified)"
expect_eq "$(row ref-a1-tol1e-8-cap100000.h5 nu)" "$(row a1-tol1e-8-cap100000.h5 nu)"
# Branches start at the run's frame at 1 degree and end at 1.3 degrees: 30 steps each.
expect_eq 1 "$(h5dump -a /parameters/branch_tilt_deg acc/a1-tol1e-2-cap2000.h5 | sed -n 's/^ *(0): //p')"
# Force balance of the converged static pile: every free grain within 1e-3 m g.
expect_near 0 "$(row ref-a1-tol1e-8-cap100000.h5 imbalance_max)" 1e-3
# Resumable: nothing is branched again.
mk > make2.log 2>&1
if grep -q 'accuracy.sh: a1' make2.log; then echo "branches were run again" >&2; cat make2.log >&2; exit 1; fi
expect_eq 4 "$(grep -vc '^#\|^file' acc/times.tsv)"
