#!/usr/bin/env bash
# One-time (and idempotent) set-up: Debian packages, real test meshes, configure and build into build/.
# Extra CMake arguments can be passed as arguments, e.g. scripts/setup.sh -DSHAPECAST_WERROR=ON
# SHAPECAST_BUILD_TARGETS (space-separated) builds only those targets (run.sh: the applications; default: all).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/install-packages.sh"
"$root/scripts/fetch-meshes.sh"
cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
read -r -a targets <<<"${SHAPECAST_BUILD_TARGETS:-all}"
cmake --build "$root/build" -j"$(nproc)" --target "${targets[@]}"
