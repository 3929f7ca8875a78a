# Usage errors exit 2 with one line and are found before any run is read; nothing is written.
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\n0\t1\t0\t1\t0\t0\t1\t0.5\n0\t1\t1\t2\t1\t0\t1\t0\n' > ok.tsv
table-to-run ok.tsv run.h5 1 0.5
# An unknown table: refused before the runs are read (missing.h5 does not exist).
expect_fail 2 "critical: --table: no table 'foo' (critical writes runs, steps, frames, events, ensemble, envelope) (see 'critical --help')" \
  critical missing.h5 --table foo
expect_fail 2 "critical: --table: no table 'foo' (critical writes runs, steps, frames, events, ensemble, envelope) (see 'critical --help')" \
  critical run.h5 --table frames,foo -o out.tsv
expect_fail 2 "critical: --table steps with --no-steps (see 'critical --help')" critical run.h5 --table steps --no-steps
critical run.h5 --table runs,frames --quiet > t.tsv
expect_eq "1 1" "$(tsv_rows t.tsv runs) $(tsv_rows t.tsv frames)"
test ! -e out.tsv
