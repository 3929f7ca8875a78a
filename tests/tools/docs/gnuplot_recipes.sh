# The gnuplot recipes of the docs run as written (gnuplot-nox, dumb terminal): the nu map of
# docs/analysis.md (index 'table: map' of the whole TSV product), and the tool pages'
# examples for gnuplot (critical's frames, correlate's windows, localnu's map).
if ! command -v gnuplot > /dev/null; then
  echo "skipped: gnuplot (Debian package gnuplot-nox) is not installed; scripts/install-deps.sh installs it" >&2
  exit 77
fi
export GNUTERM=dumb
docs="$CDPILE_SOURCE/docs"
block() { awk -v b="$2" '$0 == "```sh " b {on=1; next} /^```/{on=0} on' "$1"; }
example() { awk -v t="**$2**" '$0 == t {on=1; next} on && /^```sh$/ {code=1; next} code && /^```$/ {exit} code' "$1"; }
# gnuplot: every plot drew points (a warning or an error fails), exit status 0
plotted() {
  if grep -i 'warning\|error\|invalid' "$1.err" >&2; then return 1; fi
  test "$(wc -l < "$1.txt")" -gt 10
}
deposit --grains 100 --width 12 --seed 3 -o pile.h5 --quiet
tilt-cd pile.h5 --rate 0.5 --to 10 --frame-every 2 -o run.h5 --quiet
block "$docs/analysis.md" gnuplot-map > map.sh
expect_eq 2 "$(wc -l < map.sh)" "(lines of the recipe)"
bash -euo pipefail map.sh > map.txt 2> map.err.all
grep -v '^localnu: ' map.err.all > map.err || true
plotted map
# critical: "One run, the per-frame table for gnuplot": columns run, frame, step, theta, N, Nc, nu
example "$docs/tools/critical.md" "One run, the per-frame table for gnuplot" > frames.sh
bash -euo pipefail frames.sh 2> /dev/null
gnuplot -e "plot 'frames.tsv' u 4:7 w lp" > frames.txt 2> frames.err
plotted frames
# correlate: "nu_bar against r at every degree, for gnuplot", plotted with 'u 4:8:9 w yerr'
localnu run.h5 --quiet -o localnu.h5
example "$docs/tools/correlate.md" "nu_bar against r at every degree, for gnuplot" > nubar.sh
grep -q "plot with 'u 4:8:9 w yerr'" "$docs/tools/correlate.md"
bash -euo pipefail nubar.sh
gnuplot -e "plot 'nubar.tsv' u 4:8:9 w yerr" > nubar.txt 2> nubar.err
plotted nubar
# localnu's help: after 'localnu run.h5 --table map > map.tsv', plot "map.tsv" u 5:6:9 w image
grep -q "after 'localnu run.h5 --table map > map.tsv', gnuplot's 'plot \"map.tsv\" u 5:6:9 w image'" "$docs/tools/localnu.md"
localnu run.h5 --table map --quiet > map.tsv
gnuplot -e 'plot "map.tsv" u 5:6:9 w image' > help_map.txt 2> help_map.err
plotted help_map
