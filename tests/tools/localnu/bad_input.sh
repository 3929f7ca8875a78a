# Bad input gives one line, exit 1 (data) or 2 (usage) and no output file; empty frames and frames without critical contacts give a documented empty result (NA, never NaN).
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\n0\t1\t0\t1\t0\t0\t1\t0\n0\t1\t1\t2\t1\t0\t1\t0.1\n' > ok.tsv
table-to-run ok.tsv run.h5 1 0.5
table-to-run ok.tsv mu0.h5 1 0
printf 'x\ty\tfn\n1\t2\t3\n' > nocol.tsv
printf 'x\ty\tfn\tft\n0\t0\t1\tnan\n' > nan.tsv
printf 'x,y,fn,ft\n0,0,1,NA\n' > na.csv
head -c 4000 run.h5 > truncated.h5
printf '\001\002garbage\000\377' > junk.bin
T="--mu 0.5 --diameter 1"
expect_fail 1 "localnu: nocol.tsv: line 1: missing column 'ft' (the header has: x y fn)" localnu nocol.tsv $T -o out.h5
expect_fail 1 "localnu: nan.tsv: line 2, column ft: 'nan' is not a finite number" localnu nan.tsv $T -o out.h5
expect_fail 1 "localnu: na.csv: line 2, column ft: missing value (NA) where a number is required" localnu na.csv $T -o out.h5
expect_fail 1 "localnu: truncated.h5: cannot open as HDF5 (truncated or damaged?)" localnu truncated.h5 -o out.h5
expect_fail 1 "localnu: junk.bin: line 1: binary data in a text table" localnu junk.bin $T -o out.h5
# Plainly not a contact table: said so before --mu and --diameter are asked for.
: > empty.tsv
expect_fail 1 "localnu: empty.tsv: empty: neither a run (HDF5) nor a contact table" localnu empty.tsv -o out.h5
critical run.h5 --quiet > crit.tsv
expect_fail 1 "localnu: crit.tsv: is a 'critical' product, expected a run (HDF5) or a contact table" localnu crit.tsv -o out.h5
expect_fail 1 "localnu: missing.h5: no such file" localnu missing.h5 -o out.h5
expect_fail 1 "localnu: stdin: no data on standard input (did the previous tool fail?)" bash -c 'localnu - -o out.h5 < /dev/null'
# mu <= 0: on the command line a usage error, in a run's parameters a data error
expect_fail 2 "localnu: --mu must be > 0 (mu = 0 makes every active contact critical), got 0 (see 'localnu --help')" \
  localnu ok.tsv --mu 0 --diameter 1 -o out.h5
expect_fail 2 "localnu: --mu: expected a finite number in [0, 1000], got '-0.5' (out of range) (see 'localnu --help')" \
  localnu run.h5 --mu -0.5 -o out.h5
expect_fail 1 "localnu: mu0.h5: /parameters: mu_grain must be > 0, got 0" localnu mu0.h5 -o out.h5
# a contact table has no parameters: --mu and --diameter are required options (usage errors)
expect_fail 2 "localnu: --mu is required for a contact table (ok.tsv) (see 'localnu --help')" localnu ok.tsv --diameter 1 -o out.h5
expect_fail 2 "localnu: --diameter is required for a contact table (ok.tsv) (see 'localnu --help')" localnu ok.tsv --mu 0.5 -o out.h5
expect_fail 2 "localnu: --mu and --diameter are required for a contact table (nocol.tsv) (see 'localnu --help')" localnu nocol.tsv -o out.h5
expect_fail 2 "localnu: --mu is required for a contact table (stdin) (see 'localnu --help')" bash -c 'localnu - --diameter 1 -o out.h5 < ok.tsv'
expect_fail 1 "localnu: run.h5: no frame 7 to map (--map-frame)" localnu run.h5 --map-frame 7 -o out.h5
expect_fail 2 "localnu: --radii must be strictly increasing (see 'localnu --help')" localnu run.h5 --radii 2,1 -o out.h5
expect_fail 2 "localnu: --map-run 1: there are 1 inputs (see 'localnu --help')" localnu run.h5 --map-run 1 -o out.h5
expect_fail 2 "localnu: --nu and --nu-c exclude each other (see 'localnu --help')" localnu run.h5 --nu x.tsv --nu-c 0.1 -o out.h5
expect_fail 1 "localnu: ok.tsv: not a cdpile critical product (no '# kind:' header line)" localnu run.h5 --nu ok.tsv -o out.h5
# A bad value of an option with a fixed set of values (--table, --format, --edge, --floor-grains)
# is a usage error found when the command line is parsed, before any input is read
# (missing.h5 does not exist); so is a table the other options leave out.
expect_fail 2 "localnu: --table: expected one or more of frames, states, pdf, map, contacts (comma-separated), got 'foo' (see 'localnu --help')" \
  localnu missing.h5 --table foo -o out.tsv
expect_fail 2 "localnu: --table: expected one or more of frames, states, pdf, map, contacts (comma-separated), got 'foo' (see 'localnu --help')" \
  localnu run.h5 --table frames,foo -o out.tsv
expect_fail 2 "localnu: --table contacts without --per-contact (see 'localnu --help')" localnu missing.h5 --table contacts -o out.tsv
expect_fail 2 "localnu: --format: expected one of auto, tsv, hdf5, got 'csv' (see 'localnu --help')" localnu missing.h5 --format csv -o out.tsv
expect_fail 2 "localnu: --edge: expected one of keep, exclude, got 'foo' (see 'localnu --help')" localnu missing.h5 --edge foo -o out.tsv
expect_fail 2 "localnu: --floor-grains: expected one of wall, grain, got 'foo' (see 'localnu --help')" localnu missing.h5 --floor-grains foo -o out.tsv
expect_fail 2 "localnu: '-' (standard input) given twice (see 'localnu --help')" bash -c 'localnu - --nu - -o out.tsv < /dev/null'
test ! -e out.h5
test ! -e out.tsv
expect_eq "" "$(ls -A | grep tmp || true)" "(temporary files left)"

# A header and no rows: no frames, empty tables, NA pdfs; exit 0.
printf 'x\ty\tfn\tft\n' > empty.tsv
localnu empty.tsv $T --pdf-bins 2 --quiet > e.tsv
expect_eq "0 0 0" "$(tsv_result e.tsv frames) $(tsv_rows e.tsv frames) $(tsv_rows e.tsv states)"
expect_eq "NA NA" "$(tsv_value e.tsv pdf P_c 1) $(tsv_value e.tsv pdf P_nc 2)"
# A frame without critical contacts, and a frame whose contacts are all inactive (fn = 0):
# nu_bar NA at every radius, nu = 0 and NA, P_c NA; no NaN anywhere.
printf 'frame\tx\ty\tfn\tft\n0\t0\t0\t1\t0\n0\t1\t0\t1\t0.1\n1\t0\t0\t0\t0\n' > nocrit.tsv
localnu nocrit.tsv $T --radii 1,2 --quiet > n.tsv
expect_eq "0 NA" "$(tsv_value n.tsv frames nu 1) $(tsv_value n.tsv frames nu 2)"
expect_eq "NA NA 0 0" "$(tsv_value n.tsv states nu_bar 1) $(tsv_value n.tsv states nu_bar 2) $(tsv_value n.tsv states n 1) $(tsv_value n.tsv frames N 2)"
expect_eq NA "$(tsv_value n.tsv pdf P_c 1)"
expect_eq "" "$(grep -ilw nan n.tsv e.tsv || true)" "(NaN in the output)"
# ... and it flows through correlate and clusterfit as an empty result.
localnu nocrit.tsv $T -o - --quiet | correlate - -o - | clusterfit - --nu-c 0.1 > f.tsv
expect_eq "0 0" "$(tsv_result f.tsv windows_fitted) $(tsv_rows f.tsv affine)"
expect_eq "" "$(grep -ilw nan f.tsv || true)" "(NaN in the output)"
grep -q '^# note: no window could be fitted' f.tsv
