#!/usr/bin/env bash
# Large meshes end to end (issue 19 item 3; figures in docs/benchmarks.md, "Large meshes end to end"): for each MESH,
# one step after the other (one process chain at a time, `nice`), each step's wall time and peak memory:
#   basis     shapecast-cli basis (cold when the basis cache, ~/.cache/shapecast/bases, has no entry; the cache is
#             then written and the later steps read it)
#   levels    the 5% display level and the 20k-triangle interactive proxy (shapecast-bench-decimation
#             --no-distance, meshoptimizer)
#   host      shapecast-cli host: launch to "hosting" (mesh read + cached basis + operators + listening); then each
#             level the host builds for a join (decimation, P, K = P·H, int16, encoding, SHA-256, compression: its
#             "level built" log line)
#   join 5%   shapecast-cli join --level n/20: level ready (connect → level decoded and installed), bytes read, the
#             client's peak RSS; then --level full
#   drag      shapecast-cli drive docs/examples/dragon-drag.json (181 frames at 30 fps; the driver joins at full
#             resolution, its anchors thinned within the host's work bound) while a 5% client watches: the host's
#             CPU per frame over the drag (/proc/PID/stat), frames the watcher applied
#   kernel    shapecast-bench-kernel at n/20 and at n (the client's X' = X̂' + K·Z, int16 K)
#   viewport  shapecast-bench-viewport under Xvfb with LIBGL_ALWAYS_SOFTWARE=1: the client's frame drawn in full
#             and through the proxy (--proxy-only), skipped without xvfb-run
# Peak memory: /usr/bin/time -v's maximum resident set (the host's: VmHWM from /proc after each step).
#   scripts/large-mesh-e2e.sh [MESH ...]   (default: assets/meshes/dragon_vrip.ply assets/meshes/dragon_1m.off)
#   SHAPECAST_BUILD_DIR picks another build (default build/).
set -u
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=${SHAPECAST_BUILD_DIR:-$root/build}/bin
cli=$bin/shapecast-cli
if [[ $# -eq 0 ]]; then set -- "$root/assets/meshes/dragon_vrip.ply" "$root/assets/meshes/dragon_1m.off"; fi
out=$(mktemp -d)
host_time_pid=""
cleanup() {
  [[ -n $host_time_pid ]] && kill -INT "$(pgrep -P "$host_time_pid")" 2>/dev/null
  rm -rf "$out"
}
trap cleanup EXIT

machine() {
  printf 'machine: %s, %s cores, %s GiB RAM; load average %s\n' "$(lscpu | sed -n 's/^Model name: *//p')" \
    "$(nproc)" "$(free -g | awk '/^Mem:/ {print $2}')" "$(cut -d' ' -f1-3 /proc/loadavg)"
}
# timed NAME CMD...: runs CMD (nice) under /usr/bin/time -v; stdout in $out/NAME.out, stderr in $out/NAME.err.
timed() { nice -n 5 /usr/bin/time -v -o "$out/$1.time" "${@:2}" > "$out/$1.out" 2> "$out/$1.err"; }
wall_s() { awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, a, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + a[i]; print s}' "$out/$1.time"; }
peak_mb() { awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$out/$1.time"; }
json() { python3 -c 'import json,sys; d=json.loads(open(sys.argv[1]).read().strip().splitlines()[-1]); print(eval(sys.argv[2], {}, d))' "$@"; }
cpu_ticks() { awk '{print $14 + $15}' "/proc/$1/stat"; }              # the whole process
thread_ticks() { awk '{print $14 + $15}' "/proc/$1/task/$1/stat"; }    # its main (network) thread: solves, sends
hwm_mb() { awk '/VmHWM/ {printf "%.0f", $2 / 1024}' "/proc/$1/status"; }
row() { printf '| %s | %s | %s | %s |\n' "$1" "$2" "$3" "$4"; }

machine
for mesh in "$@"; do
  name=$(basename "$mesh")
  echo
  echo "## $name"
  echo
  row step "time (s)" "peak memory (MB)" notes
  row --- --- --- ---

  # basis
  timed basis "$cli" basis "$mesh" --json || { echo "basis failed: $(tail -3 "$out/basis.err")"; continue; }
  n=$(json "$out/basis.out" vertices)
  row basis "$(json "$out/basis.out" "'%.1f' % total_s")" "$(peak_mb basis)" \
    "$n vertices, m = $(json "$out/basis.out" m), $(json "$out/basis.out" "'cached' if cached else 'cold, ' + solver + ', eigensolve %.1f s' % eigensolve_s"), max residual $(json "$out/basis.out" "'%.1e' % max_residual"); load $(cut -d' ' -f1 /proc/loadavg)"

  # levels and proxy
  timed decimation "$bin/shapecast-bench-decimation" --no-legacy --no-distance --repeats 1 "$mesh"
  level_line=$(grep -m1 'level  after' "$out/decimation.out"); proxy_line=$(grep -m1 'proxy  after' "$out/decimation.out")
  row "5% level (decimation)" "$(awk '{print $4}' <<< "$level_line")" "$(peak_mb decimation) (both)" "$(awk '{print $6 " vertices"}' <<< "$level_line")"
  row "proxy" "$(awk '{print $4}' <<< "$proxy_line")" "" "$(awk '{print $8 " triangles"}' <<< "$proxy_line")"

  # host
  t0=$(date +%s.%N)
  nice -n 5 /usr/bin/time -v -o "$out/host.time" "$cli" host "$mesh" --port 0 --seconds 3600 > "$out/host.out" 2> "$out/host.err" &
  host_time_pid=$!
  for _ in $(seq 1200); do grep -q '^hosting' "$out/host.out" 2> /dev/null && break; sleep 0.1; done
  t1=$(date +%s.%N)
  host_pid=$(pgrep -P "$host_time_pid")
  port=$(sed -n 's/.*TCP port \([0-9]*\),.*/\1/p' "$out/host.out"); fp=$(sed -n 's/.*--fingerprint \(.*\)$/\1/p' "$out/host.out")
  if [[ -z $port ]]; then echo "host did not start: $(tail -3 "$out/host.err")"; continue; fi
  row "host start → ready" "$(python3 -c "print('%.1f' % ($t1 - $t0))")" "$(hwm_mb "$host_pid")" "read, cached basis, operators, listening"

  # joins
  n5=$((n / 20))
  for level in "$n5" full; do
    label=$([[ $level == full ]] && echo "full" || echo "5%")
    timed "join-$label" "$cli" join "127.0.0.1:$port" --fingerprint "$fp" --name "e2e-$label" --level "$level" --seconds 2 --json \
      || { echo "join $label failed: $(tail -3 "$out/join-$label.err")"; continue; }
    lv=$(json "$out/join-$label.out" level_vertices)
    built=$(grep "level built: $lv vertices" "$out/host.out" | tail -1 | sed 's/.*level built: [0-9]* vertices, //')
    row "join $label: level ready" "$(json "$out/join-$label.out" "'%.1f' % level_ready_s")" "$(peak_mb "join-$label") client, $(hwm_mb "$host_pid") host" \
      "$(json "$out/join-$label.out" "'%d vertices, %.1f MB read' % (level_vertices, level_ready_stream_bytes / 1e6)"); host built it: $built"
  done

  # drag: a 5% client watches, and the desktop client (Xvfb, software GL) shows the full level, while the driver
  # plays the script; the desktop client says each event-loop stall of 250 ms or more (SHAPECAST_STALL_MS; with
  # llvmpipe on a loaded machine a frame alone can take 100 ms)
  nice -n 5 "$cli" join "127.0.0.1:$port" --fingerprint "$fp" --name watcher --level "$n5" --json > "$out/watch.out" 2> "$out/watch.err" &
  watcher=$!
  gui=""
  if command -v xvfb-run > /dev/null && [[ -x $bin/shapecast ]]; then
    g0=$(date +%s.%N)
    SHAPECAST_STALL_MS=250 LIBGL_ALWAYS_SOFTWARE=1 nice -n 5 /usr/bin/time -v -o "$out/gui.time" xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
      "$bin/shapecast" --join "127.0.0.1:$port" --fingerprint "$fp" --name gui --level full > "$out/gui.out" 2> "$out/gui.err" &
    gui=$!
    # ready when the host prints the desktop client's first statistics with the full vertex count
    for _ in $(seq 6000); do grep -q "^  gui ($n vertices)" "$out/host.out" 2> /dev/null && break; kill -0 $gui 2> /dev/null || break; sleep 0.1; done
    g1=$(date +%s.%N)
  fi
  for _ in $(seq 600); do grep -q 'joined as peer' "$out/watch.err" 2> /dev/null && break; sleep 0.1; done
  nice -n 5 /usr/bin/time -v -o "$out/drive.time" "$cli" drive "127.0.0.1:$port" --fingerprint "$fp" --script "$root/docs/examples/dragon-drag.json" --json > "$out/drive.out" 2> "$out/drive.err" &
  driver=$!
  for _ in $(seq 3000); do grep -q 'lock held' "$out/drive.err" 2> /dev/null && break; kill -0 $driver 2> /dev/null || break; sleep 0.05; done
  c0=$(cpu_ticks "$host_pid"); m0=$(thread_ticks "$host_pid"); d0=$(date +%s.%N)
  wait $driver
  c1=$(cpu_ticks "$host_pid"); m1=$(thread_ticks "$host_pid"); d1=$(date +%s.%N)
  sleep 1
  kill -INT $watcher; wait $watcher
  frames=$(json "$out/drive.out" frames_sent 2> /dev/null || echo 0)
  tick=$(getconf CLK_TCK)
  row "drag (host)" "$(python3 -c "print('%.1f' % ($d1 - $d0))")" "$(hwm_mb "$host_pid") host, $(peak_mb drive) driver" \
    "$frames frames sent; host main thread $(python3 -c "f=max($frames,1); print('%.2f ms CPU per frame, whole process %.0f%% of a core (level builds included)' % (1e3*($m1-$m0)/$tick/f, 100*($c1-$c0)/$tick/max($d1-$d0,1e-9)))"); $(grep -o 'keeping one anchor in [0-9]* ([0-9]*)' "$out/drive.err" || echo 'anchors as given'); watcher applied $(json "$out/watch.out" frames_applied) frames"
  if [[ -n $gui ]]; then
    for p in $(pgrep -P "$(pgrep -P $gui)"); do [[ $(cat "/proc/$p/comm" 2> /dev/null) == shapecast ]] && kill -TERM "$p"; done
    wait $gui 2> /dev/null
    stalls=$(grep -c 'event loop stalled' "$out/gui.err")
    longest=$(grep -o 'stalled for [0-9]* ms' "$out/gui.err" | awk '{print $3}' | sort -n | tail -1)
    row "desktop client (full level, llvmpipe)" "$(python3 -c "print('%.1f' % ($g1 - $g0))")" "$(peak_mb gui) (Xvfb + shapecast)" \
      "launch → host sees its figures at $n vertices; $stalls event-loop stalls ≥ 250 ms$([[ -n $longest ]] && echo ", longest $longest ms"): $(grep -o 'stalled for [0-9]* ms (at [0-9.]* s)' "$out/gui.err" | sed 's/stalled for //' | tr '\n' ';')"
  fi
  kill -INT "$host_pid"; wait "$host_time_pid"; host_time_pid=""
  row "host (whole run)" "" "$(peak_mb host)" "$(grep -c 'level built' "$out/host.out") levels built: $(grep 'level built' "$out/host.out" | sed 's/.*level built: //' | tr '\n' ';')"

  # client kernel
  for k in "$n5" "$n"; do
    timed kernel "$bin/shapecast-bench-kernel" "$k" 100 30
    line=$(grep -m1 'int16 .*threads 1 ' "$out/kernel.out")
    row "client kernel n' = $k" "$(sed 's/.*median \([0-9.]*\) ms.*/\1/' <<< "$line") ms" "$(peak_mb kernel)" \
      "median per frame, int16 K, 1 thread (thread CPU $(sed 's/.*calling thread \([0-9.]*\) ms.*/\1/' <<< "$line") ms)"
    sed 's/^/    /' "$out/kernel.out" | grep -v machine >&2
  done

  # viewport (GUI frame, software GL)
  if command -v xvfb-run > /dev/null && [[ -x $bin/shapecast-bench-viewport ]]; then
    LIBGL_ALWAYS_SOFTWARE=1 timed viewport xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$bin/shapecast-bench-viewport" --frames 10 "$mesh"
    grep -E 'proxy|cpu|gpu|static' "$out/viewport.out" | sed 's/^/    /' >&2
    row "viewport (llvmpipe)" "" "$(peak_mb viewport)" "frame median / p90 ms: $(grep -E '^  [a-z0-9+]+ +frame median' "$out/viewport.out" | awk '{printf "%s %s / %s; ", $1, $4, $7}')"
  fi
  machine
done
