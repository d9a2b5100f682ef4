#!/usr/bin/env bash
# Installs what is missing, builds, and starts the ShapeCast desktop app. Without arguments the app hosts a local
# session on the default mesh (assets/meshes/dragon_vrip_res3.ply, the 23k-vertex Stanford dragon; a generated
# torus if no mesh was fetched), ready to drag. Arguments go to the app (e.g. --demo, or a mesh file to view); with
# --screenshot/--size first (./scripts/run.sh --screenshot shot.png) the default mesh is viewed and rendered.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# Only what the window needs (and the command-line tool): the tests, fuzz seeds and benchmarks are the test
# command's to build.
SHAPECAST_BUILD_TARGETS="shapecast shapecast-cli" "$root/scripts/setup.sh"
if [[ $# -gt 0 && ( "$1" == --screenshot* || "$1" == --size* ) ]]; then
  set -- "$root/assets/meshes/dragon_vrip_res3.ply" "$@"
fi
exec "$root/build/bin/shapecast" "$@"
