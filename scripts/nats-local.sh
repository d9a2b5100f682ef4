#!/usr/bin/env bash
# Starts a local nats-server for a relayed session (issue 18; README "Viewers through NATS"): loopback only, a
# random port, JetStream in a temporary folder, one host user and one viewer user with the relay's permissions
# (the same layout as tests/support/nats_server_process.cpp; a plain `authorization` block, never mixed with
# `accounts`: advisory GHSA-fr2g-9hjm-wr23). Prints the URL, the password files and the host and watch commands;
# Ctrl-C stops the server and removes the folder.
#   scripts/nats-local.sh [SESSION_ID]      (default: demo)
set -euo pipefail
sid=${1:-demo}
[[ $sid =~ ^[A-Za-z0-9_-]{1,32}$ ]] || { echo "session id: 1..32 of A-Z a-z 0-9 _ -" >&2; exit 2; }
server=$(command -v nats-server || echo /usr/sbin/nats-server)
[[ -x $server ]] || { echo "nats-server is not installed (Debian: apt install nats-server)" >&2; exit 1; }
dir=$(mktemp -d)
trap 'kill "${pid:-}" 2> /dev/null || true; wait "${pid:-}" 2> /dev/null || true; rm -rf "$dir"' EXIT
umask 077
head -c 18 /dev/urandom | base64 | tr -d '/+=' > "$dir/host.pw"
head -c 18 /dev/urandom | base64 | tr -d '/+=' > "$dir/viewer.pw"
stream="KV_sc_$sid"
levels="SC_${sid}_LEVELS"  # the level payloads (read-only for viewers)
cat > "$dir/nats.conf" << CONF
listen: 127.0.0.1:-1
jetstream { store_dir: "$dir/js" }
write_deadline: "2s"
max_pending: 8MB
authorization {
  users = [
    { user: "host", password: "$(cat "$dir/host.pw")", permissions: {
        publish: ["sc.$sid.>", "\$KV.sc_$sid.>", "\$JS.API.STREAM.CREATE.$stream", "\$JS.API.STREAM.UPDATE.$stream",
                  "\$JS.API.STREAM.INFO.$stream", "\$JS.API.STREAM.CREATE.$levels",
                  "\$JS.API.STREAM.UPDATE.$levels", "\$JS.API.STREAM.INFO.$levels"],
        subscribe: ["_INBOX.>", "sc.$sid.stats.>"] } }
    { user: "viewer", password: "$(cat "$dir/viewer.pw")", permissions: {
        publish: ["\$JS.API.STREAM.INFO.$stream", "\$JS.API.STREAM.MSG.GET.$stream",
                  "\$JS.API.DIRECT.GET.$stream.>", "sc.$sid.stats.>", "\$JS.API.STREAM.MSG.GET.$levels"],
        subscribe: ["sc.$sid.z", "_INBOX.>"] } }
  ]
}
CONF
"$server" -c "$dir/nats.conf" --ports_file_dir "$dir" > "$dir/nats-server.log" 2>&1 &
pid=$!
for _ in $(seq 100); do [[ -f $dir/nats-server_$pid.ports ]] && break; sleep 0.05; done
url=$(sed -n 's/.*"nats":\["\([^"]*\)".*/\1/p' "$dir/nats-server_$pid.ports" 2> /dev/null || true)
[[ -n $url ]] || { echo "nats-server did not start; its log:" >&2; cat "$dir/nats-server.log" >&2; exit 1; }
cat << TEXT
nats-server $pid on $url (folder $dir)
host:  build/bin/shapecast-cli host MESH --nats $url --session $sid --nats-user host --nats-password-file $dir/host.pw
watch: build/bin/shapecast-cli watch --nats $url --session $sid --nats-user viewer --nats-password-file $dir/viewer.pw --pin FINGERPRINT
Ctrl-C stops the server.
TEXT
wait "$pid"
