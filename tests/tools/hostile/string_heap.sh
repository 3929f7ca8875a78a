# A run of this version's format whose global heap (the units' variable-length strings) is damaged: every tool that reads it exits 1 with one line, no output, no hang.
# ctest: slow, timeout 180
src="$CDPILE_SOURCE"
gunzip -c "$src/tests/fuzz/run/run-unit-global-heap-hang.h5.gz" > bad.h5
cp "$src/fuzz/corpus/run/run.h5" good-run.h5

# expect_refused TOOL NAME ARGS...: exit 1, one line naming the global heap, no output
# left; a generous bound on the time (the child's CPU bound is 5 s; the machine may be busy).
expect_refused() {
  local tool=$1 name=$2; shift 2
  local rc=0
  rm -f out.*
  timeout 300 "$tool" "$@" > stdout.txt 2> err.txt || rc=$?
  expect_eq 1 "$rc" "(exit code of $tool $*)"
  expect_eq 1 "$(wc -l < err.txt)" "(lines on stderr from $tool $*: $(cat err.txt))"
  expect_eq 0 "$(wc -c < stdout.txt)" "(bytes on stdout from $tool $*)"
  if ! grep -qx "$tool: $name: damaged HDF5 file: .* (global heap of its string attributes)" err.txt; then
    echo "unexpected message from $tool $*: $(cat err.txt)" >&2; return 1
  fi
  if compgen -G 'out.*' > /dev/null || compgen -G '.out.*' > /dev/null; then echo "output left by $tool $*" >&2; return 1; fi
}

expect_refused critical bad.h5 bad.h5 -o out.tsv
expect_refused critical stdin - -o out.tsv < bad.h5
expect_refused localnu bad.h5 bad.h5 -o out.h5
expect_refused to-xdmf bad.h5 bad.h5 -o out.xdmf
expect_refused to-lammps bad.h5 bad.h5 -o out.dump
expect_refused tilt-cd bad.h5 bad.h5 --branch-at 0.5 --to 1 -o out.h5
# an interrupted run whose partial file is the damaged run
cp bad.h5 out.h5.partial
rc=0
timeout 300 tilt-cd good-run.h5 --branch-at 0.5 --to 1 -o out.h5 --resume > stdout.txt 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code of tilt-cd --resume)"
expect_eq 1 "$(wc -l < err.txt)" "(lines on stderr from tilt-cd --resume: $(cat err.txt))"
[[ ! -e out.h5 ]] || { echo "tilt-cd --resume wrote out.h5" >&2; exit 1; }

# The intact run is read as before.
critical good-run.h5 -o crit.tsv --quiet
