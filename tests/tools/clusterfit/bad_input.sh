# clusterfit refuses other products, truncated files and bad options with one line; nothing to fit is a documented empty result.
"$PY" "$CDPILE_SOURCE/tests/tools/clusterfit/synthetic.py" d.tsv 0 1 law
printf '# kind: localnu\n\n\n# table: frames\nrun\n' > l.tsv
clusterfit d.tsv -o f.h5 --quiet
head -c 3000 f.h5 > truncated.h5
expect_fail 1 "clusterfit: l.tsv: is a 'localnu' product, expected 'correlate'" clusterfit l.tsv -o out.h5
expect_fail 1 "clusterfit: f.h5: is a 'clusterfit' product, expected 'correlate'" clusterfit f.h5 -o out.h5
expect_fail 1 "clusterfit: truncated.h5: cannot open as HDF5 (truncated or damaged?)" clusterfit truncated.h5 -o out.h5
expect_fail 1 "clusterfit: d.tsv: is a 'correlate' product, expected 'critical'" clusterfit d.tsv --nu d.tsv -o out.h5
sed 's/\tnu_bar\t/\tnb\t/' d.tsv > nocol.tsv
expect_fail 1 "clusterfit: nocol.tsv: table 'windows' has no column 'nu_bar'" clusterfit nocol.tsv -o out.h5
sed '6s/\t[^\t]*$/\tnan/' d.tsv > nan.tsv
expect_fail 1 "clusterfit: nan.tsv: line 6, column nu_pile: 'nan' is not a finite number" clusterfit nan.tsv -o out.h5
expect_fail 2 "clusterfit: --r-max must be above --r-min (see 'clusterfit --help')" clusterfit d.tsv --r-min 5 --r-max 2 -o out.h5
expect_fail 2 "clusterfit: --nu-inf ensemble needs the critical product (--nu FILE) (see 'clusterfit --help')" clusterfit d.tsv --nu-inf ensemble -o out.h5
expect_fail 2 "clusterfit: --nu-c: expected a finite number in [1e-12, 0.999999], got '0' (out of range) (see 'clusterfit --help')" clusterfit d.tsv --nu-c 0 -o out.h5
# A bad value of an option with a fixed set of values (--table, --format, --nu-inf, --rc-from)
# is a usage error found before any input is read (missing.h5 does not exist).
expect_fail 2 "clusterfit: --table: expected one or more of fits, model, affine (comma-separated), got 'foo' (see 'clusterfit --help')" \
  clusterfit missing.h5 --table foo -o out.tsv
expect_fail 2 "clusterfit: --table: expected one or more of fits, model, affine (comma-separated), got 'foo' (see 'clusterfit --help')" \
  clusterfit d.tsv --table fits,foo -o out.tsv
expect_fail 2 "clusterfit: --format: expected one of auto, tsv, hdf5, got 'csv' (see 'clusterfit --help')" clusterfit missing.h5 --format csv -o out.tsv
expect_fail 2 "clusterfit: --nu-inf: expected one of auto, ensemble, pile, fit, got 'foo' (see 'clusterfit --help')" clusterfit missing.h5 --nu-inf foo -o out.tsv
expect_fail 2 "clusterfit: --rc-from: expected one of window, affine, got 'foo' (see 'clusterfit --help')" clusterfit missing.h5 --rc-from foo -o out.tsv
# both inputs from standard input: refused before either is read
expect_fail 2 "clusterfit: '-' (standard input) given twice (see 'clusterfit --help')" bash -c 'clusterfit - --nu - -o out.tsv < d.tsv'
test ! -e out.h5
test ! -e out.tsv
# Too few radii to fit (L = 3 leaves 3 < 4 points): no fit, NA values, a note; exit 0.
clusterfit d.tsv --r-max 3 --nu-c 0.08 > e.tsv
expect_eq "0 NA NA 0" "$(tsv_result e.tsv windows_fitted) $(tsv_value e.tsv fits A 1) $(tsv_value e.tsv fits r_c 1) $(tsv_rows e.tsv affine)"
grep -q '^# note: no window could be fitted' e.tsv
expect_eq "" "$(tsv_result e.tsv beta)"
expect_eq "" "$(grep -ilw nan e.tsv || true)" "(NaN in the output)"
# No nu_c: A and alpha, but r_c not computed, said in a note
clusterfit d.tsv > n.tsv
expect_eq "3 NA" "$(tsv_result n.tsv windows_fitted) $(tsv_value n.tsv fits r_c 1)"
grep -q '^# note: r_c not computed: no nu_c' n.tsv
