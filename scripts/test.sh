#!/usr/bin/env bash
# The test command: installs what is missing, builds, and runs every test through ctest
# (GoogleTest cases one by one, and the pvpython/pvbatch tests). Extra arguments go to ctest.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh"
build="${STRATAMESH_BUILD_DIR:-$here/build}"
cd "$build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" --timeout 300 "$@"
