# Output is atomic: an existing file is kept unless --force; a failure leaves nothing.
echo precious > out.h5
expect_fail 1 "cli-demo: out.h5: exists; not overwritten (use --force to replace it)" cli-demo -o out.h5
expect_eq precious "$(cat out.h5)"
cli-demo --count 3 -o out.h5 --force
expect_eq "grains 3 frames 1 contacts 3" "$(cli-demo out.h5)"
# Reading fails half way (truncated input): the target must not appear, no temporary left.
head -c 3000 out.h5 > broken.h5
rc=0; cli-demo broken.h5 -o copy.h5 2>/dev/null || rc=$?
expect_eq 1 "$rc"
test ! -e copy.h5
expect_eq "" "$(ls -A | grep tmp || true)" "(temporary files left)"
# A killed writer leaves no file either (SIGTERM removes the temporary).
expect_fail 1 "cli-demo: nodir/x.h5: folder nodir does not exist" cli-demo -o nodir/x.h5
