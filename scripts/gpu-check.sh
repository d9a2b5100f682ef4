#!/usr/bin/env bash
# Runs shapecast-gpu-check (tools/gpu_check) on a machine with a GPU and no display server: Qt's eglfs platform
# kept away from the framebuffer device, the context made by hand on EGL's default display (--egl). Under an X
# server run the tool directly instead. Extra arguments go to the tool (meshes, --m, --frames).
#   scripts/gpu-check.sh assets/meshes/dragon_vrip_res2.ply
# SHAPECAST_GPU_CHECK: the tool's path (default build/bin/shapecast-gpu-check).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export QT_QPA_PLATFORM=eglfs QT_QPA_EGLFS_FB=/dev/null QT_QPA_EGLFS_INTEGRATION=none QT_QPA_EGLFS_DISABLE_INPUT=1
export QT_QPA_EGLFS_WIDTH=1024 QT_QPA_EGLFS_HEIGHT=768 QT_QPA_EGLFS_PHYSICAL_WIDTH=300 QT_QPA_EGLFS_PHYSICAL_HEIGHT=200
exec "${SHAPECAST_GPU_CHECK:-$root/build/bin/shapecast-gpu-check}" --egl "$@"
