# A product of several runs keeps every run's history, each entry marked with the run it came through (HDF5 attribute via, TSV sixth field).
deposit --grains 40 --width 8 --seed 1 -o p1.h5 --quiet
deposit --grains 40 --width 8 --seed 2 -o p2.h5 --quiet
tilt-cd p1.h5 --rate 1 --to 2 -o run1.h5 --quiet
tilt-cd p2.h5 --rate 1 --to 2 -o run2.h5 --quiet
critical run1.h5 run2.h5 -o c.h5 --quiet
# deposit and tilt-cd of run 1, then of run 2, then critical itself
"$PY" - <<'P'
import h5py
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
with h5py.File("c.h5", "r") as f:
    g = f["provenance"]
    got = [(t(g[k].attrs["tool"]), t(g[k].attrs.get("via", "")), t(g[k].attrs["command_line"])) for k in g]
want = [("deposit", "run1.h5", "deposit --grains 40 --width 8 --seed 1 -o p1.h5 --quiet"),
        ("tilt-cd", "run1.h5", "tilt-cd p1.h5 --rate 1 --to 2 -o run1.h5 --quiet"),
        ("deposit", "run2.h5", "deposit --grains 40 --width 8 --seed 2 -o p2.h5 --quiet"),
        ("tilt-cd", "run2.h5", "tilt-cd p2.h5 --rate 1 --to 2 -o run2.h5 --quiet"),
        ("critical", "", "critical run1.h5 run2.h5 -o c.h5 --quiet")]
assert got == want, got
P
# The same as TSV: the marked entries have a sixth field.
critical run1.h5 run2.h5 --table runs --header --quiet > c.tsv
expect_eq "deposit run1.h5|tilt-cd run1.h5|deposit run2.h5|tilt-cd run2.h5|critical " \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %s", n++ ? "|" : "", $1, $6 }' c.tsv)"
# One run: its chain as it is, with no marks.
critical run1.h5 --table runs --header --quiet > one.tsv
expect_eq "deposit 5|tilt-cd 5|critical 5" \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %d", n++ ? "|" : "", $1, NF }' one.tsv)"
# localnu keeps them too, and correlate passes the marks on.
localnu run1.h5 run2.h5 -o - --quiet | correlate - --table windows --header > w.tsv
expect_eq "deposit run1.h5|tilt-cd run1.h5|deposit run2.h5|tilt-cd run2.h5|localnu |correlate " \
  "$(awk -F'\t' '/^# provenance: / { sub(/^# provenance: /, ""); printf "%s%s %s", n++ ? "|" : "", $1, $6 }' w.tsv)"
