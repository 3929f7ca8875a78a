# pipelines/limit.py at its smallest (60 disks, two seeds, to 2 degrees at k = 1e4): four
# studies of the same piles, at h, every step at h/4 with and without the contact dashpot
# (zeta = 1), and k = 1e5 at h; each row's nu over
# 0-2 degrees is each run's mean of its per-degree nu from the run files' own per-step
# counts, the share at |f_t| / (mu f_n) >= 0.95 the frames' histograms' top bin, the
# kinetic energy the median of the run's steps, each difference the paired one; the step,
# the dashpot and k h_s^2 / m are read from the summaries' parameters, not from the
# folders' names (a summary without the dashpot's parameter, made before it was one, has
# none), and so is the active-set finish (a study finished after N sweeps is its own
# row); the chart is written; a folder whose
# runs were made with different settings, one without a seed in common and one that is
# not there are refused in one line with nothing on stdout; a study tilted to 1 degree is
# refused over 0-2 degrees, left out with --skip-short (and by make limit), and taken over
# the first degree. Studies tilted past the avalanche get theta_c paired too, and make limit finds
# them (NAME-...-k<k> and NAME-<tag>-...).
# ctest: slow, timeout 120
B=$CDPILE_BIN
for s in 1 2; do
  "$B/deposit" --grains 60 --width 10 --seed $s --quiet -o pile-$s.h5
done
tilt() {  # folder seed options...
  local dir=$1 s=$2; shift 2
  mkdir -p runs/$dir sum/$dir
  local to=(--to "${TO:-2}")
  [[ -z ${PAST:-} ]] || to=()  # past the avalanche (tilt-cd's rule)
  "$B/tilt-cd" pile-$s.h5 --rate 0.05 "${to[@]}" --frame-every-deg 1 --quiet "$@" -o runs/$dir/run-$s.h5 2> /dev/null
  (cd runs/$dir && "$B/summarise" run-$s.h5 --radii 1:1:3 --map-theta 1 --quiet -o ../../sum/$dir/run-$s.summary.h5)
}
for s in 1 2; do
  tilt soft $s --stiffness 1e4
  tilt fine $s --stiffness 1e4 --substep-after 1 --max-substeps 4
  tilt damped $s --stiffness 1e4 --damping-ratio 1 --substep-after 1 --max-substeps 4
  tilt stiff $s --stiffness 1e5
  TO=1 tilt short $s --stiffness 1e5
  tilt rigid $s --stiffness 0
  PAST=1 tilt past $s --stiffness 1e4
  PAST=1 tilt past-rigid $s --stiffness 0
  tilt finished $s --stiffness 1e4 --finish-after 50
done
"$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft sum/fine sum/damped sum/stiff --to 2 -o chart.png > table.md 2> err.log \
  || { cat err.log >&2; exit 1; }
[[ -s chart.png && -s chart.pdf ]]
"$PY" - table.md <<'PYEOF'
import sys, h5py, numpy as np
table = sys.argv[1]
def nu(dir, s):
    """each run's mean over its degrees of the per-step critical / contacts (grain-grain)"""
    with h5py.File(f"runs/{dir}/run-{s}.h5", "r") as r:
        th = np.round(r["observables/tilt_angle/value"][()], 9)
        c = r["observables/critical_grain/value"][()].astype(float)
        n = r["observables/contacts_grain/value"][()].astype(float)
    per = []
    for d in range(2):
        m = ((th > d) & (th <= d + 1) if d else (th <= 1)) & (n > 0)
        per.append((c[m] / n[m]).mean())
    return np.mean(per)
lines = [l for l in open(table) if l.startswith("| ") and not l.startswith("| study ")]
assert len(lines) == 12, lines  # nu's table, the share at >= 0.95's, the kinetic energy's
tables = [{l.split("|")[1].strip(): [x.strip() for x in l.split("|")[1:-1]] for l in part}
          for part in (lines[:4], lines[4:8], lines[8:])]
rows, near_rows, quiet_rows = tables
assert set(rows) == set(near_rows) == set(quiet_rows) == {"soft", "fine", "damped", "stiff"}, tables
def near(dir, s):
    """each run's mean over its degrees of the frames' share of counted contacts in the top
    bin of |f_t| / (mu f_n) (20 bins of [0, 1]: >= 0.95)"""
    with h5py.File(f"sum/{dir}/run-{s}.summary.h5", "r") as f:
        t = f["tables/frames"]
        th = np.round(t["theta"][()], 9)
        h = np.array([t[f"mobilisation_{i}"][()] for i in range(20)], float)
    share = h[19] / h.sum(axis=0)
    return np.mean([share[((th > d) & (th <= d + 1)) if d else (th <= 1)].mean() for d in range(2)])
def quiet(dir, s):
    """the median over the run's steps to 2 degrees of its kinetic energy"""
    with h5py.File(f"runs/{dir}/run-{s}.h5", "r") as r:
        th = np.round(r["observables/tilt_angle/value"][()], 9)
        return np.median(r["observables/kinetic_energy/value"][()][th <= 2])
# k g h_s^2 / D: h = 1e-4 s, D = 1e-3 m (deposit's defaults), h_s = h/4 where every step split
want_step = {"soft": ("1e4", "0", "h (split after 1000 sweeps, to h/64)", 1e4 * 9.81 * 1e-8 / 1e-3),
             "fine": ("1e4", "0", "h/4 (every step)", 1e4 * 9.81 * 1e-8 / 16 / 1e-3),
             "damped": ("1e4", "1", "h/4 (every step)", 1e4 * 9.81 * 1e-8 / 16 / 1e-3),
             "stiff": ("1e5", "0", "h (split after 1000 sweeps, to h/64)", 1e5 * 9.81 * 1e-8 / 1e-3)}
ref = np.array([nu("soft", s) for s in (1, 2)])
ref_near = np.array([near("soft", s) for s in (1, 2)])
ref_quiet = np.array([quiet("soft", s) for s in (1, 2)])
for name, (k, zeta, step, khm) in want_step.items():
    r = rows[name]
    assert r[1] == k and r[2] == zeta and r[3] == step, r
    assert abs(float(r[4]) - khm) <= 1e-3 * khm, (r, khm)
    assert r[5] == "2", r
    for quantity, r, ref_q in ((nu, rows[name], ref), (near, near_rows[name], ref_near),
                               (quiet, quiet_rows[name], ref_quiet)):
        assert r[1:6] == rows[name][1:6], (r, rows[name])
        got = np.array([quantity(name, s) for s in (1, 2)])
        tol = 5e-5 if quantity is not quiet else 5e-3 * ref_q.mean()  # printed to 4 decimals, or 3 digits
        assert abs(float(r[6]) - ref_q.mean()) < tol and abs(float(r[7]) - got.mean()) < tol, (r, ref_q, got)
        if name == "soft":
            assert r[8] == "", r
            continue
        d = (got - ref_q).mean()
        assert d != 0 and abs(float(r[8].split("±")[0]) - d) <= 5e-3 * abs(d), (r, d)  # printed to 3 digits
PYEOF
# A summary made before the dashpot was a parameter (without run_contact_damping_ratio) had none.
mkdir -p earlier && cp sum/damped/* earlier/
"$PY" - earlier/run-*.summary.h5 <<'PYEOF'
import sys, h5py
for path in sys.argv[1:]:
    with h5py.File(path, "r+") as f:
        assert f["parameters"].attrs["run_contact_damping_ratio"] == 1.0
        del f["parameters"].attrs["run_contact_damping_ratio"]
        del f["parameters"].attrs["run_finish_after"]
PYEOF
"$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft earlier --to 2 > earlier.md
grep -q "^| earlier | 1e4 | 0 | h/4 (every step) |" earlier.md || { cat earlier.md >&2; exit 1; }
# A study finished by the active set is a setting of its own, named by its step.
"$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft sum/finished --to 2 > finished.md
grep -q "^| finished | 1e4 | 0 | h (finished after 50 sweeps, split after 1000 sweeps, to h/64) | .* | 2 |" finished.md \
  || { cat finished.md >&2; exit 1; }
# Refused in one line, nothing on stdout: mixed settings, no common seed, no folder.
mkdir -p mixed one
cp sum/soft/run-1.summary.h5 mixed/ && cp sum/stiff/run-2.summary.h5 mixed/
cp sum/fine/run-1.summary.h5 one/run-3.summary.h5
expect_fail 1 "limit.py: mixed: run-1.summary.h5 and run-2.summary.h5 were made with different settings (k, h, dashpot, sub-steps or finish)" \
  "$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft mixed
expect_fail 1 "limit.py: one: no seed in common with the reference" "$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft one --to 2
expect_fail 1 "limit.py: nothing: not a folder of summaries" "$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft nothing --to 2
# A study tilted to 1 degree has no nu over 0-2: refused, or left out with --skip-short
expect_fail 1 "limit.py: sum/short: run-1 has 1 of the 2 degrees: it stops before --to 2" \
  "$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft sum/short --to 2
expect_fail 1 "limit.py: no study reaches --to 2 beside the reference (sum/short: run-1 has 1 of the 2 degrees)" \
  "$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft sum/short --to 2 --skip-short
"$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft sum/short sum/fine sum/damped sum/stiff --to 2 --skip-short > skip.md 2> skip.err
[[ "$(cat skip.err)" == "limit.py: left out sum/short: run-1 has 1 of the 2 degrees" ]] || { cat skip.err >&2; exit 1; }
cmp skip.md table.md
# rigid contacts: the row last, k h_s^2 / m infinite; the chart drawn (a level across it)
"$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft sum/rigid sum/stiff --to 2 -o rigid.png > rigid.md
[[ -s rigid.png && -s rigid.pdf ]]
[[ "$(grep '^| ' rigid.md | sed -n 4p | cut -d'|' -f2-6)" == " rigid | rigid | 0 | h | inf " ]] || { cat rigid.md >&2; exit 1; }
# over the first degree it is a study like the others
"$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/soft sum/short --to 1 > first.md
grep -q "^| short | 1e5 | 0 | h (split after 1000 sweeps, to h/64) |" first.md || { cat first.md >&2; exit 1; }
# Studies tilted past the avalanche: theta_c paired as well (the summaries' angle by the
# rule), a study tilted to 2 degrees left out of that table only; with a reference tilted to 2
# degrees there is no theta_c table (the 12 rows above).
"$PY" "$CDPILE_SOURCE/pipelines/limit.py" sum/past sum/soft sum/past-rigid --to 2 > past.md
"$PY" - past.md <<'PYEOF'
import sys, h5py, numpy as np
lines = [l for l in open(sys.argv[1]) if l.startswith("| ") and not l.startswith("| study ")]
assert len(lines) == 3 * 3 + 2, lines  # three studies in three tables, two in theta_c's
rows = [[x.strip() for x in l.split("|")[1:-1]] for l in lines[9:]]
assert [r[0] for r in rows] == ["past", "past-rigid"], rows
def theta_c(dir, s):
    with h5py.File(f"sum/{dir}/run-{s}.summary.h5", "r") as f:
        a = f["results"].attrs
        assert a["loading_theta_c_from"] in (b"rule", "rule"), dict(a)
        return float(a["loading_theta_c_deg"])
ref = np.array([theta_c("past", s) for s in (1, 2)])
rig = np.array([theta_c("past-rigid", s) for s in (1, 2)])
d = rig - ref
assert rows[1][1] == "rigid" and rows[1][5] == "2", rows
assert abs(float(rows[1][6]) - ref.mean()) < 5e-3 and abs(float(rows[1][7]) - rig.mean()) < 5e-3, (rows, ref, rig)
def half_last_digit(text):
    """the rounding of a printed number: half a unit of its last digit"""
    text = text.strip()
    return 0.5 * 10.0 ** -(len(text.split(".")[1]) if "." in text else 0) + 1e-12
shown_d, shown_se = rows[1][8].split("±")
assert abs(float(shown_d) - d.mean()) <= half_last_digit(shown_d), (rows, d)
se = d.std(ddof=1) / np.sqrt(2)
assert abs(float(shown_se) - se) <= half_last_digit(shown_se), (rows, se)
PYEOF
# make limit: the studies of the study's piles found by their names under SUMMARY_ROOT (a
# study without a summary yet, one of another preparation and one tilted to 1 degree left
# out), the same rows.
base=N60-R1.5-mu0.5-rate0.05-pcg
mkdir -p root/t-$base-k1e4 root/t-to2-h4-$base-k1e4 root/t-to2-z1-h4-$base-k1e4 root/t-to2-$base-k1e5 root/t-to2-$base-k1e9 root/t-to2-$base-mudep0.1-k1e5
cp sum/soft/* root/t-$base-k1e4/ && cp sum/fine/* root/t-to2-h4-$base-k1e4/ && cp sum/stiff/* root/t-to2-$base-k1e5/
cp sum/damped/* root/t-to2-z1-h4-$base-k1e4/
cp sum/fine/* root/t-to2-$base-mudep0.1-k1e5/
mkdir -p root/t-to1-$base-k1e5 && cp sum/short/* root/t-to1-$base-k1e5/
# tilted past the avalanche: at another k (NAME-...-k<k>) and tagged at the study's
# (NAME-<tag>-...), both found; of another preparation, not
mkdir -p root/t-$base-k0 root/t-z1-$base root/t-$base-mudep0.1-k0
cp sum/past-rigid/* root/t-$base-k0/ && cp sum/past-rigid/* root/t-$base-mudep0.1-k0/ && cp sum/past/* root/t-z1-$base/
make -s --no-print-directory -C "$CDPILE_SOURCE/pipelines" limit NAME=t GRAINS=60 WIDTH=10 RATE=0.05 STIFFNESS=1e4 \
  LIMIT_TO=2 SUMMARY_ROOT="$PWD/root" STIFF_DOCS="$PWD/docs" CDPILE_BIN="$B" > make.md 2> make.err || { cat make.err >&2; exit 1; }
cmp make.md docs/limit-t-$base-k1e4-to2.md
[[ -s docs/limit-t-$base-k1e4-to2.png && -s docs/limit-t-$base-k1e4-to2.pdf ]]
diff <(grep '^| ' table.md | grep -v '^| study ' | cut -d'|' -f3-) \
  <(grep '^| ' make.md | grep -v -e '^| study ' -e "^| t-$base-k0 |" -e "^| t-z1-$base |" | cut -d'|' -f3-) || { cat make.md >&2; exit 1; }
[[ $(grep -c "^| t-$base-k0 | rigid |" make.md) == 3 && $(grep -c "^| t-z1-$base | 1e4 |" make.md) == 3 ]] || { cat make.md >&2; exit 1; }
grep -q "^| t-to2-h4-$base-k1e4 | 1e4 | 0 | h/4 (every step) |" make.md || { cat make.md >&2; exit 1; }
# the table's name: -to<LIMIT_TO> beside the study's name, none at the default 10
for to in 10 1; do
  make -n -s --no-print-directory -C "$CDPILE_SOURCE/pipelines" limit NAME=t GRAINS=60 WIDTH=10 RATE=0.05 STIFFNESS=1e4 \
    LIMIT_TO=$to SUMMARY_ROOT="$PWD/root" STIFF_DOCS="$PWD/docs" | grep -o "out=[^ ]*" > dry-$to.txt
done
[[ "$(cat dry-10.txt)" == "out=$PWD/docs/limit-t-$base-k1e4;" && "$(cat dry-1.txt)" == "out=$PWD/docs/limit-t-$base-k1e4-to1;" ]] || { cat dry-10.txt dry-1.txt >&2; exit 1; }
# no such study: make's one line (then make's own), nothing on stdout
if make -s --no-print-directory -C "$CDPILE_SOURCE/pipelines" limit NAME=u GRAINS=60 WIDTH=10 RATE=0.05 STIFFNESS=1e4 \
  LIMIT_TO=2 SUMMARY_ROOT="$PWD/root" STIFF_DOCS="$PWD/docs" > none.md 2> none.err; then echo "limit made a table of nothing" >&2; exit 1; fi
grep -qx "pipelines: limit: no study of u-$base-k1e4's piles tilted to 2 degrees in $PWD/root" none.err || { cat none.err >&2; exit 1; }
[[ ! -s none.md ]]
# The chart draws one point per setting: of two rigid studies at h (to 2 degrees and past the
# avalanche, the same runs' first degrees) the one with more pairs.
"$PY" - "$CDPILE_SOURCE/pipelines" <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
from limit import one_per_setting, settings
rigid, past = settings("sum/rigid"), settings("sum/past-rigid")
stiff = settings("sum/stiff")
got = one_per_setting([(rigid, 1.0, 0.1, 1), (past, 2.0, 0.2, 2), (stiff, 3.0, 0.3, 1)])
assert got == [(past, 2.0, 0.2), (stiff, 3.0, 0.3)], got
# the same rigid study split by the rescue (to h/64) is another setting, drawn beside it
split = dict(past, n=64)
got = one_per_setting([(rigid, 1.0, 0.1, 1), (past, 2.0, 0.2, 2), (split, 4.0, 0.4, 1)])
assert got == [(past, 2.0, 0.2), (split, 4.0, 0.4)], got
PYEOF
