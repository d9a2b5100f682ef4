#!/usr/bin/env bash
# One-time (and idempotent) set-up: Debian packages, real test meshes, configure and build into build/.
# Extra CMake arguments can be passed as arguments, e.g. scripts/setup.sh -DSHAPECAST_WERROR=ON
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/install-packages.sh"
"$root/scripts/fetch-meshes.sh"
cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$root/build" -j"$(nproc)"
