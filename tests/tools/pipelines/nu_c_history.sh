# pipelines/nu_c_history.py: critical over the first n summaries, seeds in numeric order
# (2, 3, 10, not 10, 2, 3); each row is critical's own result over those runs; a folder
# without summaries and a mix that critical refuses stop with one line.
# ctest: slow, timeout 120
B=$CDPILE_BIN
mkdir -p sums
for s in 2 3 10; do
  "$B/deposit" --grains 60 --width 10 --seed $s --quiet -o pile-$s.h5
  "$B/tilt-cd" pile-$s.h5 --rate 0.05 --frame-every-deg 1 --quiet -o run-$s.h5
  "$B/summarise" run-$s.h5 --radii 1:1:3 --map-theta 1 --quiet -o sums/run-$s.summary.h5
done
"$PY" "$CDPILE_SOURCE/pipelines/nu_c_history.py" sums --from 1 > table.md
expect_eq "1 2 3" "$(awk -F'|' '/^\| [0-9]/ {gsub(/ /, "", $2); printf "%s ", $2}' table.md | sed 's/ $//')" "(runs column)"
expect_eq "2 3 10" "$(awk -F'|' '/^\| [0-9]/ {gsub(/ /, "", $3); printf "%s ", $3}' table.md | sed 's/ $//')" "(seeds column, numeric order)"
# Rows 2 and 3 are critical's results over seeds {2, 3} and {2, 3, 10}.
for n in 2 3; do
  case $n in 2) files="sums/run-2.summary.h5 sums/run-3.summary.h5" ;; 3) files="sums/run-2.summary.h5 sums/run-3.summary.h5 sums/run-10.summary.h5" ;; esac
  "$B/critical" $files --no-steps --quiet -o c$n.h5
  want=$("$PY" - c$n.h5 <<'PYEOF'
import sys, h5py
r = h5py.File(sys.argv[1], "r")["results"].attrs
def cell(k):
    return "none" if k not in r else f"{float(r[k]):.4f}" + (f" ± {float(r[k + '_se']):.4f}" if k + "_se" in r else "")
print(f"| {cell('nu_c_static')} | {cell('nu_c')} |")
PYEOF
)
  got=$(grep "^| $n |" table.md | cut -d'|' -f4- | sed 's/^/|/')
  expect_eq "$want" "$got" "(row $n)"
done
mkdir empty
expect_fail 1 "nu_c_history.py: empty: no run-SEED.summary.h5" "$PY" "$CDPILE_SOURCE/pipelines/nu_c_history.py" empty
# A summary at another eps beside the others: critical's refusal, in its one line.
"$B/summarise" run-10.h5 --eps 1e-2 --radii 1:1:3 --map-theta 1 --quiet -o sums/run-11.summary.h5
rc=0; "$PY" "$CDPILE_SOURCE/pipelines/nu_c_history.py" sums --from 4 > out.md 2> err.txt || rc=$?
[[ $rc -ne 0 && $(wc -l < err.txt) -eq 1 ]] || { echo "rc=$rc"; cat err.txt; exit 1; } >&2
grep -q '^critical: ' err.txt || { cat err.txt >&2; exit 1; }
