# The solver-path ensemble at its smallest (80 disks, one run, one window of 3 steps,
# two scrambled paths and a rigid branch): the branches start from the run's frames, path 0
# redoes the run's own steps, the summary reports the window, one past the run's end is
# skipped with its reason, a second make redoes nothing, and the ensemble's tables are kept
# beside the study's summaries, where the reports find them once the branches are gone.
# ctest: slow, timeout 120
B=$CDPILE_BIN
"$B/deposit" --grains 80 --width 10 --seed 3 --quiet -o pile.h5
mkdir -p study
"$B/tilt-cd" pile.h5 --rate 0.05 --to 8 --stiffness 1e5 --frame-every-deg 1 --quiet -o study/run-1.h5
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" indeterminacy STUDY="$PWD/study" RATE=0.05 STIFFNESS=1e5 \
  INDETERMINACY_SEEDS=1 INDETERMINACY_ANGLES="2 9" CDPILE_BIN="$B" SUMMARY_ROOT="$PWD/summaries" \
  INDETERMINACY_OPTIONS='WINDOW=0.15 FRAMES=3 PATHS="1 2" RULES=0' "$@"; }
mk > make1.log 2>&1 || { cat make1.log >&2; exit 1; }
out=study/indeterminacy
for a in 2; do for p in path-0 path-1 path-2 k0; do [[ -s $out/run-1/theta-$a/$p.h5 ]] || { echo "missing $p at $a" >&2; exit 1; }; done; done
# Path 0 is the run itself, redone: its per-step critical counts equal the run's over the window.
"$PY" - "$out/run-1/theta-2/path-0.h5" study/run-1.h5 <<'PYEOF'
import sys, h5py, numpy as np
b, r = h5py.File(sys.argv[1], "r"), h5py.File(sys.argv[2], "r")
# a branch numbers its steps from 1 after the run's step branch_step
first = int(b["parameters"].attrs["branch_step"])
bc = b["observables/critical_grain/value"][:]
rc = dict(zip(r["observables/critical_grain/step"][:], r["observables/critical_grain/value"][:]))
assert len(bc) == 3, len(bc)
assert list(bc) == [rc[first + k] for k in range(1, 4)], (list(bc), [rc[first + k] for k in range(1, 4)])
PYEOF
# The summary has a row per window with three paths, and says why 9 deg is skipped.
grep -q '^| 1 | 2 | 3 |' $out/summary.md || { cat $out/summary.md >&2; exit 1; }
grep -q 'run 1 at 9 deg: skip: the run ends at 8' $out/summary.md || { cat $out/summary.md >&2; exit 1; }
expect_eq 4 "$(grep -vc '^seed' $out/paths.tsv)" "(branch rows: 1 window x 4 branches)"
[[ -s $out/figure.png ]]
# Every branch has its eq (4) fit (alpha over the frames after the start); paths.tsv carries
# each branch's alpha as that fit gives it (NA when it did not converge).
"$PY" - $out <<'PYEOF'
import csv, math, os, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "paths.tsv")), delimiter="\t"))
for r in rows:
    fit = os.path.join(out, f"run-{r['seed']}", f"theta-{r['angle_deg']}", r["path"] + ".fit.tsv")
    assert os.path.exists(fit), fit
    data = [l for l in open(fit) if l.strip() and not l.startswith("#")]
    fits = list(csv.DictReader(data, delimiter="\t"))
    assert len(fits) == 1, (fit, fits)  # one window: the frames after the start
    want = fits[0]["alpha"] if fits[0]["converged"] == "1" else "NA"
    got = r["alpha"]
    assert (want == "NA" and got == "NA") or abs(float(want) - float(got)) <= 1e-5 * abs(float(want)), (fit, want, got)
spread = list(csv.DictReader(open(os.path.join(out, "spread.tsv")), delimiter="\t"))
assert "alpha_sd" in spread[0] and "alpha_k0" in spread[0], spread[0].keys()
PYEOF
mk > make2.log 2>&1 || { cat make2.log >&2; exit 1; }
if grep -q 'tilt-cd' make2.log; then echo "branches were made again" >&2; cat make2.log >&2; exit 1; fi
# The tables kept for a commit, and read from there when the study's own are gone.
for f in spread.tsv paths.tsv summary.md; do cmp $out/$f summaries/study/indeterminacy/$f; done
mv $out moved
CDPILE_SUMMARY_ROOT=$PWD/summaries "$PY" - "$CDPILE_SOURCE/pipelines" <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
from cdpile_py.paper import spread_rows
rows = spread_rows("study")
assert rows and rows[0]["seed"] == "1" and rows[0]["angle_deg"] == "2", rows
PYEOF
