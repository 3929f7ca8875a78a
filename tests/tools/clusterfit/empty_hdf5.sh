# Nothing to fit (every window outside --from/--to) writes a valid HDF5 product (an empty affine table), to a file and to a pipe.
"$PY" "$CDPILE_SOURCE/tests/tools/clusterfit/synthetic.py" d.tsv 0 1 law
# The text column 'param' of the empty table affine has no labels: an empty list attribute.
clusterfit d.tsv --from 100 -o f.h5 --quiet
"$PY" - <<'P'
import h5py
def t(v): return v.decode() if isinstance(v, bytes) else v  # fixed-length strings read as bytes
with h5py.File("f.h5", "r") as f:
    assert t(f.attrs["kind"]) == "clusterfit"
    for c in f["tables/affine"].attrs["columns"]:
        assert f["tables/affine"][c].shape == (0,), c
    assert list(f["tables/fits/converged"][:]) == [0, 0, 0]
    assert len(f["tables/affine/param"].attrs["labels"]) == 0
    assert f["results"].attrs["windows_fitted"] == 0
P
clusterfit d.tsv --from 100 -o - --quiet | cat > g.h5
"$PY" -c "import h5py; f = h5py.File('g.h5', 'r'); assert f['tables/affine/param'].shape == (0,)"
