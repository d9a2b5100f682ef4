#!/usr/bin/env bash
# Builds (if needed) and runs the benchmarks; results are printed and written to docs/benchmarks.md.
# Not part of CI: run it by hand on an otherwise idle machine.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh"
"$root/build/bin/shapecast-bench-basis" "$@"
