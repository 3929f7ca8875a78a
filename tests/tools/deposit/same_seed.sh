# The same seed gives the same pile file, every dataset and attribute equal to the bit
# (provenance aside: it holds the date); another seed gives another pile.
deposit --grains 80 --width 12 --seed 5 -o a.h5 --quiet
deposit --grains 80 --width 12 --seed 5 -o b.h5 --quiet
h5diff --exclude-path /provenance a.h5 b.h5
deposit --grains 80 --width 12 --seed 6 -o c.h5 --quiet
rc=0; h5diff -q --exclude-path /provenance a.h5 c.h5 > /dev/null || rc=$?
expect_eq 1 "$rc" "(seed 6 should give another pile)"
# The pile records what it is: a settled pile of 80 free grains and its measures.
"$PY" - <<'PY'
import h5py, numpy as np
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
f = h5py.File("a.h5", "r")
assert t(f.attrs["kind"]) == "pile"
p, r = f["parameters"].attrs, f["results"].attrs
assert p["grains"] == 80 and p["seed"] == 5 and p["rough_floor"] == 1
species = f["particles/grains/species"][:]
assert (species == 0).sum() == 80 and (species == 1).sum() == p["floor_grains"] > 0
assert r["settled"] == 1
assert 0.6 < r["packing_fraction"] < 0.9, r["packing_fraction"]
assert 2.0 < r["coordination_number"] < 4.5, r["coordination_number"]
fn = f["contacts/fn"][:]
assert (fn >= 0).all() and r["max_overlap_m"] < 1e-6
PY
