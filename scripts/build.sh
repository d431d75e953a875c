#!/usr/bin/env bash
# Configures and builds StrataMesh in build/ (Release), after installing what is missing.
# Used by scripts/demo.sh and scripts/test.sh; safe to run again (incremental).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/install-deps.sh"
build="${STRATAMESH_BUILD_DIR:-$here/build}"
jobs="$(nproc 2>/dev/null || echo 2)"
echo "[build] configuring in $build"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build.configure.log" 2>&1 || {
  cat "$build.configure.log"
  echo "[build] error: configuring failed (log above)" >&2
  exit 1
}
echo "[build] building with $jobs jobs"
cmake --build "$build" -j "$jobs"
plugin="$build/lib/paraview-5.11/plugins/StrataMesh/StrataMesh.so"
echo "[build] plugin: $plugin"
