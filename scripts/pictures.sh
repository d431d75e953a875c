#!/usr/bin/env bash
# Remakes the README's pictures in Documentation/ from the bundled models (after a build).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/build.sh"
build="${STRATAMESH_BUILD_DIR:-$here/build}"
plugin="$build/lib/paraview-5.11/plugins/StrataMesh/StrataMesh.so"
xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch "$here/scripts/pictures.py" \
  --plugin "$plugin" --data "$here/Data" --out "$here/Documentation"
