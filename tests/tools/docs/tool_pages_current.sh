# docs/tools/<tool>.md equals the tool's --help-markdown (run docs/generate_tool_docs.sh).
found=0
for tool in $(awk '!/^#/ && NF { print $1 }' "$CDPILE_SOURCE/tools/LIST"); do  # every tool
  [[ -x "$CDPILE_BIN/$tool" ]] || continue
  found=1
  page="$CDPILE_SOURCE/docs/tools/$tool.md"
  [[ -f "$page" ]] || { echo "missing $page (run docs/generate_tool_docs.sh)" >&2; exit 1; }
  "$tool" --help-markdown > current.md
  diff -u "$page" current.md || { echo "$page is stale (run docs/generate_tool_docs.sh)" >&2; exit 1; }
  # Every tool names itself in its usage line and exits 0 on --help and --version.
  "$tool" --help | grep -q "^Usage: $tool "
  "$tool" --version | grep -q "^$tool (cdpile) "
done
[[ $found -eq 1 ]] || exit 77  # no tool built yet
