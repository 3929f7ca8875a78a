# make -C pipelines stiffness at its smallest (60 disks to 3 degrees, two seeds, k = 1e4 to
# 2 degrees, softer than the default so that nu moves on so small a pile): the other study
# tilts the study's own piles, bit for bit; the table's nu per degree is each side's mean
# over the steps of the runs' own observables, and the difference theirs; the mean
# mobilisation per degree is the frames' histograms' (summaries); a second make, and
# a make after the run files are gone (a new machine with the committed summaries), tilt
# nothing; two ensembles without a common seed are refused in one line.
# ctest: slow, timeout 120
B=$CDPILE_BIN
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" stiffness NAME=t GRAINS=60 WIDTH=10 RATE=0.05 TO=3 \
  FRAME_EVERY_DEG=1 MAP_THETAS=1 RADII=1:1:3 STIFF_KS=1e4 STIFF_TO=2 STIFF_SEEDS="1 2" STUDIES="$PWD/studies" \
  SUMMARY_ROOT="$PWD/summaries" STIFF_DOCS="$PWD/docs" CDPILE_BIN="$B" "$@"; }
mk > make1.log 2>&1 || { cat make1.log >&2; exit 1; }
soft=studies/t-N60-R1.5-mu0.5-rate0.05-pcg
stiff=studies/t-to2-N60-R1.5-mu0.5-rate0.05-pcg-k1e4
for s in 1 2; do
  h5diff --exclude-path /provenance $soft/pile-$s.h5 $stiff/pile-$s.h5 || { echo "pile $s differs between the studies" >&2; exit 1; }
  [[ -s summaries/$(basename $soft)/run-$s.summary.h5 && -s summaries/$(basename $stiff)/run-$s.summary.h5 ]]
done
table=docs/stiffness-$(basename $soft)-k1e4.md
[[ -s $table && -s ${table%.md}.png && -s ${table%.md}.pdf ]]
# Each side's nu per degree, from the run files' own per-step counts (grain-grain contacts).
"$PY" - $soft $stiff $table <<'PYEOF'
import sys, h5py, numpy as np
soft, stiff, table = sys.argv[1:]
def nu(study, s):
    with h5py.File(f"{study}/run-{s}.h5", "r") as r:
        th = np.round(r["observables/tilt_angle/value"][()], 9)
        c = r["observables/critical_grain/value"][()].astype(float)
        n = r["observables/contacts_grain/value"][()].astype(float)
    out = []
    for d in range(2):
        m = ((th > d) & (th <= d + 1) if d else (th <= 1)) & (n > 0)
        out.append((c[m] / n[m]).mean())
    return out
want = {side: np.mean([nu(study, s) for s in (1, 2)], axis=0) for side, study in (("soft", soft), ("stiff", stiff))}
rows = [l.split("|")[1:-1] for l in open(table) if l.startswith("| 0-1 |") or l.startswith("| 1-2 |")]
assert len(rows) == 4, rows  # nu's table, then the mobilisation's
rows, mobilisation_rows = rows[:2], rows[2:]
for d, r in enumerate(rows):
    assert r[1].strip() == "2", r
    got_soft, got_stiff = float(r[2]), float(r[3])
    assert abs(got_soft - want["soft"][d]) < 5e-5 and abs(got_stiff - want["stiff"][d]) < 5e-5, (d, r, want)
    diff = float(r[4].split("±")[0])
    d_want = want["stiff"][d] - want["soft"][d]
    assert d_want != 0 and abs(diff - d_want) <= 5e-3 * abs(d_want), (d, r, want)  # printed to 3 digits
# The mean mobilisation per degree: each frame's histogram of |f_t| / (mu f_n) (20 bins of
# [0, 1]) at its bins' centres, averaged over the degree's frames, then over the seeds.
def mobilisation(study, s):
    name = study.split("/")[-1]
    with h5py.File(f"summaries/{name}/run-{s}.summary.h5", "r") as f:
        t = f["tables/frames"]
        th = np.round(t["theta"][()], 9)
        h = np.array([t[f"mobilisation_{i}"][()] for i in range(20)], float)
    m = ((np.arange(20) + 0.5) / 20) @ h / h.sum(axis=0)
    return [m[((th > d) & (th <= d + 1)) if d else (th <= 1)].mean() for d in range(2)]
for side, study, col in (("soft", soft, 2), ("stiff", stiff, 3)):
    want = np.mean([mobilisation(study, s) for s in (1, 2)], axis=0)
    for d, r in enumerate(mobilisation_rows):
        assert 0 < want[d] < 1 and abs(float(r[col]) - want[d]) < 5e-5, (side, d, r, want)
PYEOF
grep -q '^crossing: ' $table || { cat $table >&2; exit 1; }
# Up to date: nothing is tilted again, with or without the run files.
mk > make2.log 2>&1 || { cat make2.log >&2; exit 1; }
if grep -q 'tilt-cd\|deposit' make2.log; then cat make2.log >&2; exit 1; fi
rm -f $soft/*.h5 $stiff/*.h5
mk > make3.log 2>&1 || { cat make3.log >&2; exit 1; }
if grep -q 'tilt-cd\|deposit' make3.log; then cat make3.log >&2; exit 1; fi
# No seed in both: one line, exit 1.
mkdir -p one two
cp summaries/$(basename $soft)/run-1.summary.h5 one/
cp summaries/$(basename $stiff)/run-2.summary.h5 two/
expect_fail 1 "stiffness.py: no seed in both ensembles" "$PY" "$CDPILE_SOURCE/pipelines/stiffness.py" "a=one" "b=two"
