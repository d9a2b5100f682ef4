#!/usr/bin/env bash
# Idle CPU of a ShapeCast host and a client with nothing moving (issue 16): starts `shapecast --host MESH` and
# `shapecast --join` as two processes on one display (Xvfb when DISPLAY is unset), waits until the client has
# joined and settled, then reads each process's CPU time (utime + stime, /proc/PID/stat) before and after an idle
# stretch and prints it as a percentage of one core, with the machine it ran on.
#
# usage: scripts/idle-cpu.sh [MESH] [IDLE_SECONDS=30] [SETTLE_SECONDS=20]   (BIN=path/to/shapecast to override)
set -euo pipefail
cd "$(dirname "$0")/.."
mesh=${1:-assets/meshes/elephant.off}
idle=${2:-30}
settle=${3:-20}
bin=${BIN:-build/bin/shapecast}
if [ -z "${DISPLAY:-}" ]; then
  exec xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$0" "$mesh" "$idle" "$settle"
fi
work=$(mktemp -d)
export XDG_CONFIG_HOME="$work/config" HOME="$work"
port=$((47300 + RANDOM % 600))
"$bin" --host "$mesh" --port "$port" --name host >"$work/host.log" 2>&1 &
host=$!
cleanup() {
  kill "$host" "${client:-}" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
for _ in $(seq 1 600); do  # the host listens once its basis is computed
  if ss -ltn 2>/dev/null | grep -q ":$port "; then break; fi
  sleep 0.5
done
"$bin" --join "127.0.0.1:$port" --name client >"$work/client.log" 2>&1 &
client=$!
sleep "$settle"
ticks() { awk '{ sub(/^.*\) /, ""); print $12 + $13 }' "/proc/$1/stat"; }  # utime + stime (fields 14, 15)
hz=$(getconf CLK_TCK)
h0=$(ticks "$host")
c0=$(ticks "$client")
t0=$(date +%s.%N)
sleep "$idle"
h1=$(ticks "$host")
c1=$(ticks "$client")
t1=$(date +%s.%N)
cpu=$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')
echo "machine: $cpu, $(nproc) cores; display $DISPLAY; mesh $mesh; idle ${idle} s after ${settle} s to settle"
awk -v h="$((h1 - h0))" -v c="$((c1 - c0))" -v hz="$hz" -v t0="$t0" -v t1="$t1" 'BEGIN {
  wall = t1 - t0
  printf "host   CPU %.2f s in %.1f s = %.1f%% of a core\n", h / hz, wall, 100 * h / hz / wall
  printf "client CPU %.2f s in %.1f s = %.1f%% of a core\n", c / hz, wall, 100 * c / hz / wall
}'
