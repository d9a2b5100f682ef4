#!/usr/bin/env bash
# The desktop client's GUI-thread stalls on a large mesh (issue 19 item 3; figures in docs/benchmarks.md, "Large
# meshes end to end"). For each MESH: a `shapecast-cli host` (cached basis), then the desktop client `shapecast
# --join` under Xvfb with software GL (LIBGL_ALWAYS_SOFTWARE=1) and SHAPECAST_STALL_MS=100, twice:
#   5%    join at 5% until the host has the client's figures at that level, then 10 s idle
#   full  join at full resolution (progressive: the smallest level first) until the host has its figures at n
#         vertices, 10 s idle, the scripted drag (shapecast-cli drive docs/examples/dragon-drag.json, 181 frames
#         at 30 fps), 15 s after it
# and prints, per step, the event-loop stalls of 200 ms or more and the longest gap, with the client's peak RSS
# (/usr/bin/time -v on shapecast itself), the machine and the load average. One process chain at a time, `nice`.
#   scripts/gui-stalls.sh [MESH ...]   (default: assets/meshes/dragon_1m.off)
#   SHAPECAST_BUILD_DIR picks another build (default build/), e.g. a build of the previous commit for "before".
#   GUI_STALLS_KEEP=PREFIX keeps each client's stderr as PREFIX.5%.err and PREFIX.full.err (the stalls, and the
#   client's own lines: each level install's GUI-thread time and its first paint's stages).
set -u
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=${SHAPECAST_BUILD_DIR:-$root/build}/bin
cli=$bin/shapecast-cli
if [[ $# -eq 0 ]]; then set -- "$root/assets/meshes/dragon_1m.off"; fi
out=$(mktemp -d)
host_pid=""
gui_pid=""
cleanup() {
  [[ -n $gui_pid ]] && kill -TERM "$gui_pid" 2> /dev/null
  [[ -n $host_pid ]] && kill -INT "$host_pid" 2> /dev/null
  sleep 1
  rm -rf "$out"
}
trap cleanup EXIT

machine() {
  printf 'machine: %s, %s cores, %s GiB RAM; load average %s\n' "$(lscpu | sed -n 's/^Model name: *//p')" \
    "$(nproc)" "$(free -g | awk '/^Mem:/ {print $2}')" "$(cut -d' ' -f1-3 /proc/loadavg)"
}
now() { date +%s.%N; }
# wait_for FILE PATTERN SECONDS: until PATTERN is in FILE; false on timeout
wait_for() {
  local end=$((SECONDS + $3))
  while ((SECONDS < end)); do grep -q -- "$2" "$1" 2> /dev/null && return 0; sleep 0.2; done
  return 1
}
# stalls LOG FROM TO LAUNCH: the stalls of LOG that ended between the unix times FROM and TO (the probe prints its
# start; a build older than that line is taken to start at LAUNCH, a few hundred ms early)
stalls() {
  python3 - "$@" << 'PY'
import re, sys
log, t0, t1, launch = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
text = open(log).read()
m = re.search(r'from unix time ([0-9.]+)', text)
start = float(m.group(1)) if m else launch
gaps = [(float(ms), start + float(at)) for ms, at in re.findall(r'stalled for ([0-9]+) ms \(at ([0-9.]+) s\)', text)]
inside = sorted(ms for ms, at in gaps if t0 <= at < t1)
big = [ms for ms in inside if ms >= 200]
print('%d stalls >= 200 ms, longest %s; %s' % (len(big), ('%.0f ms' % inside[-1]) if inside else '< 100 ms',
      ' '.join('%.0f' % ms for ms in big[-12:]) or '-'))
PY
}
gui_rss() { awk -F': ' '/Maximum resident set size/ {printf "%.0f MB", $2 / 1024}' "$out/gui.time"; }

machine
for mesh in "$@"; do
  echo
  echo "## $(basename "$mesh")"
  nice -n 5 "$cli" host "$mesh" --port 0 --seconds 3600 > "$out/host.out" 2> "$out/host.err" &
  host_pid=$!
  wait_for "$out/host.out" '^hosting' 600 || { echo "host did not start: $(tail -3 "$out/host.err")"; continue; }
  n=$(sed -n 's/^hosting .*: \([0-9]*\) vertices.*/\1/p' "$out/host.out")
  port=$(sed -n 's/.*TCP port \([0-9]*\),.*/\1/p' "$out/host.out")
  fp=$(sed -n 's/.*--fingerprint \(.*\)$/\1/p' "$out/host.out" | head -1)
  echo "host ready: $n vertices; $(machine)"
  for level in 5% full; do
    : > "$out/gui.err"
    t0=$(now)
    SHAPECAST_STALL_MS=100 LIBGL_ALWAYS_SOFTWARE=1 nice -n 5 xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
      /usr/bin/time -v -o "$out/gui.time" "$bin/shapecast" --join "127.0.0.1:$port" --fingerprint "$fp" \
      --name "gui$level" --level "$level" > "$out/gui.out" 2> "$out/gui.err" &
    xvfb=$!
    for _ in $(seq 50); do gui_pid=$(pgrep -x shapecast -P "$(pgrep -d, -P $xvfb)" 2> /dev/null | head -1); [[ -n $gui_pid ]] && break; sleep 0.1; done
    # at 5% the smallest level is the one asked for; at full the host sees n vertices once the full level is in
    want=$([[ $level == full ]] && echo "$n" || echo '[1-9][0-9]*')
    wait_for "$out/host.out" "^  gui$level ($want vertices)" 900 || echo "the host never saw the client at $want vertices"
    want=$(grep -m1 -o "^  gui$level ($want vertices" "$out/host.out" | sed 's/.*(//')
    t1=$(now)
    echo "$level: launch → the host has the client's figures at $want: $(python3 -c "print('%.1f s' % ($t1 - $t0))"); stalls: $(stalls "$out/gui.err" "$t0" "$t1" "$t0")"
    sleep 10
    t2=$(now)
    echo "$level: 10 s idle after it: $(stalls "$out/gui.err" "$t1" "$t2" "$t0")"
    if [[ $level == full ]]; then
      nice -n 5 "$cli" drive "127.0.0.1:$port" --fingerprint "$fp" --script "$root/docs/examples/dragon-drag.json" --json > "$out/drive.out" 2> "$out/drive.err"
      t3=$(now)
      echo "$level: drag ($(grep -o '"frames_sent":[0-9]*' "$out/drive.out"), $(python3 -c "print('%.1f s' % ($t3 - $t2))")): $(stalls "$out/gui.err" "$t2" "$t3" "$t0")"
      sleep 15
      t4=$(now)
      echo "$level: 15 s after the drag: $(stalls "$out/gui.err" "$t3" "$t4" "$t0")"
      echo "$level: the host's last figures of the client: $(grep "^  gui$level (" "$out/host.out" | tail -1 | sed 's/^ *//')"
    fi
    kill -TERM "$gui_pid" 2> /dev/null
    wait "$xvfb" 2> /dev/null
    [[ -n ${GUI_STALLS_KEEP:-} ]] && cp "$out/gui.err" "$GUI_STALLS_KEEP.$level.err"
    gui_pid=""
    echo "$level: client peak RSS $(gui_rss); $(machine)"
  done
  kill -INT "$host_pid"
  wait "$host_pid"
  host_pid=""
done
