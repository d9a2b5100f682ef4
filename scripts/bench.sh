#!/usr/bin/env bash
# Builds (if needed) and runs the benchmarks; results are printed and written to docs/benchmarks.md.
# Not part of CI: run it by hand on an otherwise idle machine.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh"
"$root/build/bin/shapecast-bench-basis" "$@"
# Viewport frame time (reconstruction + redraw) on both reconstruction paths; needs a display, so under Xvfb.
if command -v xvfb-run > /dev/null; then
  xvfb-run -a -s "-screen 0 1280x1024x24" "$root/build/bin/shapecast-bench-viewport"
else
  echo "xvfb-run not found: skipping shapecast-bench-viewport" >&2
fi
# The paper's experiments and Table 1 are shapecast-lab's (experiments/; also run as `shapecast-cli experiment
# loss|load` and `shapecast-cli bench table1`). They take minutes to hours, so they are run one by one, by hand:
echo "paper experiments: $root/build/bin/shapecast-lab table1|loss|load (see --help)" >&2
