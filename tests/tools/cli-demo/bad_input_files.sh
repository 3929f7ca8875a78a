# Bad input files exit 1 with one line (tool: file: where: what), never an HDF5 stack.
printf 'x\ty\n1\t2\n' > table.tsv
expect_fail 1 "cli-demo: table.tsv: not an HDF5 file (no HDF5 signature)" cli-demo table.tsv
expect_fail 1 "cli-demo: missing.h5: no such file" cli-demo missing.h5
cli-demo --count 20 -o good.h5
head -c 3000 good.h5 > truncated.h5
rc=0; cli-demo truncated.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code for a truncated file)"
expect_eq 1 "$(wc -l < err.txt)" "(lines of error)"
grep -q '^cli-demo: truncated.h5: .*truncated' err.txt
expect_fail 1 "cli-demo: stdin: no data on standard input (did the previous tool fail?)" \
  bash -c 'cli-demo - < /dev/null'
expect_fail 1 "cli-demo: stdin: not an HDF5 file (no HDF5 signature)" bash -c 'cli-demo - < table.tsv'
# A pile with a negative radius, written by h5py as another program might.
cp good.h5 negative.h5
"$PY" -c "import h5py; f = h5py.File('negative.h5', 'r+'); f['particles/grains/radius'][3] = -1e-3"
expect_fail 1 "cli-demo: negative.h5: /particles/grains/radius: radius of grain 3 is not positive" cli-demo negative.h5
