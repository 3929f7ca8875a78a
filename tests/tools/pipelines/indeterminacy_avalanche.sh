# theta_c along other solver paths at its smallest (80 disks tilted to their avalanche):
# the branches start from the last frame at or below theta_c - lead, each stops when its
# avalanche is confirmed, avalanche.tsv holds the run and every path, a second make redoes
# nothing, a run without an avalanche is skipped with its reason, and a call with other
# seeds remakes the table for them.
# ctest: slow, timeout 120
B=$CDPILE_BIN
# the engine of the studies made so far (pipelines/Makefile, STUDY_ENGINE)
old=(--solver nsgs --max-substeps 1 --max-sweeps 2000 --tolerance 1e-4)
"$B/deposit" --grains 80 --width 10 --seed 3 --stiffness 0 "${old[@]}" --quiet -o pile.h5
mkdir -p study
"$B/tilt-cd" pile.h5 --rate 0.05 --stiffness 1e5 "${old[@]}" --frame-every-deg 1 --quiet -o study/run-1.h5
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" indeterminacy STUDY="$PWD/study" RATE=0.05 STIFFNESS=1e5 \
  INDETERMINACY_SEEDS=1 INDETERMINACY_TARGETS=avalanche CDPILE_BIN="$B" SUMMARY_ROOT="$PWD/summaries" \
  INDETERMINACY_OPTIONS='AVALANCHE_PATHS="1 2" AVALANCHE_LEAD=2' "$@"; }
mk > make1.log 2>&1 || { cat make1.log >&2; exit 1; }
out=study/indeterminacy
"$PY" - study/run-1.h5 $out <<'PYEOF'
import csv, sys, h5py
run, out = sys.argv[1], sys.argv[2]
with h5py.File(run, "r") as f:
    tc = float(f["results"].attrs["avalanche_angle_deg"])
    frames = f["contacts/tilt_angle"][:]
start = max(a for a in frames if a <= tc - 2 + 1e-9)
rows = list(csv.DictReader(open(f"{out}/avalanche.tsv"), delimiter="\t"))
assert [r["path"] for r in rows] == ["0", "1", "2"], rows
assert abs(float(rows[0]["theta_c_deg"]) - tc) < 1e-9, (rows[0], tc)
for r in rows[1:]:
    assert abs(float(r["from_deg"]) - start) < 1e-9, (r, start)
    with h5py.File(f"{out}/run-1/avalanche/path-{r['path']}.h5", "r") as b:
        res = b["results"].attrs
        assert int(res["avalanche_detected"]) == 1 and res["stop_reason"] in (b"avalanche", "avalanche"), dict(res)
        assert abs(float(r["theta_c_deg"]) - float(res["avalanche_angle_deg"])) < 1e-9
        # no margin: the branch ends where its avalanche is confirmed
        assert abs(float(res["final_angle_deg"]) - float(res["avalanche_angle_deg"]) - 0.2) < 0.05 + 1e-9, dict(res)
PYEOF
grep -q '^| 1 | 3 |' $out/avalanche.md || { cat $out/avalanche.md >&2; exit 1; }
mk > make2.log 2>&1 || { cat make2.log >&2; exit 1; }
if grep -q 'tilt-cd' make2.log; then echo "branches were made again" >&2; cat make2.log >&2; exit 1; fi
# A run that ends before its avalanche is skipped, with its reason in the summary.
"$B/tilt-cd" pile.h5 --rate 0.05 --to 3 --stiffness 1e5 "${old[@]}" --frame-every-deg 1 --quiet -o study/run-2.h5
make --no-print-directory -C "$CDPILE_SOURCE/pipelines/indeterminacy" avalanche STUDY="$PWD/study" SEEDS="1 2" \
  AVALANCHE_PATHS="1 2" CDPILE_BIN="$B" > make3.log 2>&1 || { cat make3.log >&2; exit 1; }
grep -q "^- run 2: skip: the run has no avalanche (it ends at 3 deg)" $out/avalanche.md || { cat $out/avalanche.md >&2; exit 1; }
grep -q '^| 1 | 3 |' $out/avalanche.md || { cat $out/avalanche.md >&2; exit 1; }
# A call with other seeds prints a table of its own seeds, not the last call's.
make --no-print-directory -C "$CDPILE_SOURCE/pipelines/indeterminacy" avalanche STUDY="$PWD/study" SEEDS="1" \
  AVALANCHE_PATHS="1 2" CDPILE_BIN="$B" > make4.log 2>&1 || { cat make4.log >&2; exit 1; }
if grep -q 'run 2' $out/avalanche.md || grep -q 'tilt-cd' make4.log; then cat make4.log $out/avalanche.md >&2; exit 1; fi
grep -q '^| 1 | 3 |' $out/avalanche.md || { cat $out/avalanche.md >&2; exit 1; }
# report.py gives theta_c its systematic error from these paths (all equal here: 0).
"$B/critical" study/run-1.h5 --quiet -o study/critical.h5
"$PY" "$CDPILE_SOURCE/pipelines/report.py" study > report.md 2> report.err || { cat report.err >&2; exit 1; }
grep -q '^| theta_c (deg) | about 20 (19.96) | 25.4 | ± 0 (sd across solver paths, 1 run) |' report.md || { cat report.md >&2; exit 1; }
