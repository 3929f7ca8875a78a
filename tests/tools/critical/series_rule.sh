# --series auto uses the run's recorded per-step critical count only when the rule asked for (eps, mu, walls, floor grains) is the one it was recorded with, else the frames, with a note; an explicit --series steps with another rule is a usage error.
deposit --grains 60 --width 8 --seed 1 -o pile.h5 --quiet
tilt-cd pile.h5 --rate 0.5 --to 10 --frame-every 4 -o run.h5 --quiet   # critical_eps 1e-3, mu 0.5
# max of a column of a table (NA left out)
col_max() { awk -F'\t' -v t="$2" -v c="$3" '/^# table: /{cur = substr($0, 10); h = 0; next} /^#/ || !NF {next}
  cur == t && !h {for (i = 1; i <= NF; i++) if ($i == c) k = i; h = 1; next}
  cur == t && $k != "NA" {if (m == "" || $k + 0 > m + 0) m = $k} END {print m}' "$1"; }
note="run.h5 recorded its per-step critical count with another rule"

# The run's own rule (given or by default): the per-step series.
for opts in "" "--eps 0.001 --mu 0.5" "--walls"; do
  critical run.h5 $opts --no-cut --quiet > same.tsv
  expect_eq steps "$(sed -n 's/^# parameter series = //p' same.tsv)" "($opts)"
  expect_eq "" "$(grep "$note" same.tsv || true)" "(note with '$opts')"
  expect_eq "$(col_max same.tsv steps nu)" "$(tsv_value same.tsv runs nu_max 1)" "(nu_max with '$opts')"
done

# Another eps, mu, mu_wall with walls, or floor grains counted as grains: the frames, and the
# per-step Nc, nu and lambda are NA rather than the recorded rule's.
for opts in "--eps 0.2" "--mu 0.3" "--walls --mu-wall 0.2" "--floor-grains grain"; do
  critical run.h5 $opts --no-cut --quiet > other.tsv
  expect_eq frames "$(sed -n 's/^# parameter series = //p' other.tsv)" "($opts)"
  grep -q "^# note: $note (" other.tsv
  expect_eq "$(col_max other.tsv frames nu)" "$(tsv_value other.tsv runs nu_max 1)" "(nu_max with '$opts')"
  expect_eq "" "$(col_max other.tsv steps Nc)$(col_max other.tsv steps nu)$(col_max other.tsv steps lambda)" "(per-step Nc with '$opts')"
done
grep -q "^# note: $note (eps 0.2 asked, 0.001 recorded): " <(critical run.h5 --eps 0.2 --quiet)
# The frames are classified with the rule asked for: a looser eps finds more critical contacts.
critical run.h5 --eps 0.2 --no-cut --quiet > loose.tsv
critical run.h5 --no-cut --quiet > strict.tsv
awk -v a="$(col_max loose.tsv frames Nc)" -v b="$(col_max strict.tsv frames Nc)" 'BEGIN { exit !(a > b) }'
# The note is in the HDF5 product too (attribute notes of /tables).
critical run.h5 --mu 0.3 -o other.h5 --quiet
"$PY" -c "
import h5py
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
f = h5py.File('other.h5', 'r')
assert t(f['parameters'].attrs['series']) == 'frames'
assert any(t(n).startswith('$note (mu 0.3 asked, 0.5 recorded)') for n in f['tables'].attrs['notes'])"

# Asked for explicitly: with the run's rule it is used, with another it is a usage error.
critical run.h5 --series steps --mu 0.5 --quiet > s.tsv
expect_eq steps "$(sed -n 's/^# parameter series = //p' s.tsv)"
expect_fail 2 "critical: --series steps: $note (eps 0.2 asked, 0.001 recorded); use --series frames or auto (see 'critical --help')" \
  critical run.h5 --series steps --eps 0.2 -o out.h5
expect_fail 2 "critical: --series steps: $note (eps 0.2 asked, 0.001 recorded; mu 0.3 asked, 0.5 recorded); use --series frames or auto (see 'critical --help')" \
  critical run.h5 --series steps --eps 0.2 --mu 0.3 -o out.h5
# A run that does not record its rule (no critical_eps): auto takes the frames, steps is refused.
cp run.h5 norule.h5
"$PY" -c "import h5py; f = h5py.File('norule.h5', 'r+'); del f['parameters'].attrs['critical_eps']"
critical norule.h5 --quiet > n.tsv
expect_eq frames "$(sed -n 's/^# parameter series = //p' n.tsv)"
grep -q "^# note: norule.h5 does not record the rule of its per-step critical count (no critical_eps in /parameters)" n.tsv
expect_fail 1 "critical: norule.h5: --series steps: the rule of the per-step critical count is not recorded (no critical_eps in /parameters); use --series frames" \
  critical norule.h5 --series steps -o out.h5 --quiet
test ! -e out.h5
