#!/usr/bin/env bash
# A brush stroke's GUI-thread stalls on a large mesh (issue 19 item 3; figures in docs/benchmarks.md, "Patched
# pictures"). Opens MESH in the desktop app (`shapecast MESH`) under Xvfb with software GL (LIBGL_ALWAYS_SOFTWARE=1)
# and SHAPECAST_STALL_MS=30, waits 35 s for the mesh and its picture, then drives the pointer with xdotool: the
# Handle tool, a stroke of 25 moves 40 ms apart across the mesh (about 1.3 s), and 4 s later a screenshot. Twice per
# run: `still` (the stroke on a still view) and `orbit` (an orbit drag first, the stroke 0.2 s after it). Prints, per
# stroke, the event-loop gaps of 30 ms or more from its press to 1 s after its release, with the machine and the load.
#   scripts/brush-stalls.sh [MESH]   (default: assets/meshes/dragon_1m.off; the window is 1280x1024 with the
#                                    default layout, the stroke starts at (600, 450) on screen)
#   SHAPECAST_BUILD_DIR picks another build (default build/), e.g. a build of the previous commit for "before".
#   BRUSH_STALLS_KEEP=PREFIX keeps each run's stderr and screenshot as PREFIX.still.err, PREFIX.still.png, ...
# Needs xdotool and ImageMagick's `import` (apt install xdotool imagemagick): benchmark tools, not the project's.
set -u
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bin=${SHAPECAST_BUILD_DIR:-$root/build}/bin/shapecast
mesh=${1:-$root/assets/meshes/dragon_1m.off}
for tool in xdotool import xvfb-run; do
  command -v "$tool" > /dev/null || { echo "brush-stalls: needs $tool (apt install xdotool imagemagick xvfb)" >&2; exit 2; }
done
[[ -x $bin ]] || { echo "brush-stalls: no $bin (build first)" >&2; exit 2; }
[[ -f $mesh ]] || { echo "brush-stalls: no $mesh (scripts/setup.sh fetches it)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# The part that runs inside the X server: stroke.sh KIND (still | orbit)
cat > "$out/stroke.sh" << 'EOF'
#!/usr/bin/env bash
set -u
kind=$1
SHAPECAST_STALL_MS=30 LIBGL_ALWAYS_SOFTWARE=1 "$BIN" "$MESH" 2> "$OUT/$kind.err" &
app=$!
sleep 35
if [[ $kind == orbit ]]; then
  xdotool mousemove 600 300 mousedown 1
  for _ in $(seq 10); do xdotool mousemove_relative -- 4 0; sleep 0.03; done
  xdotool mouseup 1
  sleep 0.1
fi
xdotool mousemove 89 34 click 1  # the toolbar's Handle tool
[[ $kind == orbit ]] && sleep 0.2 || sleep 2
t0=$(date +%s.%N)
xdotool mousemove 600 450 mousedown 1
for _ in $(seq 25); do xdotool mousemove_relative -- 6 3; sleep 0.04; done
xdotool mouseup 1
t1=$(date +%s.%N)
sleep 4
import -window root "$OUT/$kind.png"
echo "stroke $t0 $t1" >> "$OUT/$kind.err"
kill "$app"
wait "$app"
EOF
chmod +x "$out/stroke.sh"

machine() {
  printf 'machine: %s, %s cores, %s GiB RAM; load average %s\n' "$(lscpu | sed -n 's/^Model name: *//p')" \
    "$(nproc)" "$(free -g | awk '/^Mem:/ {print $2}')" "$(cut -d' ' -f1-3 /proc/loadavg)"
}

machine
for kind in still orbit; do
  BIN=$bin MESH=$mesh OUT=$out timeout 150 xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$out/stroke.sh" "$kind" \
    > /dev/null 2>&1
  python3 - "$out/$kind.err" "$kind" << 'PY'
import re, sys
text = open(sys.argv[1]).read()
start = re.search(r'from unix time ([0-9.]+)', text)
stroke = re.search(r'stroke ([0-9.]+) ([0-9.]+)', text)
if not start or not stroke:
    sys.exit('%s: no stroke measured (the app did not start, or xdotool failed)' % sys.argv[2])
t0, t1 = map(float, stroke.groups())
gaps = [(int(ms), float(start.group(1)) + float(at))
        for ms, at in re.findall(r'stalled for ([0-9]+) ms \(at ([0-9.]+) s\)', text)]
inside = [ms for ms, at in gaps if t0 - 0.1 <= at < t1 + 1.0]
print('%s: stroke %.2f s; gaps >= 30 ms from its press to 1 s after: %d, longest %s, sum %d ms (%s)' % (
    sys.argv[2], t1 - t0, len(inside), ('%d ms' % max(inside)) if inside else '-', sum(inside),
    ' '.join(map(str, inside)) or '-'))
PY
  if [[ -n ${BRUSH_STALLS_KEEP:-} ]]; then
    cp "$out/$kind.err" "$BRUSH_STALLS_KEEP.$kind.err"
    cp "$out/$kind.png" "$BRUSH_STALLS_KEEP.$kind.png" 2> /dev/null
  fi
done
machine
