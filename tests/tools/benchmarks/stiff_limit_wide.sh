# benchmarks/stiff_limit_wide.sh: the tables of docs/figures/stiff-limit-wide/ and of each
# stiff-limit-wide-mudepMU/ (docs/reproduction.md, "theta_c against k on wide piles") are
# what the script makes from the committed summaries alone, to the byte, none missing and none
# left over: a clone remakes them, and a summary committed without running the script again
# fails here until its tables are remade.
docs=$CDPILE_SOURCE/docs/figures
# check FOLDER [SCRIPT OPTIONS...]: the script's tables against FOLDER's committed ones
check() {
  local folder=$1 made name; shift
  rm -rf out
  "$CDPILE_SOURCE/benchmarks/stiff_limit_wide.sh" "$@" out > stdout.txt 2> stderr.txt ||
    { cat stderr.txt >&2; return 1; }
  grep -q "^stiff_limit_wide.sh: .*/out: " stdout.txt
  for made in out/*.md out/*.tsv; do
    diff -u "$folder/${made#out/}" "$made" ||
      { echo "$folder/${made#out/} is stale: run benchmarks/stiff_limit_wide.sh $*" >&2; return 1; }
  done
  for name in "$folder"/*.md "$folder"/*.tsv; do  # the folder's README.md is not made
    name=${name##*/}
    [[ $name == README.md || -e out/$name ]] ||
      { echo "$folder/$name: not made by benchmarks/stiff_limit_wide.sh $* any more" >&2; return 1; }
  done
  ls out/*.md out/*.tsv | wc -l > count.txt
}
check "$docs/stiff-limit-wide"
expect_eq 7 "$(cat count.txt)" "(loose tables made: limit-*.md, per-degree-1e6-1e7.md, per-degree-1e6-1e8.md, seeds.md, runs.tsv, nu_c.tsv)"
preparations=0
for folder in "$docs"/stiff-limit-wide-mudep*; do
  [[ -d $folder ]] || continue
  check "$folder" --mu-deposit "${folder##*-mudep}"
  preparations=$((preparations + 1))
done
echo "checked the loose tables and $preparations other preparation(s)"
