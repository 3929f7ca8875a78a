# to-xdmf writes, beside its output, an XDMF file naming the data by its path relative to the XDMF, a small HDF5 file of derived arrays (critical flags by the run's rule, per-grain nu) and a ParaView state; it refuses standard input, an existing output without --force, and files it cannot show.
deposit --grains 20 --width 5 --seed 4 --quiet -o pile.h5
tilt-cd pile.h5 --rate 2 --to 4 --frame-every 1 --quiet -o run.h5
mkdir views
to-xdmf run.h5 -o views/run.xdmf --nu-radius 2 --quiet
for f in views/run.xdmf views/run.xdmf.hdf5 views/run.paraview.py; do test -s "$f"; done
"$PY" - <<'PY'
import xml.etree.ElementTree as ET, h5py, numpy as np
x = ET.parse("views/run.xdmf").getroot()
grids = {g.get("Name"): g for g in x.find("Domain").findall("Grid")}
assert sorted(grids) == ["contacts", "grains", "walls"], sorted(grids)
f = h5py.File("run.h5", "r")
F = f["particles/grains/position/step"].shape[0]
assert len(grids["grains"].findall("Grid")) == F and len(grids["contacts"].findall("Grid")) == F
refs = {e.text.split(":")[0] for e in x.iter("DataItem") if e.get("Format") == "HDF"}
assert refs == {"../run.h5", "run.xdmf.hdf5"}, refs
names = [a.get("Name") for a in grids["grains"].find("Grid").findall("Attribute")]
assert names == ["radius", "species", "mass", "velocity", "angular_velocity", "orientation", "nu", "tilt_angle", "step"], names
# the derived file: critical flags by the run's rule, nu in [0, 1] or NaN
s = h5py.File("views/run.xdmf.hdf5", "r")
c, p = f["contacts"], f["parameters"].attrs
mu = np.where(c["j"][:] < 0, p["mu_wall"], p["mu_grain"])
want = (c["fn"][:] > 0) & (np.abs(c["ft"][:]) >= (1 - p["critical_eps"]) * mu * c["fn"][:])
assert (s["contacts/critical"][:] == want).all()
nu = s["grains/nu"][:]
assert nu.shape == f["particles/grains/position/value"].shape[:2]
assert np.nanmin(nu) >= 0 and np.nanmax(nu) <= 1
PY
# not from standard input, not over an existing file, not a product it cannot show
expect_fail 2 "to-xdmf: the input must be a file: an XDMF file refers to its data by file name (see 'to-xdmf --help')" \
  to-xdmf - < run.h5
expect_fail 1 "to-xdmf: views/run.xdmf: exists; not overwritten (use --force to replace it)" \
  to-xdmf run.h5 -o views/run.xdmf
to-xdmf run.h5 -o views/run.xdmf --force --quiet
critical run.h5 --quiet -o crit.h5
expect_fail 1 "to-xdmf: crit.h5: /: is a 'critical' product; to-xdmf shows piles, runs and localnu maps" to-xdmf crit.h5
test ! -e crit.xdmf
localnu run.h5 --quiet --table frames > nu.tsv
expect_fail 1 "to-xdmf: nu.tsv: not an HDF5 file (no HDF5 signature)" to-xdmf nu.tsv
