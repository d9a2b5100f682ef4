#!/usr/bin/env bash
# Fan-out through NATS, by hand (issue 18; results in docs/benchmarks.md): a local nats-server (nats-local.sh), a
# host with --nats (MESH, m = 50), N `watch` processes pinned to the host, and one scripted drag (docs/examples/
# dragon-drag.json, 181 frames at 30 fps) played by `drive`. Prints one JSON object: viewers, the smallest fraction
# of frames a viewer got, latency (one machine: host stamp → viewer applied), the host's and the server's CPU over
# the drag (% of one core, /proc/PID/stat) and the relay bytes the host published per frame (keyframes included).
#   scripts/relay-fanout.sh N [MESH]      (default MESH: assets/meshes/dragon_vrip_res4.ply; SHAPECAST_CLI=… picks
#   another shapecast-cli)
set -u
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
N=$1; MESH=${2:-$root/assets/meshes/dragon_vrip_res4.ply}
cli=${SHAPECAST_CLI:-$root/build/bin/shapecast-cli}
out=$(mktemp -d); trap 'rm -rf "$out"' EXIT
"$root/scripts/nats-local.sh" fan > $out/nl.out 2>&1 &
nl=$!; sleep 1.5
URL=$(sed -n 's/^nats-server [0-9]* on \([^ ]*\) .*/\1/p' $out/nl.out); DIR=$(sed -n 's/.*(folder \(.*\))/\1/p' $out/nl.out)
NPID=$(sed -n 's/^nats-server \([0-9]*\) on.*/\1/p' $out/nl.out)
$cli host $MESH --port 0 --m 50 --seconds 60 --nats $URL --session fan --nats-user host --nats-password-file $DIR/host.pw > $out/host.out 2>&1 &
host=$!
for i in $(seq 30); do grep -q relaying $out/host.out 2>/dev/null && break; sleep 1; done
FP=$(sed -n 's/.*--pin \(.*\)$/\1/p' $out/host.out); PORT=$(sed -n 's/.*TCP port \([0-9]*\),.*/\1/p' $out/host.out)
for i in $(seq $N); do $cli watch --nats $URL --session fan --nats-user viewer --nats-password-file $DIR/viewer.pw --pin $FP --seconds 14 --json > $out/w$i.json 2>&1 & done
sleep 3
h0=$(awk '{print $14+$15}' /proc/$host/stat); s0=$(awk '{print $14+$15}' /proc/$NPID/stat); t0=$(date +%s.%N)
$cli drive 127.0.0.1:$PORT --script $root/docs/examples/dragon-drag.json --fingerprint $FP > $out/drive.out 2>&1
h1=$(awk '{print $14+$15}' /proc/$host/stat); s1=$(awk '{print $14+$15}' /proc/$NPID/stat); t1=$(date +%s.%N)
wait $(jobs -p | grep -v -e "^$host$" -e "^$nl$") 2>/dev/null
kill -INT $host; wait $host
kill $NPID; wait $nl 2>/dev/null
python3 - "$out" "$N" "$h0" "$h1" "$s0" "$s1" "$t0" "$t1" <<'PY'
import json,sys,glob,re,os
out,N,h0,h1,s0,s1,t0,t1=sys.argv[1],int(sys.argv[2]),*map(float,sys.argv[3:])
tick=os.sysconf('SC_CLK_TCK'); wall=t1-t0
rows=[]
for f in glob.glob(out+'/w*.json'):
    try: rows.append(json.loads(open(f).read().strip().splitlines()[-1]))
    except Exception as e: print('bad',f,open(f).read()[:200])
host=open(out+'/host.out').read()
m=re.search(r'relay: (\d+) frames, (\d+) keyframes, (\d+) bytes published',host)
frames,keys,byts=map(int,m.groups()) if m else (0,0,0)
applied=[r['applied'] for r in rows]; lost=[r['lost'] for r in rows]; p99=sorted(r['latency_p99_ms'] for r in rows); p50=sorted(r['latency_p50_ms'] for r in rows)
print(json.dumps({'viewers':N,'reported':len(rows),'frames_published':frames,'min_applied':min(applied),'max_lost':max(lost),
 'min_delivered_fraction':min(a/(a+l) if a+l else 0 for a,l in zip(applied,lost)),
 'latency_p50_ms_median':p50[len(p50)//2],'latency_p99_ms_median':p99[len(p99)//2],'latency_p99_ms':p99[-1],
 'host_cpu_pct':100*(h1-h0)/tick/wall,'server_cpu_pct':100*(s1-s0)/tick/wall,'drag_seconds':wall,
 'host_upload_bytes_per_frame':byts/frames if frames else 0, 'bad_signature':sum(r['bad_signature'] for r in rows)}))
PY
