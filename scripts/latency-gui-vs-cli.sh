#!/usr/bin/env bash
# The latency the desktop app reports next to the headless client's, for one loopback session during a drag
# (issue 16): `shapecast-cli host` (which prints every member's StatsReport every 5 s), a `shapecast --join`
# window named "gui" and a `shapecast-cli join` named "cli", then `shapecast-cli drive` plays a drag. Both members'
# loss and latency figures are those of the last 10 s; the script prints the host's lines for both during the drag.
#
# usage: scripts/latency-gui-vs-cli.sh [MESH=assets/meshes/dragon_vrip_res3.ply] [SCRIPT=docs/examples/dragon-drag.json]
#        (GUI=path/to/shapecast CLI=path/to/shapecast-cli to override)
set -euo pipefail
cd "$(dirname "$0")/.."
mesh=${1:-assets/meshes/dragon_vrip_res3.ply}
script=${2:-docs/examples/dragon-drag.json}
if [ -z "${DISPLAY:-}" ]; then
  exec xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$0" "$mesh" "$script"
fi
work=$(mktemp -d)
export XDG_CONFIG_HOME="$work/config" HOME="$work"
port=$((47900 + RANDOM % 600))
"${CLI:-build/bin/shapecast-cli}" host "$mesh" --port "$port" >"$work/host.log" 2>&1 &
host=$!
cleanup() {
  kill "$host" "${gui:-}" "${cli:-}" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
for _ in $(seq 1 600); do
  if ss -ltn 2>/dev/null | grep -q ":$port "; then break; fi
  sleep 0.5
done
"${GUI:-build/bin/shapecast}" --join "127.0.0.1:$port" --name gui >"$work/gui.log" 2>&1 &
gui=$!
"${CLI:-build/bin/shapecast-cli}" join "127.0.0.1:$port" --name cli >"$work/cli.log" 2>&1 &
cli=$!
sleep 15  # both joined; the join itself has left the 10 s window
for _ in 1 2 3; do "${CLI:-build/bin/shapecast-cli}" drive "127.0.0.1:$port" --script "$script" >>"$work/drive.log" 2>&1; done
sleep 1
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(nproc) cores; mesh $mesh"
echo "host's lines for both members (loss and latency p99 of their last 10 s), from the join to after the drags:"
grep -E "^  (gui|cli) " "$work/host.log" || true
echo "shapecast-cli join's own last lines:"
tail -n 3 "$work/cli.log"
