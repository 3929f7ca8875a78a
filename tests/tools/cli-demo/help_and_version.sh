# --help lists every option with its default and unit and exits 0; --version exits 0.
cli-demo --help > help.txt
grep -q '^Usage: cli-demo \[options\] \[INPUT\]$' help.txt
grep -q 'mean diameter of the sample grains (unit: m; default: 0.001; in' help.txt
grep -q -- '--force' help.txt
grep -q '^Exit status: 0 success; 1 runtime or data error' help.txt
expect_eq "cli-demo (cdpile) 0.1.0" "$(cli-demo --version)"
cli-demo --help-markdown | grep -q '^| `--count N` | number of grains of the sample pile (in \[1, 100000\]) |  | `4` |$'
