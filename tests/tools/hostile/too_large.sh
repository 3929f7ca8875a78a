# A file claiming more data than it can hold (4e8 contacts in a few kB) is refused before allocating: 'too large', the file and dataset named.
deposit --grains 40 --width 10 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.01 --rate 0.01 -o run.h5 --quiet
cp run.h5 huge.h5
"$PY" - <<'PY'
import h5py
f = h5py.File('huge.h5', 'r+')
c = f['contacts']
n = 400_000_000
for name in ['i', 'j', 'fn', 'ft', 'gap', 'status', 'point', 'normal']:
    c[name].resize(n, axis=0)  # extendible datasets: no chunk is written, the file stays small
c['count'][-1] = n - c['offset'][-1]
PY
test "$(stat -c %s huge.h5)" -lt 1000000
for tool in critical localnu; do
  rc=0; $tool huge.h5 -o out.h5 2> err.txt || rc=$?
  expect_eq 1 "$rc" "(exit code of $tool)"
  expect_eq 1 "$(wc -l < err.txt)" "(lines on stderr from $tool)"
  grep -qx "$tool: huge.h5: /contacts/[a-z]*: too large (claims [0-9]* elements, [0-9.]* [GM]B, in a file of [0-9.]* kB)" err.txt
  test ! -e out.h5
done
