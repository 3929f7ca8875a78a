# A localnu product of the earlier format whose float column is stored as a 4-byte integer of 65535 bits (a damaged type) is refused in one line, by path and from standard input, with no output; HDF5 is never asked to convert it (it read outside its buffer, and SIGBUS killed correlate).
gunzip -c "$CDPILE_SOURCE/tests/fuzz/product/old-format-int-precision-65535.h5.gz" > old.h5
why="/tables/frames/theta: stored as a 4-byte signed integer of 65535 bits at bit offset 0, little-endian, not a standard integer or IEEE float type (damaged, or written by another program): refused before conversion"
expect_fail 1 "correlate: old.h5: $why" correlate old.h5 -o out.tsv
expect_fail 1 "correlate: stdin: $why" bash -c 'correlate - -o out.tsv < old.h5'
test ! -e out.tsv
