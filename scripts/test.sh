#!/usr/bin/env bash
# Installs what is missing, builds with warnings as errors, and runs every test (ctest) under a real
# X server (xvfb-run) so the GUI tests get a display. Extra arguments go to ctest (e.g. -R Harmonic).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh" -DSHAPECAST_WERROR=ON
cd "$root/build"
# ctest runs two test processes on the two cores; OpenBLAS's own worker threads would oversubscribe them and each
# BLAS call would wait for a time slice (measured: a 0.6 s basis taking 5 s). Single-threaded BLAS for the tests.
export OPENBLAS_NUM_THREADS=1
xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure -j"$(nproc)" --timeout 600 "$@"
