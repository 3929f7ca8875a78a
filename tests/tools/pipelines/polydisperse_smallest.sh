# make -C pipelines polydisperse at its smallest (60 disks, two seeds, Dmax/Dmin = 3 beside
# 1.5): one table with a column per size ratio, each from its own summaries, whose theta_c
# is the mean of critical's per-run theta_c of that study's runs (those it detects);
# refused in one line, with nothing on stdout, while the other ratio has no summary yet.
# ctest: slow, timeout 120
B=$CDPILE_BIN
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" NAME=t GRAINS=60 WIDTH=10 RATE=0.1 \
  FRAME_EVERY_DEG=1 MAP_THETAS=1 RADII=1:1:3 SEEDS="1 2" POLYDISPERSE_RATIO=3 STUDIES="$PWD/studies" \
  SUMMARY_ROOT="$PWD/summaries" CDPILE_BIN="$B" "$@"; }
mk summaries > make1.log 2>&1 || { cat make1.log >&2; exit 1; }
# Dmax/Dmin = 3 not summarised yet: one line, exit non-zero, no table.
if mk -s polydisperse > none.md 2> none.err; then echo "polydisperse made a table without the other study" >&2; exit 1; fi
grep -qx "pipelines: polydisperse: no summary of the study at Dmax/Dmin = 3 yet" none.err || { cat none.err >&2; exit 1; }
[[ ! -s none.md ]]
mk summaries POLYDISPERSITY=3 > make2.log 2>&1 || { cat make2.log >&2; exit 1; }
mk -s polydisperse > table.md 2> make3.log || { cat make3.log table.md >&2; exit 1; }
head -n 1 table.md | grep -q '| quantity | paper | Dmax/Dmin = 1.5 (2 runs of 60 grains) |.*| Dmax/Dmin = 3 (2 runs of 60 grains) |' \
  || { head -n 1 table.md >&2; exit 1; }
# theta_c of each column: the mean of the per-run theta_c critical gives for its summaries.
for r in 1.5 3; do
  "$B/critical" summaries/t-N60-R$r-mu0.5-rate0.1-pcg/run-{1,2}.summary.h5 --table runs --quiet \
    | awk -F'\t' '$1 ~ /^[0-9]+$/ && $8 != "NA" {s += $8; n++} END {printf "%.6f\n", s / n}' > theta-$r.txt
done
row=$(grep '^| theta_c (deg) |' table.md)
IFS='|' read -r _ _ _ c15 _ _ c3 _ <<< "$row"
# printed to 4 digits: within 0.05 degree
expect_near "$(cat theta-1.5.txt)" "$(cut -d' ' -f2 <<< "$c15")" 0.05
expect_near "$(cat theta-3.txt)" "$(cut -d' ' -f2 <<< "$c3")" 0.05
[[ $(cat theta-1.5.txt) != "$(cat theta-3.txt)" ]]  # two studies, not one twice
