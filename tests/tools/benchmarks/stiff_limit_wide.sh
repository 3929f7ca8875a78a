# benchmarks/stiff_limit_wide.sh: the tables of docs/figures/stiff-limit-wide/ (docs/reproduction.md,
# "theta_c against k on wide piles") are what the script makes from the committed summaries
# alone, to the byte: a clone remakes them, and a summary committed without running the
# script again fails here until its tables are remade.
docs=$CDPILE_SOURCE/docs/figures/stiff-limit-wide
"$CDPILE_SOURCE/benchmarks/stiff_limit_wide.sh" out > stdout.txt 2> stderr.txt || { cat stderr.txt >&2; exit 1; }
grep -q "^stiff_limit_wide.sh: .*/out: " stdout.txt
found=0
for made in out/*.md out/*.tsv; do
  found=$((found + 1))
  diff -u "$docs/${made#out/}" "$made" ||
    { echo "$docs/${made#out/} is stale: run benchmarks/stiff_limit_wide.sh" >&2; exit 1; }
done
expect_eq 6 "$found" "(tables made: limit-*.md, per-degree-1e6-1e8.md, seeds.md, runs.tsv, nu_c.tsv)"
