# MU_DEPOSIT: the piles settle with that friction and are tilted with MU, into a folder of their own.
# ctest: slow, timeout 120
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" runs NAME=prep GRAINS=40 WIDTH=10 RATE=0.05 TO=0.2 \
  FRAME_EVERY_DEG=0.1 SEEDS=1 STUDIES="$PWD/studies" CDPILE_BIN="$CDPILE_BIN" "$@"; }
mk MU_DEPOSIT=0 > make.log 2>&1 || { cat make.log >&2; exit 1; }
study=$PWD/studies/prep-N40-R1.5-mu0.5-rate0.05-pcg-mudep0
[[ -s $study/pile-1.h5 && -s $study/run-1.h5 ]] || { echo "missing $study/{pile,run}-1.h5" >&2; ls -R studies >&2; exit 1; }
expect_eq "prep-N40-R1.5-mu0.5-rate0.05-pcg-mudep0" "$(ls studies)"
"$PY" - "$study" <<'PY'
import h5py, sys
s = sys.argv[1]
pile = h5py.File(f"{s}/pile-1.h5", "r")["parameters"].attrs
run = h5py.File(f"{s}/run-1.h5", "r")["parameters"].attrs
assert (pile["mu_grain"], pile["mu_wall"]) == (0.0, 0.0), dict(pile)
assert (run["mu_grain"], run["mu_wall"]) == (0.5, 0.5), dict(run)
PY
# Without it, the default folder name and the pile's own friction for the tilt.
mk > make2.log 2>&1 || { cat make2.log >&2; exit 1; }
[[ -s $PWD/studies/prep-N40-R1.5-mu0.5-rate0.05-pcg/run-1.h5 ]]
grep -qx -- '  --mu 0.5 --mu-wall 0.5 \\' make.log
if grep -qx -- '  --mu 0.5 --mu-wall 0.5 \\' make2.log; then
  echo "the default run passed --mu to tilt-cd" >&2; exit 1; fi
