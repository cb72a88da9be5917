#!/usr/bin/env bash
# The screenshot in docs/report.md ("Watching a run live"): a `keylo run --view` watched in
# Foxglove Studio, the open-source (MPL-2.0) `@foxglove/studio-base` 1.48.0 from npm run in
# headless Chromium (Debian's), on 127.0.0.1 only. Not part of the tests: it downloads 36 MB.
#
#   scripts/view/screenshot.sh [OUT.png]     (default docs/report/view-live.png; ~2 min)
#
# KEYLO: the keylo binary (default target/release/keylo). Files go to target/view-web.
# Studio 1.48 offers the WebSocket subprotocol `foxglove.websocket.v1`, the Foxglove SDK's
# server answers to its newer name `foxglove.sdk.v1` (same messages): the host page
# (screenshot/index.html) renames it. Lichtblick since its PR #819 and the Foxglove app speak
# `foxglove.sdk.v1` themselves.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KEYLO="${KEYLO:-$ROOT/target/release/keylo}"
OUT="${1:-$ROOT/docs/report/view-live.png}"
WEB="$ROOT/target/view-web"
VENV="$ROOT/target/view-venv"
log() { echo "[screenshot] $*" >&2; }
command -v chromium > /dev/null || { log "needs Debian's chromium (scripts/setup-browser.sh)"; exit 1; }
if [ ! -f "$WEB/assets/index.js" ]; then
    log "npm pack @foxglove/studio-base@1.48.0 react@17.0.2 react-dom@17.0.2"
    mkdir -p "$WEB/pack"
    (cd "$WEB/pack" && npm pack --silent @foxglove/studio-base@1.48.0 react@17.0.2 react-dom@17.0.2 > /dev/null)
    tar xzf "$WEB/pack/foxglove-studio-base-1.48.0.tgz" -C "$WEB/pack"
    mv "$WEB/pack/package/assets" "$WEB/assets"
    for p in react react-dom; do
        mkdir -p "$WEB/$p" && tar xzf "$WEB/pack/$p-17.0.2.tgz" -C "$WEB/$p" --strip-components=1
    done
    rm -rf "$WEB/pack"
fi
cp "$HERE/screenshot/index.html" "$HERE/screenshot/app.js" "$HERE/screenshot/layout.json" "$WEB/"
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/pip" install -q --disable-pip-version-check "playwright>=1.40"
port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
HTTP_PORT="$(port)"; WS_PORT="$(port)"
WORK="$(mktemp -d)"
python3 "$HERE/screenshot/serve.py" "$WEB" "$HTTP_PORT" 2> "$WORK/http.log" &
http=$!
# The indoor AKAZE pipeline on the simulated lab, played at the sensor's rate so the run is
# going on while the page loads and the picture is taken.
"$KEYLO" run "$ROOT/configs/paper/indoor-akaze-kiss-icp.toml" --set source.kind=sim \
    --set source.scene=lab --set source.frames=400 --realtime --out "$WORK/run" -q \
    --view "127.0.0.1:$WS_PORT" --view-wait 120 --view-map-every 5 2> "$WORK/keylo.log" &
run=$!
trap 'kill $http $run 2> /dev/null || true; rm -rf "$WORK"' EXIT
sleep 1
URL="http://127.0.0.1:$HTTP_PORT/index.html?ds=foxglove-websocket&ds.url=ws://127.0.0.1:$WS_PORT&layoutId=shot"
mkdir -p "$(dirname "$OUT")"
"$VENV/bin/python" "$HERE/screenshot/shot.py" "$URL" "$OUT" "${WAIT:-25}"
log "wrote $OUT"
