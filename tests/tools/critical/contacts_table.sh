# critical --contacts FILE lists every counted contact of every frame with its critical, sliding and slip flags: by hand on a table-made run (contact (0, 1) critical, (1, 2) not), and on a tilted pile the flags add up to the frames table's N, Nc, sliding and slipping, by the rule asked for (--walls); a bad target is refused before the work, with no file left.
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\n0\t1\t0\t1\t0\t0\t1\t0.5\n0\t1\t1\t2\t1\t0\t1\t0\n' > ok.tsv
table-to-run ok.tsv run.h5 1 0.5
critical run.h5 --contacts c.tsv --quiet > /dev/null
"$PY" - "$CDPILE_SOURCE/pipelines" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from cdpile_py.tables import read_product_table
rows = read_product_table("c.tsv", "contacts")
got = [(r["run"], r["frame"], r["i"], r["j"], r["critical"]) for r in rows]
assert got == [("0", "0", "0", "1", "1"), ("0", "0", "1", "2", "0")], got
PY
deposit --grains 60 --width 8 --seed 1 -o pile.h5 --quiet
tilt-cd pile.h5 --rate 0.5 --to 10 --frame-every 5 -o tilt.h5 --quiet
for rule in "" "--walls"; do
  # shellcheck disable=SC2086  # the rule's one option, or none
  critical tilt.h5 $rule --contacts contacts.tsv --force --quiet > frames.tsv
  "$PY" - "$CDPILE_SOURCE/pipelines" <<'PY'
import sys
from collections import Counter
sys.path.insert(0, sys.argv[1])
from cdpile_py.tables import read_product_table
frames = read_product_table("frames.tsv", "frames")
contacts = read_product_table("contacts.tsv", "contacts")
assert len(frames) >= 3 and len(contacts) > 0, (len(frames), len(contacts))
for name, col in (("N", None), ("Nc", "critical"), ("sliding", "sliding"), ("slipping", "slip")):
    per_frame = Counter()
    for c in contacts:
        per_frame[c["frame"]] += 1 if col is None else int(c[col])
    for f in frames:
        assert per_frame[f["frame"]] == int(f[name]), (name, f["frame"], per_frame[f["frame"]], f[name])
PY
done
# A bad target is refused before the runs are read: the same file as -o, standard output twice, an existing file.
expect_fail 2 "critical: --contacts and -o name the same file out.h5 (see 'critical --help')" \
  critical tilt.h5 -o out.h5 --contacts out.h5
expect_fail 2 "critical: --contacts - and the product both on standard output; give -o FILE (see 'critical --help')" \
  critical tilt.h5 --contacts -
expect_fail 1 "critical: contacts.tsv: exists; not overwritten (use --force to replace it)" \
  critical missing.h5 --contacts contacts.tsv -o out.h5
test ! -e out.h5
