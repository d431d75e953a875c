#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the main pipeline through pvbatch
# on the bundled default model (Data/lake_superior.vtp, or the model given as argument),
# writing its outputs under out/ and printing a summary.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh"
build="${STRATAMESH_BUILD_DIR:-$here/build}"
plugin="$build/lib/paraview-5.11/plugins/StrataMesh/StrataMesh.so"
model="${1:-$here/Data/lake_superior.vtp}"
mkdir -p "$here/out"
# pvbatch renders through X: a virtual display (xvfb-run) when none is there.
runner=()
if [ -z "${DISPLAY:-}" ]; then
  runner=(xvfb-run -a -s "-screen 0 1280x1024x24")
fi
"${runner[@]}" pvbatch "$here/scripts/demo.py" --plugin "$plugin" --model "$model" --out "$here/out"
