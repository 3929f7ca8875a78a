# A correlate input that is not a localnu product, is truncated, lacks a column or has a bad row gives one line and exit 1, and no output file.
printf 'frame\ttheta\tx\ty\tfn\tft\n0\t1\t0\t0\t1\t0.5\n0\t1\t1\t0\t1\t0\n' > c.tsv
localnu c.tsv --mu 0.5 --diameter 1 --radii 1,2 --quiet > l.tsv
localnu c.tsv --mu 0.5 --diameter 1 --radii 1,2 -o l.h5 --quiet
correlate l.h5 -o w.h5 --quiet
head -c 3000 l.h5 > truncated.h5
expect_fail 1 "correlate: truncated.h5: cannot open as HDF5 (truncated or damaged?)" correlate truncated.h5 -o out.h5
expect_fail 1 "correlate: w.h5: is a 'correlate' product, expected 'localnu'" correlate w.h5 -o out.h5
expect_fail 1 "correlate: c.tsv: not a cdpile localnu product (no '# kind:' header line)" correlate c.tsv -o out.h5
# Cut at a line boundary: the '# tables:' header line gives it away.
pdf_line=$(grep -n '^# table: pdf' l.tsv | cut -d: -f1)
head -n $(( pdf_line - 1 )) l.tsv > cut.tsv
expect_fail 1 "correlate: cut.tsv: table 'pdf' missing (the header lists it): a truncated file?" correlate cut.tsv -o out.h5
sed "$(( pdf_line - 3 ))d" l.tsv > short.tsv  # the last row of table states
expect_fail 1 "correlate: short.tsv: table 'states' has 1 rows, the header says 2: a truncated file?" correlate short.tsv -o out.h5
# the states table without its 'sum' column
awk -F'\t' -v OFS='\t' '/^# table: states/{s=1} /^# table: pdf/{s=0} s && !/^#/ && NF {NF=5} 1' l.tsv > nosum.tsv
expect_fail 1 "correlate: nosum.tsv: table 'states' has no column 'sum'" correlate nosum.tsv -o out.h5
# a NaN in the states table
awk -F'\t' -v OFS='\t' '/^# table: states/{s=1} /^# table: pdf/{s=0} s && $1 == "0" && !d {$6 = "nan"; d = 1} 1' l.tsv > nan.tsv
rc=0; correlate nan.tsv -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc"
expect_eq 1 "$(wc -l < err.txt)"
grep -q "^correlate: nan.tsv: line [0-9]*, column sum: 'nan' is not a finite number$" err.txt
# a states row whose frame is not in the frames table
awk -F'\t' -v OFS='\t' '/^# table: states/{s=1} /^# table: pdf/{s=0} s && $1 == "0" && !d {$2 = "9"; d = 1} 1' l.tsv > orphan.tsv
expect_fail 1 "correlate: orphan.tsv: table states, row 1: run 0 frame 9 is not in table frames" correlate orphan.tsv -o out.h5
expect_fail 2 "correlate: --window: expected a finite number in [1e-09, 360], got '0' (out of range) (see 'correlate --help')" correlate l.h5 --window 0 -o out.h5
expect_fail 2 "correlate: --from must not be above --to (see 'correlate --help')" correlate l.h5 --from 5 --to 1 -o out.h5
# A bad value of an option with a fixed set of values is a usage error found before the
# input is read (missing.h5 does not exist); so is a table --no-frames leaves out.
expect_fail 2 "correlate: --table: expected one or more of frames, windows (comma-separated), got 'foo' (see 'correlate --help')" \
  correlate missing.h5 --table foo -o out.tsv
expect_fail 2 "correlate: --table: expected one or more of frames, windows (comma-separated), got 'foo' (see 'correlate --help')" \
  correlate l.h5 --table windows,foo -o out.tsv
expect_fail 2 "correlate: --table frames with --no-frames (see 'correlate --help')" correlate missing.h5 --no-frames --table frames -o out.tsv
expect_fail 2 "correlate: --format: expected one of auto, tsv, hdf5, got 'csv' (see 'correlate --help')" correlate missing.h5 --format csv -o out.tsv
test ! -e out.h5
test ! -e out.tsv
