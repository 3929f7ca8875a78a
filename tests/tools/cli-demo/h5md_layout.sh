# h5dump shows the H5MD structure, and the h5py example of docs/schema.md runs as written.
cli-demo --count 6 -o pile.h5
h5dump -H pile.h5 > header.txt
for path in 'GROUP "h5md"' 'GROUP "particles"' 'GROUP "grains"' 'GROUP "box"' 'GROUP "position"' \
            'DATASET "value"' 'DATASET "step"' 'GROUP "contacts"' 'GROUP "observables"' 'GROUP "provenance"'; do
  grep -q "$path" header.txt || { echo "h5dump lacks $path" >&2; exit 1; }
done
h5dump -a /particles/grains/box/dimension pile.h5 | grep -q '(0): 2'
# Extract the example from the docs and run it on a small run: its counts are critical's.
awk '/^```python example/{on=1; next} /^```/{on=0} on' "$CDPILE_SOURCE/docs/schema.md" > example.py
test -s example.py
deposit --grains 30 --width 6 --seed 2 --quiet -o small.h5
tilt-cd small.h5 --rate 2 --to 6 --frame-every 1 --quiet -o run.h5
"$PY" example.py > example.txt
grep -q '^grains [0-9]*, frames 4$' example.txt
critical run.h5 --quiet --table frames > frames.tsv
for k in 0 1 2 3; do
  want="frame $k: $(tsv_value frames.tsv frames N $((k + 1))) contacts, $(tsv_value frames.tsv frames Nc $((k + 1))) critical"
  grep -qx "$want" example.txt || { echo "example.py disagrees with critical: want '$want'" >&2; cat example.txt >&2; exit 1; }
done
# a pile with glued floor grains and walls: the example leaves them out, as critical does
[[ $(tsv_value frames.tsv frames N 1) -gt 0 ]]
