# ctest: slow, timeout 600
# README's first session, run as written in a folder outside the clone (its first line
# points PATH at this build instead of the clone's build/), and every number README says
# it gives checked against what the commands print: the numbers cannot go stale. Also:
# the folder the session makes in the clone is ignored by git.
readme="$CDPILE_SOURCE/README.md"
awk '/^<!-- first session/{on=1; next} on && /^    /{print substr($0, 5); next} on{exit}' "$readme" |
  sed 's/  *# .*$//' > session.sh
expect_eq 8 "$(wc -l < session.sh)" "(lines of the session)"
expect_eq 'export PATH=$PWD/build/bin:$PWD/pipelines:$PATH' "$(head -n 1 session.sh)"
expect_eq 'mkdir -p first && cd first' "$(sed -n 2p session.sh)"
{ echo "export PATH=$CDPILE_BIN:$CDPILE_SOURCE/pipelines:\$PATH"; tail -n +2 session.sh; } > run_session.sh
bash -euo pipefail run_session.sh > session.out 2> session.err
cd first
test -s pile.h5 && test -s run.h5 && test -s critical.tsv && test -s fit.tsv && test -s pile.png

# What the commands printed and wrote
runs() { awk -F'\t' -v c="$1" '$1 == "run" { for (i = 1; i <= NF; i++) if ($i == c) k = i; next }
                                 k && $1 == "0" { print $k; exit }' ../session.out; }
theta_c=$(runs theta_c) nu_max=$(printf '%.3g' "$(runs nu_max)") events=$(runs events)
readings=$(sed -n 's/^critical: \(theta_c = .*\)$/\1/p' ../session.err | head -n 1)
test -n "$readings"
above=$(tsv_result critical.tsv nu_c_maxima_above_static_bound)
judged=$(tsv_result critical.tsv nu_c_maxima_judged)
fitted=$(tsv_result fit.tsv windows_fitted) windows=$(tsv_result fit.tsv windows)
rc=0
for ((r = 1; r <= $(tsv_rows fit.tsv fits); r++)); do
  [[ $(tsv_value fit.tsv fits r_c "$r") != NA ]] && rc=$((rc + 1))
done
why=$(grep '^clusterfit: ' ../session.err | head -n 1)
test -n "$why"

# ... against what README says, its paragraph joined into one line
said=$(awk '/^What it gives/{on=1} on && /^$/{exit} on' "$readme" | tr '\n' ' ')
for phrase in "**theta_c = $theta_c deg**" "**nu_max = $nu_max**" "after $events rearrangement events" \
              "critical ends with the line \`$readings\`" \
              "$above of its $judged maxima are at frames with more critical contacts" \
              "in $fitted of its $windows one-degree windows" "with a cluster size r_c in $rc of them" \
              "(\`$why\`)"; do
  [[ $said == *"$phrase"* ]] || { echo "README does not say: $phrase" >&2; echo "it says: $said" >&2; exit 1; }
done
# the warning README speaks of was given
grep -q "^critical: warning: nu_c comes from frames above the static bound: $above of the $judged " ../session.err

# what the session writes in the clone is not for git
if git -C "$CDPILE_SOURCE" rev-parse --git-dir > /dev/null 2>&1; then
  git -C "$CDPILE_SOURCE" check-ignore -q first/run.h5
fi
