# The frames table has the static bound of McNamara & Herrmann 2004 (M, N, Nc over the load-bearing grains, B = 2M - 3N, above 0/1), by hand, the same in TSV and HDF5.
# Frame 0: grains 0, 1 on the floor (wall -1) and touching; grain 2 rests on 1 only: a rattler.
# Load-bearing: 0 and 1 (N = 2); M = 3 (0-floor, 0-1, 1-floor); B = 6 - 6 = 0; critical with
# mu 0.5: 0-floor and 1-floor, Nc = 2 > 0. Frame 1: the floor contacts stick, Nc = 0 = B.
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\n0\t1\t0\t-1\t0\t0\t1\t0.5\n0\t1\t0\t1\t0.5\t0.5\t1\t0\n0\t1\t1\t-1\t1\t0\t1\t0.5\n0\t1\t2\t1\t1\t1\t1\t0.5\n1\t2\t0\t-1\t0\t0\t1\t0.1\n1\t2\t0\t1\t0.5\t0.5\t1\t0\n1\t2\t1\t-1\t1\t0\t1\t0.1\n1\t2\t2\t1\t1\t1\t1\t0.5\n' > t.tsv
table-to-run t.tsv run.h5 1 0.5
critical run.h5 --table frames --quiet > f.tsv
got=""
for col in contacts_load_bearing grains_load_bearing critical_load_bearing static_bound above_static_bound; do
  got="$got $(tsv_value f.tsv frames $col 1)/$(tsv_value f.tsv frames $col 2)"
done
expect_eq " 3/3 2/2 2/0 0/0 1/0" "$got"
critical run.h5 -o c.h5 --quiet
"$PY" -c "
import h5py
t = h5py.File('c.h5', 'r')['tables/frames']
assert [list(t[c][()]) for c in ('contacts_load_bearing', 'grains_load_bearing', 'critical_load_bearing', 'static_bound', 'above_static_bound')] == [[3, 3], [2, 2], [2, 0], [0, 0], [1, 0]]
"
