# cmake --install puts the tools in PREFIX/bin and their manual pages in
# PREFIX/share/man/man1, each page made from the tool's usage declaration (the options of
# --help, no more, no fewer); the benchmarks are built apart (build/benchmarks) and not
# installed.
build=$(cd "$CDPILE_BIN/.." && pwd)
cmake --install "$build" --prefix "$PWD/prefix" > install.log
tools="clusterfit correlate critical deposit from-lammps localnu summarise tilt-cd to-lammps to-xdmf"
expect_eq "$tools" "$(ls prefix/bin | paste -sd ' ')" "(installed executables)"
expect_eq "$(for t in $tools; do echo "$t.1"; done | paste -sd ' ')" "$(ls prefix/share/man/man1 | paste -sd ' ')" "(manual pages)"
for t in $tools; do
  page=prefix/share/man/man1/$t.1
  grep -q "^\.TH $(echo "$t" | tr a-z A-Z) 1 " "$page"
  # the page's options are --help's (roff writes a dash as \-)
  expect_eq "$("$t" --help | grep -oE '^  (-[a-z], |    )--[a-z-]+' | grep -oE -- '--[a-z-]+' | sort | paste -sd ' ')" \
            "$(sed -n '/^\.B /p' "$page" | sed 's/\\-/-/g' | grep -oE -- '--[a-z-]+' | sort | paste -sd ' ')" "($t: options)"
done
# rendered by man when it is there
if command -v man > /dev/null; then
  MANWIDTH=80 man -l prefix/share/man/man1/tilt-cd.1 2> man.err | grep -q -- '--branch-at'
  expect_eq "" "$(grep -v 'cannot adjust' man.err || true)" "(man's complaints)"
fi
# benchmarks: beside build/bin, never in it, never installed
for b in bench_engine bench_analysis bench_siconos export_steps tile_pile; do
  test ! -e "$build/bin/$b"
done
if [[ -d $build/benchmarks ]]; then test -x "$build/benchmarks/export_steps"; fi
