#!/usr/bin/env bash
# README command 1: install what is missing, build in Release, run the demo study.
#   ./setup.sh            everything
#   ./setup.sh --no-demo  install and build only
set -euo pipefail
cd "$(dirname "$0")"
scripts/install-deps.sh
cmake --workflow --preset release
if [[ "${1:-}" == "--no-demo" ]]; then
  echo "setup: built; the tools are in build/bin"
  exit 0
fi
exec make -C pipelines demo
