# Usage errors exit 2 with one line and are found before any run is read; nothing is written.
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\n0\t1\t0\t1\t0\t0\t1\t0.5\n0\t1\t1\t2\t1\t0\t1\t0\n' > ok.tsv
table-to-run ok.tsv run.h5 1 0.5
# An unknown table: refused when the command line is parsed, before the runs are read
# (missing.h5 does not exist).
expect_fail 2 "critical: --table: expected one or more of runs, steps, frames, events, ensemble, envelope, mobilisation, windows (comma-separated), got 'foo' (see 'critical --help')" \
  critical missing.h5 --table foo
expect_fail 2 "critical: --table: expected one or more of runs, steps, frames, events, ensemble, envelope, mobilisation, windows (comma-separated), got 'foo' (see 'critical --help')" \
  critical run.h5 --table frames,foo -o out.tsv
expect_fail 2 "critical: --table steps with --no-steps (see 'critical --help')" critical run.h5 --table steps --no-steps
expect_fail 2 "critical: --table steps with --no-steps (see 'critical --help')" critical missing.h5 --no-steps --table runs,steps -o out.tsv
# Every option with a fixed set of values is checked the same way, up front.
expect_fail 2 "critical: --series: expected one of auto, steps, frames, sliding, got 'foo' (see 'critical --help')" \
  critical missing.h5 --series foo -o out.tsv
expect_fail 2 "critical: --rattlers: expected one of exclude, include, got 'foo' (see 'critical --help')" \
  critical missing.h5 --rattlers foo -o out.tsv
expect_fail 2 "critical: --floor-grains: expected one of wall, grain, got 'foo' (see 'critical --help')" \
  critical missing.h5 --floor-grains foo -o out.tsv
expect_fail 2 "critical: --format: expected one of auto, tsv, hdf5, got 'csv' (see 'critical --help')" \
  critical run.h5 --format csv -o out.tsv
expect_fail 2 "critical: --table chooses tables of TSV output; an HDF5 product (-o out.h5) holds them all (use a .tsv name or --format tsv) (see 'critical --help')" \
  critical missing.h5 --table frames -o out.h5
critical run.h5 --table runs,frames --quiet > t.tsv
expect_eq "1 1" "$(tsv_rows t.tsv runs) $(tsv_rows t.tsv frames)"
test ! -e out.tsv
# The same run twice (or by two paths) would be counted twice in the ensemble: refused.
mkdir sub
expect_fail 2 "critical: ./run.h5: the same file as run.h5; an ensemble counts each run once (see 'critical --help')" \
  critical run.h5 ./run.h5 -o out.tsv
expect_fail 2 "localnu: sub/../run.h5: the same file as run.h5; an ensemble counts each run once (see 'localnu --help')" \
  localnu run.h5 sub/../run.h5 -o out.tsv
test ! -e out.tsv
# A target that make would clobber is refused before the runs are read (missing.h5 is
# not looked at): an existing output without --force, a missing folder.
touch exists.tsv
expect_fail 1 "critical: exists.tsv: exists; not overwritten (use --force to replace it)" critical missing.h5 -o exists.tsv
expect_fail 1 "localnu: exists.tsv: exists; not overwritten (use --force to replace it)" localnu missing.h5 -o exists.tsv
expect_fail 1 "correlate: exists.tsv: exists; not overwritten (use --force to replace it)" correlate missing.h5 -o exists.tsv
expect_fail 1 "clusterfit: exists.tsv: exists; not overwritten (use --force to replace it)" clusterfit missing.h5 -o exists.tsv
