# Usage errors exit 2 with one line naming the option; nothing is written.
expect_fail 2 "cli-demo: --count: expected an integer in [1, 100000], got '1e' (see 'cli-demo --help')" \
  cli-demo --count 1e -o out.h5
expect_fail 2 "cli-demo: --scale: expected a finite number in [1e-09, 1000], got 'nan' (see 'cli-demo --help')" \
  cli-demo --scale nan -o out.h5
expect_fail 2 "cli-demo: unrecognised option '--coun' (see 'cli-demo --help')" cli-demo --coun 3 -o out.h5
expect_fail 2 "cli-demo: no output file given (-o FILE, or -o - for standard output) (see 'cli-demo --help')" cli-demo
test ! -e out.h5
