# h5dump shows the H5MD structure, and the h5py example of docs/schema.md runs as written.
cli-demo --count 6 -o pile.h5
h5dump -H pile.h5 > header.txt
for path in 'GROUP "h5md"' 'GROUP "particles"' 'GROUP "grains"' 'GROUP "box"' 'GROUP "position"' \
            'DATASET "value"' 'DATASET "step"' 'GROUP "contacts"' 'GROUP "observables"' 'GROUP "provenance"'; do
  grep -q "$path" header.txt || { echo "h5dump lacks $path" >&2; exit 1; }
done
h5dump -a /particles/grains/box/dimension pile.h5 | grep -q '(0): 2'
# Extract the example from the docs and run it on this file.
awk '/^```python example/{on=1; next} /^```/{on=0} on' "$CDPILE_SOURCE/docs/schema.md" > example.py
test -s example.py
cp pile.h5 run.h5
"$PY" example.py > example.txt
grep -q '^grains 6, frames 1$' example.txt
grep -q '^frame 0: 6 contacts, 0 critical$' example.txt
