# Damaged files of HDF5's earlier format (which crash or hang libhdf5 1.10.8) give one line and exit 1 in every tool that reads them, from a file or standard input; intact ones are still read.
# ctest: slow, timeout 180
src="$CDPILE_SOURCE"
damaged="$src/tests/fuzz/hdf5-1.10.8"
prefix="damaged file of HDF5's earlier format (superblock version 0, no checksums): libhdf5 [0-9.]*"
advice="in a separate process; an intact copy can be rewritten in the checksummed format with h5repack --low=2 --high=2 OLD NEW"

# expect_refused TOOL FILE-NAME-IN-MESSAGE HOW ARGS...: exit 1, one line on stderr saying
# the file crashed (HOW = crashed) or looped (HOW = looped) libhdf5 or anything else
# (HOW = any), no output left; a
# generous bound on the time (the CPU bound of the check is 5 s).
expect_refused() {
  local tool=$1 name=$2 how=$3; shift 3
  local rc=0
  rm -f out.*
  timeout 300 "$tool" "$@" > /dev/null 2> err.txt || rc=$?
  expect_eq 1 "$rc" "(exit code of $tool $*)"
  expect_eq 1 "$(wc -l < err.txt)" "(lines on stderr from $tool $*: $(cat err.txt))"
  local want="$tool: $name: $prefix crashed reading it $advice"
  [[ $how == looped ]] && want="$tool: $name: $prefix did not finish reading it in 5 s of CPU time (a loop) $advice"
  [[ $how == any ]] && want="$tool: $name: .*"
  if ! grep -qx "$want" err.txt; then
    echo "unexpected message from $tool $*: $(cat err.txt)" >&2; return 1
  fi
  if compgen -G 'out.*' > /dev/null || compgen -G '.out.*' > /dev/null; then echo "output left by $tool $*" >&2; return 1; fi
}

# What the tools read alongside: this version's files, intact.
cp "$src/fuzz/corpus/run/run.h5" good-run.h5
cp "$src/fuzz/corpus/product/correlate.h5" good-correlate.h5

for gz in "$damaged"/*.h5.gz; do
  f=$(basename "$gz" .gz)
  gunzip -c "$gz" > "$f"
  how=crashed
  [[ $f == *hang* ]] && how=looped
  # Two that crash libhdf5 in-process give an error of HDF5's in the child: an
  # allocation of 2 TB fails within the child's memory bound (`/: cannot open`; without
  # the bound, under AddressSanitizer, it ends the child), and H5Ocopy meets the damaged
  # attribute table as an error (`/parameters: cannot read (damaged?)`). One line and
  # exit 1 either way.
  [[ $f == *cache-protect* || $f == *attribute-list* ]] && how=any
  case $f in
    run-*)
      expect_refused tilt-cd "$f" $how "$f" --to 0.01 -o out.h5
      expect_refused critical "$f" $how "$f" -o out.h5
      expect_refused localnu "$f" $how "$f" -o out.h5
      expect_refused to-xdmf "$f" $how "$f" -o out.xdmf
      expect_refused to-lammps "$f" $how "$f" -o out.dump
      expect_refused critical stdin $how - -o out.h5 < "$f"
      ;;
    product-*)  # damaged critical products
      expect_refused localnu "$f" $how good-run.h5 --nu "$f" -o out.h5
      expect_refused clusterfit "$f" $how good-correlate.h5 --nu "$f" -o out.tsv
      expect_refused correlate "$f" $how "$f" -o out.h5
      expect_refused clusterfit "$f" $how "$f" -o out.tsv
      expect_refused to-xdmf "$f" $how "$f" -o out.xdmf
      expect_refused localnu stdin $how good-run.h5 --nu - -o out.h5 < "$f"
      ;;
    *) echo "no tool is known to read $f" >&2; exit 1 ;;
  esac
done

# Intact files of the earlier format are read as before, and so are those rewritten as
# the message advises (superblock version 3).
cp "$src/fuzz/corpus/run/old-run.h5" "$src/fuzz/corpus/product/old-critical.h5" .
critical old-run.h5 -o crit.tsv --quiet
critical - -o crit2.tsv --quiet < old-run.h5
# (this old product has no nu_c: the reader got past the check and through the file)
expect_fail 1 "localnu: old-critical.h5: the critical product has no nu_c (its envelope was not fitted); give --nu-c" \
  localnu old-run.h5 --nu old-critical.h5 -o nu.tsv
h5repack --low=2 --high=2 old-run.h5 new-run.h5
expect_eq 3 "$(od -An -tu1 -j8 -N1 new-run.h5 | tr -d ' ')" "(superblock version after h5repack)"
critical new-run.h5 -o crit3.tsv --quiet
# the same results, but for the file's name
cmp <(grep -v '^# \(input\|command\|provenance\):' crit.tsv) \
    <(grep -v '^# \(input\|command\|provenance\):' crit3.tsv | sed 's/new-run\.h5/old-run.h5/')
