# docs/architecture.md's layer rule holds: no file of libcommon includes a cdpile header of a layer of its own level or above (model 0; cd, analysis 1; io 2; cli, sim, reading 3).
level() {
  case $1 in
    model) echo 0 ;;
    cd | analysis) echo 1 ;;
    io) echo 2 ;;
    cli | sim | reading) echo 3 ;;
    *) echo "unknown layer '$1' (add it to docs/architecture.md and to this test)" >&2; return 1 ;;
  esac
}
root="$CDPILE_SOURCE/libcommon"
files=0
bad=0
while IFS= read -r -d '' f; do
  rel=${f#"$root/"}
  case $rel in
    include/cdpile/*/*) from=${rel#include/cdpile/}; from=${from%%/*} ;;
    src/*/*) from=${rel#src/}; from=${from%%/*} ;;
    *) from=model ;;  # include/cdpile/model.hpp, error.hpp, check.hpp; src/model.cpp
  esac
  from_level=$(level "$from")
  files=$((files + 1))
  while IFS= read -r inc; do
    case $inc in */*) to=${inc%%/*} ;; *) to=model ;; esac
    [[ $to == "$from" ]] && continue
    to_level=$(level "$to")
    if ((to_level >= from_level)); then
      echo "libcommon/$rel ($from, level $from_level) includes cdpile/$inc ($to, level $to_level)" >&2
      bad=1
    fi
  done < <(sed -n 's|^[[:space:]]*#[[:space:]]*include[[:space:]]*"cdpile/\([^"]*\)".*|\1|p' "$f")
done < <(find "$root" \( -name '*.hpp' -o -name '*.cpp' \) -print0)
((files > 50)) || { echo "only $files files found under $root" >&2; exit 1; }
# io reads and writes, analysis decides: io uses analysis' types (products, tables, the
# fields a view is handed) and calls none of its functions (snake_case names; types are
# CamelCase). The reading layer joins the two (docs/architecture.md).
if grep -nE 'analysis::[a-z][a-z0-9_]*[[:space:]]*\(' "$root"/src/io/*.cpp "$root"/include/cdpile/io/*.hpp >&2; then
  echo "io calls the analysis functions above: move the decision to reading/ (docs/architecture.md)" >&2
  bad=1
fi
exit $bad
