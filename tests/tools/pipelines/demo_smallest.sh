# The study pipeline at its smallest (2 runs of 80 disks): every tool and figure; the products made from the runs' summaries are those of the runs; a second make recomputes nothing; a removed product alone is remade; on a new machine (the study's folder gone, the summaries kept) no run is made again, and a new seed makes only its own run.
# ctest: slow, timeout 300
mk() { make --no-print-directory -C "$CDPILE_SOURCE/pipelines" study NAME=tiny GRAINS=80 WIDTH=12 RATE=0.05 \
  FRAME_EVERY_DEG=1 SEEDS="1 2" MAP_THETAS="5 10" STUDIES="$PWD/studies" SUMMARY_ROOT="$PWD/summaries" CDPILE_BIN="$CDPILE_BIN" "$@"; }
mk > make1.log 2>&1 || { cat make1.log >&2; exit 1; }
study=$PWD/studies/tiny-N80-R1.5-mu0.5-rate0.05-pcg
sums=$PWD/summaries/tiny-N80-R1.5-mu0.5-rate0.05-pcg
for s in 1 2; do [[ -s $sums/run-$s.summary.h5 ]] || { echo "missing run-$s.summary.h5" >&2; exit 1; }; done
grep -qx 'ENGINE=default' "$sums/variables.txt"
# The study's products, made from the summaries, are the runs' own: critical and localnu
# again on the run files (named as the summaries name them), then correlate, clusterfit.
same() { diff <(grep -v '^# \(tool\|command\|input\|provenance\):' "$1") <(grep -v '^# \(tool\|command\|input\|provenance\):' "$2"); }
(cd "$study" && critical run-1.h5 run-2.h5 --quiet -o "$OLDPWD/c-runs.h5" 2> /dev/null && localnu run-1.h5 run-2.h5 --radii 1:1:40 --quiet -o "$OLDPWD/l-runs.h5")
h5diff --exclude-path /provenance c-runs.h5 "$study/critical.h5"
h5diff --exclude-path /provenance l-runs.h5 "$study/localnu.h5"
correlate l-runs.h5 --quiet -o co-runs.h5
h5diff --exclude-path /provenance co-runs.h5 "$study/correlate.h5"
same <(clusterfit co-runs.h5 --nu c-runs.h5 --quiet --digits 0 2> /dev/null) <(clusterfit "$study/correlate.h5" --nu "$study/critical.h5" --quiet --digits 0 2> /dev/null)
for f in pile-1 pile-2 run-1 run-2 critical localnu correlate clusterfit map-05 map-10; do
  [[ -s $study/$f.h5 ]] || { echo "missing $f.h5" >&2; exit 1; }
done
# every run and map has its ParaView description (to-xdmf)
for f in run-1 run-2 map-05 map-10; do
  for ext in xdmf xdmf.hdf5 paraview.py; do [[ -s $study/$f.$ext ]] || { echo "missing $f.$ext" >&2; exit 1; }; done
done
for fig in fig1a_nu fig1b_ek fig1c_envelope fig2_events fig3_pdf fig4a_nubar fig5_maps fig7_mobilisation; do
  for ext in png pdf; do [[ -s $study/figures/$fig.$ext ]] || { echo "missing $fig.$ext" >&2; exit 1; }; done
done
# the pile itself at three angles, from the first run (pipelines/pile.py)
[[ -s $study/figures/pile.png ]] || { echo "missing pile.png" >&2; exit 1; }
grep -q "figures/pile.png (frames \[0, [0-9]*, [0-9]*\] of run-1.h5)" make1.log || { cat make1.log >&2; exit 1; }
# Fig 6 needs nu_c: drawn, or not drawn with its reason written instead (never empty axes).
if [[ -e $study/figures/fig6_rc.txt ]]; then
  grep -q '^Fig 6 is not drawn: r_c not computed: no nu_c' "$study/figures/fig6_rc.txt"
  [[ ! -e $study/figures/fig6_rc.png ]] || { echo "fig6 drawn and said not drawn" >&2; exit 1; }
else
  for ext in png pdf; do [[ -s $study/figures/fig6_rc.$ext ]] || { echo "missing fig6_rc.$ext" >&2; exit 1; }; done
fi
grep -q '^| theta_c (deg) | about 20 (19.96) | ' "$study/report.md"
# Every row has a number or a reason: no bare n/a, and every "none" says why.
if grep -q 'n/a' "$study/report.md"; then cat "$study/report.md" >&2; exit 1; fi
if grep -E '\| none \|' "$study/report.md"; then echo "a none without its reason" >&2; exit 1; fi
# and what the runs cost, from the CPU their deposits and tilts recorded (cpu_s)
grep -Eq '^Cost: [0-9.e+-]+ s of CPU for the 2 of 2 runs that record it' "$study/report.md" || { cat "$study/report.md" >&2; exit 1; }
"$PY" - "$study" <<'PY'
import h5py, sys
s = sys.argv[1]
c = h5py.File(f"{s}/critical.h5", "r")
assert c["results"].attrs["runs"] == 2
runs = c["tables/runs"]
assert list(runs["grains"][()]) == [80, 80], runs["grains"][()]
# the make variables reached the tools, and critical reports each run's own detection
for k in (1, 2):
    r = h5py.File(f"{s}/run-{k}.h5", "r")
    p = r["parameters"].attrs
    assert (p["tilt_rate_deg_per_step"], p["grains"], p["box_width_D"], p["seed"]) == (0.05, 80, 12.0, k), dict(p)
    assert runs["theta_c_recorded"][k - 1] == r["results"].attrs["avalanche_angle_deg"]
m = h5py.File(f"{s}/map-10.h5", "r")
assert abs(m["results"].attrs["map_theta_deg"] - 10) <= 1.0, m["results"].attrs["map_theta_deg"]
PY
# Up to date: nothing runs again.
mk > make2.log 2>&1
if grep -q "$CDPILE_BIN/" make2.log; then echo "second make ran a tool:" >&2; cat make2.log >&2; exit 1; fi
# A removed product is remade, and only what depends on it.
rm "$study/correlate.h5"
mk > make3.log 2>&1
grep -q "$CDPILE_BIN/correlate" make3.log
grep -q "$CDPILE_BIN/clusterfit" make3.log
if grep -q -e "$CDPILE_BIN/tilt-cd" -e "$CDPILE_BIN/deposit" make3.log; then echo "runs were remade" >&2; exit 1; fi
# The reproduction table of the study: a verdict for every number the paper gives.
"$PY" "$CDPILE_SOURCE/pipelines/reproduction.py" "$study=tiny" > repro.md
grep -q '^| quantity | paper | tiny (2 runs of 80 grains) | systematic | verdict |' repro.md
grep -Eq '^\| theta_c \(deg\) \| about 20 \(19.96\) \| [0-9.]+ ± [0-9.]+ \| not measured: `make -C pipelines indeterminacy` \(its avalanche target\) \| (reproduced|not reproduced) \|$' repro.md \
  || { cat repro.md >&2; exit 1; }
grep -Eq '^\| nu_c, every state \| about 0.08 \| .* \| (reproduced|within the systematic error|not reproduced|not determined) \|$' repro.md
# nu_c against the end of the envelope's fit: one critical product per end, recorded in it, and one table row each.
mk envelope-ends ENVELOPE_ENDS="4 8" > make4.log 2>&1 || { cat make4.log >&2; exit 1; }
for e in 4 8; do
  "$PY" -c 'import h5py, sys; p = h5py.File(sys.argv[1], "r")["parameters"].attrs; assert p["envelope_fit_to_deg"] == float(sys.argv[2]), dict(p)' \
    "$study/envelope-ends/critical-to$e.h5" "$e"
done
grep -q '^| fit up to (deg) | every state | static states | contacts at rest |$' "$study/envelope-ends/ends.md"
expect_eq "windows every run reaches|4|8" "$(awk -F' [|] ' '/^[|] [^f-]/ { sub(/^[|] /, "", $1); printf "%s%s", n++ ? "|" : "", $1 }' "$study/envelope-ends/ends.md")"
# every cell is a number or a reason
if grep -E '\| none \|' "$study/envelope-ends/ends.md"; then echo "a none without its reason" >&2; exit 1; fi
# A study not analysed yet gets its column saying so; the table of the others is still made.
"$PY" "$CDPILE_SOURCE/pipelines/reproduction.py" "$study=tiny" "$PWD/not-made=other" > repro2.md
grep -q '^| quantity | paper | tiny (2 runs of 80 grains) | systematic | verdict | other (not analysed) | systematic | verdict |$' repro2.md
grep -Eq "^\| theta_c \(deg\) \| .* \| not analysed yet: no critical.h5 in not-made \|  \| not determined \|$" repro2.md \
  || { cat repro2.md >&2; exit 1; }
# none analysed: one line, non-zero exit
if "$PY" "$CDPILE_SOURCE/pipelines/reproduction.py" "$PWD/not-made" > /dev/null 2> err.txt; then exit 1; fi
expect_eq "reproduction.py: no study has been analysed: not analysed yet: no critical.h5 in not-made" "$(cat err.txt)"
# nu_c per step at another eps: the piles tilted again to EPS_STEPS_TO with that eps (the same trajectory to the bit), read per step beside the study's runs.
mk eps-steps EPS_STEPS="0.2" EPS_STEPS_TO=6 EPS_STEPS_FIT=5 > make5.log 2>&1 || { cat make5.log >&2; exit 1; }
d=$study/eps-steps
"$PY" - "$study" "$d" <<'PY'
import h5py, numpy as np, sys
s, d = sys.argv[1:]
for k in (1, 2):
    a, b = h5py.File(f"{d}/eps0.2/run-{k}.h5", "r"), h5py.File(f"{s}/run-{k}.h5", "r")
    assert a["parameters"].attrs["critical_eps"] == 0.2, dict(a["parameters"].attrs)
    pa, pb = a["particles/grains/position"], b["particles/grains/position"]
    last = int(pa["step"][-1]); j = list(pb["step"][()]).index(last)
    assert np.array_equal(pa["value"][-1], pb["value"][j]), "the trajectory moved with eps"
    # a looser test counts at least as many critical contacts, step by step
    ca, cb = a["observables/critical/value"][()], b["observables/critical/value"][()]
    n = min(len(ca), len(cb)); assert np.all(ca[:n] >= cb[:n]) and np.any(ca[:n] > cb[:n])
for e, series in (("0.2", b"steps"), ("1e-3", b"steps")):
    p = h5py.File(f"{d}/critical-eps{e}.h5", "r")["parameters"].attrs
    assert (p["eps"], p["series"], p["envelope_fit_to_deg"]) == (float(e), series, 5.0), dict(p)
PY
expect_eq "0.001 (steps)|0.2 (steps)" "$(awk -F' [|] ' '/^[|] [0-9]/ { sub(/^[|] /, "", $1); printf "%s%s", n++ ? "|" : "", $1 }' "$d/eps.md")"
# A new machine: the study's folder (piles, runs, products) gone, the summaries kept (as
# committed): the study is made again from them, no run with it, the same products.
cp "$study/critical.h5" critical-before.h5
rm -rf studies
mk > make6.log 2>&1 || { cat make6.log >&2; exit 1; }
if grep -q -e "$CDPILE_BIN/tilt-cd" -e "$CDPILE_BIN/deposit" -e "$CDPILE_BIN/summarise" make6.log; then echo "a run was remade from committed summaries:" >&2; cat make6.log >&2; exit 1; fi
h5diff --exclude-path /provenance critical-before.h5 "$study/critical.h5"
[[ -s $study/figures/fig1a_nu.png && -s $study/map-05.h5 && -s $study/report.md ]]
# ... and a new seed makes only its own pile, run and summary; the analysis follows it.
mk SEEDS="1 2 3" > make7.log 2>&1 || { cat make7.log >&2; exit 1; }
expect_eq "1 1 1" "$(grep -c "$CDPILE_BIN/deposit" make7.log) $(grep -c "$CDPILE_BIN/tilt-cd" make7.log) $(grep -c "$CDPILE_BIN/summarise" make7.log)"
grep -q "pile-3.h5" make7.log
grep -q "pipelines: the analysis of tiny-N80-R1.5-mu0.5-rate0.05-pcg is now of the seeds 1 2 3 (was 1 2)" make7.log
"$PY" -c 'import h5py, sys; assert h5py.File(sys.argv[1], "r")["results"].attrs["runs"] == 3' "$study/critical.h5"
