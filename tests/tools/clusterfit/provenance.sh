# clusterfit --nu keeps the critical product's history beside the correlate input's, each entry marked with the input it came through (HDF5 attribute via, TSV sixth field); without --nu the chain stays linear.
deposit --grains 40 --width 8 --seed 1 -o p.h5 --quiet
tilt-cd p.h5 --rate 1 --to 2 -o run.h5 --quiet
critical run.h5 -o c.h5 --quiet
critical run.h5 --table runs,ensemble --header --quiet > c.tsv
localnu run.h5 --radii 1:1:6 -o l.h5 --quiet
correlate l.h5 -o w.h5 --quiet
clusterfit w.h5 --nu c.h5 -o f.h5 --quiet
# the correlate chain, then critical's, then clusterfit itself, which names both inputs
"$PY" - <<'P'
import h5py
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
with h5py.File("f.h5", "r") as f:
    g = f["provenance"]
    got = [(t(g[k].attrs["tool"]), t(g[k].attrs.get("via", ""))) for k in g]
    last = g[list(g)[-1]].attrs
    inputs, command = t(last["inputs"]), t(last["command_line"])
want = [("deposit", "w.h5"), ("tilt-cd", "w.h5"), ("localnu", "w.h5"), ("correlate", "w.h5"),
        ("deposit", "c.h5"), ("tilt-cd", "c.h5"), ("critical", "c.h5"),
        ("clusterfit", "")]
assert got == want, got
assert inputs == "w.h5 c.h5", inputs
assert command == "clusterfit w.h5 --nu c.h5 -o f.h5 --quiet", command
P
# The critical entry is the one of c.h5, copied as it is (same command line and date).
"$PY" - <<'P'
import h5py
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
with h5py.File("c.h5", "r") as c, h5py.File("f.h5", "r") as f:
    mine = c["provenance"][list(c["provenance"])[-1]].attrs
    copied = [f["provenance"][k].attrs for k in f["provenance"] if t(f["provenance"][k].attrs["tool"]) == "critical"]
    assert len(copied) == 1
    for key in ("tool", "version", "command_line", "inputs", "date"):
        assert copied[0][key] == mine[key], (key, copied[0][key], mine[key])
P
# The same with a TSV critical product, through a pipe, and TSV output.
correlate l.h5 -o - --quiet | clusterfit - --nu c.tsv --quiet > f.tsv
expect_eq "deposit stdin|tilt-cd stdin|localnu stdin|correlate stdin|deposit c.tsv|tilt-cd c.tsv|critical c.tsv|clusterfit " \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %s", n++ ? "|" : "", $1, $6 }' f.tsv)"
expect_eq "stdin c.tsv" "$(awk -F'\t' '/^# provenance: clusterfit/ { print $4 }' f.tsv)"
# Without --nu: one input, its chain as it is, with no marks.
clusterfit w.h5 --nu-c 0.1 --quiet > n.tsv
expect_eq "deposit 5|tilt-cd 5|localnu 5|correlate 5|clusterfit 5" \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %d", n++ ? "|" : "", $1, NF }' n.tsv)"
