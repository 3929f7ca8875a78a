#!/usr/bin/env bash
# Regenerates docs/tools/<tool>.md from each tool's own declaration (--help-markdown),
# so the manual pages and --help never drift apart. A test checks they are current.
#   docs/generate_tool_docs.sh [BIN_DIR]     (default: build/bin)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-$here/../build/bin}
mkdir -p "$here/tools"
# The tools are listed once, in tools/LIST: the first word of each line not a comment.
for tool in $(awk '!/^#/ && NF { print $1 }' "$here/../tools/LIST"); do
  if [[ -x "$bin/$tool" ]]; then
    "$bin/$tool" --help-markdown > "$here/tools/$tool.md"
    echo "docs/tools/$tool.md"
  fi
done
