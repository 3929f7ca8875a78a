# Every check that does not need the result comes before the work: binary output to a
# terminal is refused before deposit simulates and before critical or localnu read a run,
# and an existing output before tilt-cd reads its input.
command -v script > /dev/null || exit 77
msg="refusing to write HDF5 to a terminal (use -o FILE or a pipe)"
# 4000 grains take minutes to settle: the refusal must come first
timeout 120 script -qec "deposit --grains 4000 -o -; echo rc=\$?" /dev/null > tty.txt || true
expect_eq "deposit: stdout: $msg|rc=1" "$(tr -d '\r' < tty.txt | paste -sd '|')"
for tool in critical localnu; do
  script -qec "$tool missing.h5 -o -; echo rc=\$?" /dev/null > tty.txt
  expect_eq "$tool: stdout: $msg|rc=1" "$(tr -d '\r' < tty.txt | paste -sd '|')"
done
script -qec "critical missing.h5 --format hdf5; echo rc=\$?" /dev/null > tty.txt
expect_eq "critical: stdout: $msg|rc=1" "$(tr -d '\r' < tty.txt | paste -sd '|')"
# tilt-cd: an existing output, before its input (here one that never ends) is read
touch out.h5
mkfifo never
exec 3<> never
rc=0
timeout 120 tilt-cd - -o out.h5 < never 2> stderr.txt || rc=$?
exec 3>&-
expect_eq 1 "$rc"
expect_eq "tilt-cd: out.h5: exists; not overwritten (use --force to replace it)" "$(cat stderr.txt)"
script -qec "tilt-cd missing.h5 -o -; echo rc=\$?" /dev/null > tty.txt
expect_eq "tilt-cd: stdout: $msg|rc=1" "$(tr -d '\r' < tty.txt | paste -sd '|')"
