# ParaView opens a small run through to-xdmf: File > Open (OpenDataFile, the Xdmf3 reader ParaView picks) loads one point per grain per frame and the network file one segment per contact; the legacy XDMF Reader of the state reads every frame (time steps, grain count, arrays, contact counts, critical flags against the run's own observable); the state renders the disks at their radii, the force network with the critical contacts in red and the last frame's tilt angle (one offscreen image whose pixels are checked), and a localnu map reads back as its nu field.
# ctest: slow, timeout 600
if ! command -v pvpython > /dev/null; then
  echo "skipped: ParaView's Python (pvpython, Debian package python3-paraview) is not installed; scripts/install-deps.sh installs it" >&2
  exit 77
fi
if ! command -v Xvfb > /dev/null; then
  echo "skipped: ParaView renders through X and Xvfb (Debian package xvfb) is not installed; scripts/install-deps.sh installs it" >&2
  exit 77
fi
here="$CDPILE_SOURCE/tests/tools/to-xdmf"
deposit --grains 30 --width 6 --seed 2 --quiet -o pile.h5
tilt-cd pile.h5 --rate 2 --to 6 --frame-every 1 --quiet -o run.h5
to-xdmf run.h5 --quiet
test -s run.xdmf && test -s run.network.xdmf && test -s run.xdmf.hdf5 && test -s run.paraview.py
# docs/analysis.md's map recipe as written, but for its last line (the ParaView window): the
# state it loads is loaded offscreen below
awk '$0 == "```sh paraview-map" {on=1; next} /^```/{on=0} on' "$CDPILE_SOURCE/docs/analysis.md" > map.sh
expect_eq "paraview --state=map.paraview.py" "$(tail -n 1 map.sh)"
head -n -1 map.sh > map_files.sh
bash -euo pipefail map_files.sh 2> map.err
test -s map.xdmf && test -s map.xdmf.hdf5 && test -s map.paraview.py
# what ParaView must find, from the files themselves
"$PY" - <<'PY'
import json, h5py, numpy as np
f = h5py.File("run.h5", "r")
g, c = f["particles/grains"], f["contacts"]
steps = g["position/step"][:]
obs_step, obs_crit = f["observables/critical/step"][:], f["observables/critical/value"][:]
off, cnt = c["offset"][:], c["count"][:]
e = dict(frames=len(steps), times=g["position/time"][:].tolist(), grains=int(g["radius"].shape[0]),
         positions=g["position/value"][:].tolist(), velocities=g["velocity/value"][:].tolist(),
         tilt=c["tilt_angle"][:].tolist(), contacts=cnt.tolist(), radius=g["radius"][:].tolist(),
         fn=[c["fn"][o:o + n].tolist() for o, n in zip(off, cnt)])
# critical contacts by the run's rule, which its observable 'critical' counted at each step
par = f["parameters"].attrs
crit = []
for o, n, s in zip(off, cnt, steps):
    fn, ft, j = c["fn"][o:o + n], c["ft"][o:o + n], c["j"][o:o + n]
    mu = np.where(j < 0, par["mu_wall"], par["mu_grain"])
    crit.append(int(((fn > 0) & (np.abs(ft) >= (1 - par["critical_eps"]) * mu * fn)).sum()))
    k = np.searchsorted(obs_step, s)
    if k < len(obs_step) and obs_step[k] == s:
        assert obs_crit[k] == crit[-1], (s, obs_crit[k], crit[-1])
e["critical"] = crit
# the last frame's contacts, for the picture: the pairs and which are critical
o, n = off[-1], cnt[-1]
fn, ft, j = c["fn"][o:o + n], c["ft"][o:o + n], c["j"][o:o + n]
mu = np.where(j < 0, par["mu_wall"], par["mu_grain"])
e["last_i"], e["last_j"] = c["i"][o:o + n].tolist(), j.tolist()
e["last_critical"] = ((fn > 0) & (np.abs(ft) >= (1 - par["critical_eps"]) * mu * fn)).astype(int).tolist()
e["last_fn"] = fn.tolist()
assert sum(crit) > 0
p = h5py.File("map.h5", "r")
m = p["tables/map"]
defined = m["nu_defined"][:] if "nu_defined" in m else np.ones(m["nu"].shape, bool)
r = p["results"].attrs
e["map"] = dict(nx=int(r["map_nx"]), ny=int(r["map_ny"]), x0=float(m["x"][0]), y0=float(m["y"][0]),
                dx=float(r["map_dx_m"]), nu=[float(v) if d else None for v, d in zip(m["nu"][:], defined)])
e["xdmf"], e["network"] = "run.xdmf", "run.network.xdmf"
json.dump(e, open("expected.json", "w"))
PY
# a private X display for ParaView's offscreen window (-noreset: a server that resets when
# its last client leaves drops the connections that come during the reset)
Xvfb -displayfd 3 -screen 0 640x480x24 -nolisten tcp -noreset 3> display.txt 2> xvfb.log &
xvfb=$!
trap 'kill $xvfb 2> /dev/null || true' EXIT
for _ in $(seq 100); do [[ -s display.txt ]] && break; sleep 0.1; done
[[ -s display.txt ]] || { echo "Xvfb did not start:" >&2; cat xvfb.log >&2; exit 1; }
DISPLAY=":$(cat display.txt)" timeout 300 pvpython "$here/check_paraview.py" expected.json run.paraview.py image.png map.xdmf map.paraview.py > out.txt 2> err.txt || {
  cat out.txt err.txt >&2; exit 1; }
cat out.txt
grep -q '% of pixels drawn' out.txt
grep -q '^File > Open: ' out.txt
grep -q 'critical segments red' out.txt
grep -q '^tilt text: ' out.txt
grep -q 'grain centres drawn' out.txt
grep -q '^nu field: ' out.txt
grep -q '^map state: ' out.txt
