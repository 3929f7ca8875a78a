# A number the tool cannot compute is said on stderr, one line with its reason, not only in
# a '# note:' line of the output (--quiet silences it like the other information).
"$PY" "$CDPILE_SOURCE/tests/tools/clusterfit/synthetic.py" exact.tsv 0 1 law
clusterfit exact.tsv > f.tsv 2> stderr.txt
expect_eq "clusterfit: r_c not computed: no nu_c (give --nu-c, or --nu with a critical product that has one)" "$(cat stderr.txt)"
grep -q '^# note: r_c not computed: no nu_c' f.tsv
clusterfit exact.tsv --quiet > q.tsv 2> stderr.txt
expect_eq 0 "$(wc -c < stderr.txt)"
# with nu_c, r_c is computed and nothing is said
clusterfit exact.tsv --nu-c 0.08 --power-from 0 > rc.tsv 2> stderr.txt
if grep -q 'r_c not computed' stderr.txt rc.tsv; then echo "r_c said not computed with --nu-c" >&2; exit 1; fi
