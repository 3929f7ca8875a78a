# A full disk (ENOSPC) ends every writer with exit 1 and one line naming the output, no crash in HDF5's shutdown, no temporary left, an old file kept. Needs root (a tiny tmpfs).
if [[ $(id -u) -ne 0 ]] || ! command -v mount > /dev/null; then
  echo "skipped: mounting a small tmpfs needs root" >&2; exit 77
fi
deposit --grains 40 --width 10 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.05 --rate 0.01 -o run.h5 --quiet
critical run.h5 -o crit.h5 --quiet
localnu run.h5 -o ln.h5 --quiet
correlate ln.h5 -o cor.h5 --quiet
"$PY" "$CDPILE_SOURCE/tests/tools/from-lammps/make_dumps.py" lammps plain p
mkdir full
mount -t tmpfs -o size=64k tmpfs full || { echo "skipped: cannot mount a tmpfs here" >&2; exit 77; }
trap 'umount full' EXIT
echo kept > full/old.h5
# The disk is full once the filler has taken every block: every write fails with ENOSPC.
dd if=/dev/zero of=full/filler bs=4k 2> /dev/null || true

# full_disk TOOL ARGS...: writing to full/out.* fails with exit 1, one line naming it.
check() {
  local out=$1; shift
  local rc=0
  "$@" > stdout.txt 2> err.txt || rc=$?
  if [[ $rc -ne 1 ]]; then echo "expected exit 1, got $rc from: $*" >&2; cat err.txt >&2; return 1; fi
  expect_eq 1 "$(wc -l < err.txt)" "(lines on stderr from $*)"
  grep -q "^$1: $out: .*\(disk full\|No space left on device\)" err.txt || { cat err.txt >&2; return 1; }
  expect_eq "filler old.h5" "$(ls -A full | tr '\n' ' ' | sed 's/ $//')" "(files left by $*)"
}
check full/out.h5 deposit --grains 20 --width 6 -o full/out.h5 --quiet
check full/out.h5.partial tilt-cd pile.h5 --to 0.05 --rate 0.01 -o full/out.h5 --quiet
check full/out.h5 critical run.h5 -o full/out.h5 --quiet
check full/out.tsv critical run.h5 -o full/out.tsv --quiet
check full/out.h5 localnu run.h5 -o full/out.h5 --quiet
check full/out.h5 correlate ln.h5 -o full/out.h5 --quiet
check full/out.tsv clusterfit cor.h5 --nu crit.h5 -o full/out.tsv --quiet
check full/out.xmf.hdf5 to-xdmf run.h5 -o full/out.xmf --quiet
check full/out.dump to-lammps run.h5 -o full/out.dump --quiet
check full/out.tsv from-lammps p.atoms p.pairs --script p.in --rate 2 --dt 1e-3 --quiet -o full/out.tsv
# An existing output replaced with --force is kept when the new one cannot be written.
check full/old.h5 critical run.h5 -o full/old.h5 --force --quiet
expect_eq kept "$(cat full/old.h5)" "(the old file)"
