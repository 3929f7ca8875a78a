# Bad input and options: one-line errors (exit 1 for data, 2 for usage), no output file.
deposit --grains 40 --width 10 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.01 --rate 0.01 -o run.h5 --quiet
echo hello > text.txt
expect_fail 1 "tilt-cd: text.txt: not an HDF5 file (no HDF5 signature)" tilt-cd text.txt -o out.h5
expect_fail 1 "tilt-cd: run.h5: /: is a 'run' file, expected a pile (made by deposit)" tilt-cd run.h5 -o out.h5
expect_fail 2 "tilt-cd: --rate: expected a finite number in [1e-12, 90], got '-1' (out of range) (see 'tilt-cd --help')" \
  tilt-cd pile.h5 --rate -1 -o out.h5
expect_fail 2 "tilt-cd: --to 1 is below the starting tilt 2 deg (--from, or the frame of --branch-at) (see 'tilt-cd --help')" tilt-cd pile.h5 --from 2 --to 1 -o out.h5
expect_fail 2 "tilt-cd: --resume needs an output file (-o FILE), not standard output (see 'tilt-cd --help')" \
  tilt-cd pile.h5 --resume -o -
expect_fail 1 "tilt-cd: run.h5: exists; not overwritten (use --force to replace it)" tilt-cd pile.h5 -o run.h5
test ! -e out.h5
expect_eq "" "$(ls -A | grep -E 'tmp|partial' || true)" "(temporary files left)"
# Branches start from a run, at or above its first frame, and take their tilt from it.
expect_fail 1 "tilt-cd: pile.h5: /: is a 'pile' file; a branch starts from a run (made by tilt-cd)" \
  tilt-cd pile.h5 --branch-at 1 -o out.h5
expect_fail 1 "tilt-cd: run.h5: /particles/grains/position: has no frame at or below -1 deg (the first is at 0 deg)" \
  tilt-cd run.h5 --branch-at -1 -o out.h5
expect_fail 2 "tilt-cd: give --from or --branch-at, not both (a branch starts at its frame's tilt) (see 'tilt-cd --help')" \
  tilt-cd run.h5 --branch-at 0 --from 0 -o out.h5
test ! -e out.h5
