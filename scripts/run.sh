#!/usr/bin/env bash
# Installs what is missing, builds, and starts the ShapeCast desktop app on the default mesh
# (assets/meshes/dragon_vrip_res3.ply, the 23k-vertex Stanford dragon). Arguments go to the app; when the first
# one is not a mesh file (e.g. ./scripts/run.sh --screenshot shot.png) the default mesh is opened.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh"
if [[ $# -eq 0 || "$1" == -* ]]; then
  set -- "$root/assets/meshes/dragon_vrip_res3.ply" "$@"
fi
exec "$root/build/bin/shapecast" "$@"
