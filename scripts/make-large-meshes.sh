#!/usr/bin/env bash
# Makes the million-vertex test mesh from the fetched 437k Stanford dragon (scripts/fetch-meshes.sh):
#   assets/meshes/dragon_1m.off = dragon_vrip.ply, one midpoint subdivision (1.74M vertices, the same surface),
#   simplified to 1,000,000 vertices by the product's decimation (meshoptimizer); OFF with 17 significant digits.
# About 7 s and 1 GB on this 2-core machine. Needs the build (build/bin/shapecast-make-mesh). Idempotent: an
# existing file is kept. Prints the result's SHA-256 (the same input and build give the same file).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dest="$root/assets/meshes"
tool="${SHAPECAST_BUILD_DIR:-$root/build}/bin/shapecast-make-mesh"
if [[ ! -f "$dest/dragon_vrip.ply" ]]; then
  echo "[large meshes] $dest/dragon_vrip.ply is missing: run scripts/fetch-meshes.sh first" >&2
  exit 1
fi
if [[ ! -f "$dest/dragon_1m.off" ]]; then
  "$tool" --subdivide 1 --vertices 1000000 "$dest/dragon_vrip.ply" "$dest/dragon_1m.part.off"
  mv "$dest/dragon_1m.part.off" "$dest/dragon_1m.off"
fi
sha256sum "$dest/dragon_1m.off"
