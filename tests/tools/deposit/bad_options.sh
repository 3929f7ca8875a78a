# Bad options are one-line usage errors (exit 2) and leave no output file.
expect_fail 2 "deposit: --grains: expected an integer in [1, 100000000], got '-3' (out of range) (see 'deposit --help')" \
  deposit --grains -3 -o x.h5
expect_fail 2 "deposit: --width must be at least Dmax + 0.2 D = 1.400000 D (see 'deposit --help')" \
  deposit --grains 10 --width 1.2 -o x.h5
expect_fail 2 "deposit: --diameter: expected a finite number in [1e-09, 1000], got '-1e-3' (out of range) (see 'deposit --help')" \
  deposit --diameter -1e-3 -o x.h5
expect_fail 2 "deposit: no output file given (-o FILE, or -o - for standard output) (see 'deposit --help')" \
  deposit --grains 10
test ! -e x.h5
# An existing file is not overwritten.
echo keep > x.h5
expect_fail 1 "deposit: x.h5: exists; not overwritten (use --force to replace it)" deposit --grains 10 -o x.h5
expect_eq keep "$(cat x.h5)"
