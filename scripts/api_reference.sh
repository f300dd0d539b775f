#!/usr/bin/env bash
# The API reference (Doxygen, docs/Doxyfile) of include/toolpoint into BUILD_DIR/api/html; fails
# on any Doxygen warning, listing them. Exit 77 (a skip for ctest) when doxygen is not installed
# (scripts/run.sh installs it for the test job).
#
#   bash scripts/api_reference.sh build        # then open build/api/html/index.html
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$(mkdir -p "${1:-build}" && cd "${1:-build}" && pwd)
if ! command -v doxygen >/dev/null; then
  echo "api_reference: doxygen is not installed (Debian package doxygen); skipped" >&2
  exit 77
fi
out="$build_dir/api"
rm -rf "$out"
mkdir -p "$out"
cd "$here"  # docs/Doxyfile's paths are relative to the repository
TOOLPOINT_API_OUTPUT="$out" doxygen docs/Doxyfile
if [ -s "$out/warnings.log" ]; then
  echo "api_reference: Doxygen warned ($(grep -c 'warning:' "$out/warnings.log") warnings); fix the header comments:" >&2
  cat "$out/warnings.log" >&2
  exit 1
fi
echo "api_reference: $out/html/index.html (no warnings)"
