# The structure mutator's findings (tests/fuzz/*/structure-*, valid checksummed files with a wrong structure), a damaged partial run (tests/fuzz/run/partial-*) and the damaged type of tests/fuzz/product/ give one line naming the file and the object, exit 1 and no output, in every tool that reads them, by path and from standard input.
src="$CDPILE_SOURCE/tests/fuzz"
# expect_refused NAME TOOL ARGS...: exit 1, one line "TOOL: NAME: /PATH...: ..." on stderr
# (the object named), nothing written.
expect_refused() {
  local name=$1 tool=$2; shift 2
  local rc=0
  rm -rf out.*
  timeout 120 "$tool" "$@" > /dev/null 2> err.txt || rc=$?
  expect_eq 1 "$rc" "(exit code of $tool $*: $(cat err.txt))"
  expect_eq 1 "$(wc -l < err.txt)" "(lines on stderr from $tool $*: $(cat err.txt))"
  grep -q "^$tool: $name: /[^ ]*: " err.txt || { echo "no object named: $(cat err.txt)" >&2; return 1; }
  test -z "$(ls out.* 2> /dev/null)"
}
found=0
# unpack GZ: the input, gunzipped into the working folder as $f, counted in $found
unpack() {
  found=$((found + 1))
  f=$(basename "$1" .gz)
  gunzip -c "$1" > "$f"
}
for gz in "$src"/run/structure-*.h5.gz; do
  [[ -e $gz ]] || continue
  unpack "$gz"
  expect_refused "$f" critical "$f" -o out.tsv
  expect_refused "$f" localnu "$f" -o out.h5
  expect_refused "$f" to-xdmf "$f" -o out.xdmf
  expect_refused "$f" to-lammps "$f" -o out.dump
  expect_refused stdin critical - -o out.tsv < "$f"
done
# A partial run whose series is damaged (fuzz_run's finding): the tools that read the
# series refuse it in one line, without the partial run's note before it.
for gz in "$src"/run/partial-*.h5.gz; do
  unpack "$gz"
  expect_refused "$f" critical "$f" -o out.tsv
  expect_refused "$f" localnu "$f" -o out.h5
  expect_refused stdin critical - -o out.tsv < "$f"
done
for gz in "$src"/product/*.h5.gz; do
  unpack "$gz"
  expect_refused "$f" correlate "$f" -o out.tsv
  expect_refused "$f" clusterfit "$f" -o out.tsv
  expect_refused stdin correlate - -o out.tsv < "$f"
done
[[ $found -ge 3 ]]
