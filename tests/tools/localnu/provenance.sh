# localnu --nu reads a critical product as an input like the runs: its history is kept after the runs', each entry marked with the input it came through (HDF5 attribute via, TSV sixth field).
deposit --grains 40 --width 8 --seed 1 -o p.h5 --quiet
tilt-cd p.h5 --rate 1 --to 2 -o run.h5 --quiet
# a 2-degree run has no fitted envelope: give its product a nu_c, as a longer ensemble would
critical run.h5 --table runs --header --quiet | sed '/^# kind: /a # result nu_c = 0.1' > c.tsv
localnu run.h5 --nu c.tsv --radii 1,2 --table frames --header --quiet > l.tsv
expect_eq "deposit run.h5|tilt-cd run.h5|deposit c.tsv|tilt-cd c.tsv|critical c.tsv|localnu " \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %s", n++ ? "|" : "", $1, $6 }' l.tsv)"
expect_eq "run.h5 c.tsv" "$(awk -F'\t' '/^# provenance: localnu/ { print $4 }' l.tsv)"
expect_eq "c.tsv" "$(sed -n 's/^# parameter map_nu_c_from = //p' l.tsv)"
# HDF5 output, passed on by correlate
localnu run.h5 --nu c.tsv --radii 1,2 -o - --quiet | correlate - -o w.h5 --quiet
"$PY" - <<'P'
import h5py
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
with h5py.File("w.h5", "r") as f:
    g = f["provenance"]
    got = [(t(g[k].attrs["tool"]), t(g[k].attrs.get("via", ""))) for k in g]
want = [("deposit", "run.h5"), ("tilt-cd", "run.h5"), ("deposit", "c.tsv"), ("tilt-cd", "c.tsv"),
        ("critical", "c.tsv"), ("localnu", ""), ("correlate", "")]
assert got == want, got
P
# Without --nu: one run, its chain as it is, with no marks.
localnu run.h5 --radii 1,2 --table frames --header --quiet > n.tsv
expect_eq "deposit 5|tilt-cd 5|localnu 5" \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %d", n++ ? "|" : "", $1, NF }' n.tsv)"
