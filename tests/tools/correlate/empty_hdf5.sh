# An empty result (no frame in --from/--to) is a valid HDF5 product, to a file and through a pipe, and clusterfit reads it.
cat > line.tsv <<'T'
frame	theta	x	y	fn	ft
0	2	0	0	2	1
0	2	1	0	2	0.2
T
localnu line.tsv --mu 0.5 --diameter 1 --radii 1,2 -o l.h5 --quiet
# The text column se_over has no rows, so no labels: its attribute is an empty list.
correlate l.h5 --from 100 -o w.h5 --quiet
"$PY" - <<'P'
import h5py
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
with h5py.File("w.h5", "r") as f:
    assert t(f.attrs["kind"]) == "correlate"
    assert f["tables/windows/se_over"].shape == (0,)
    assert len(f["tables/windows/se_over"].attrs["labels"]) == 0
    assert f["tables/windows/nu_bar"].shape == (0,)
    assert f["results"].attrs["windows"] == 0
P
clusterfit w.h5 --nu-c 0.1 > f.tsv
expect_eq "0 0" "$(tsv_result f.tsv windows_fitted) $(tsv_rows f.tsv fits)"
# The same through a pipe: correlate -o - | clusterfit -, HDF5 all along.
correlate l.h5 --from 100 -o - --quiet | clusterfit - --nu-c 0.1 -o f.h5 --quiet
"$PY" -c "import h5py; f = h5py.File('f.h5', 'r'); assert f['tables/fits/theta'].shape == (0,), f['tables/fits/theta'].shape"
# An open range (--pdf-from, --from without an upper end) leaves the open end out of the
# parameters: an HDF5 product holds no infinity.
localnu line.tsv --mu 0.5 --diameter 1 --radii 1,2 --pdf-from 1 -o - --quiet | correlate - --from 100 -o - |
  clusterfit - -o - | cat > f2.h5
"$PY" -c "import h5py; f = h5py.File('f2.h5', 'r'); assert f.attrs['kind'] == b'clusterfit'"
