#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Generates the API reference (Doxygen HTML for every public header; entry page docs/api.md, the concepts) into
# build/docs/html. Installs doxygen and graphviz if missing. Fails if Doxygen warns (warnings in
# build/docs/warnings.log).
# Usage: scripts/docs.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh --with-docs
mkdir -p build/docs
rm -f build/docs/warnings.log
doxygen Doxyfile
if [[ -s build/docs/warnings.log ]]; then
  echo "docs: Doxygen warned ($(wc -l < build/docs/warnings.log) lines):" >&2
  head -40 build/docs/warnings.log >&2
  exit 1
fi
echo "docs: wrote build/docs/html/index.html ($(find build/docs/html -name '*.html' | wc -l) pages, no warnings)"
