#!/usr/bin/env bash
# keylo's live view as a person uses it: `keylo run --view` received by an independent client
# of the Foxglove WebSocket protocol (npm's @foxglove/ws-protocol, ws-client.mjs), and a
# viewer that hangs or goes away never holds the run up (docs/report.md, "Watching a run
# live"). The server listens on 127.0.0.1 only (TCP; no multicast, no UDP).
#
#   scripts/view/live-test.sh        (KEYLO: the keylo binary, default target/debug/keylo)
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
KEYLO="${KEYLO:-$ROOT/target/debug/keylo}"
log() { echo "[view-test] $*" >&2; }
if [ ! -d "$HERE/node_modules/@foxglove/ws-protocol" ]; then
    log "npm ci (@foxglove/ws-protocol, ws, protobufjs)"
    (cd "$HERE" && npm ci --no-audit --no-fund --loglevel=error)
fi
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
FRAMES=20
# The indoor AKAZE pipeline on the simulated lab: every stream (images and keypoints too).
RUN=("$KEYLO" run "$ROOT/configs/paper/indoor-akaze-kiss-icp.toml" --set source.kind=sim
     --set source.scene=lab --set "source.frames=$FRAMES" -q)
"${RUN[@]}" --out "$WORK/plain"

for mode in all stall drop; do
    # Every frame's large messages too (--view-hz 0): `all` counts them, and a stalled client's
    # socket and queue overflow within the first frames (2 MB of points each).
    "${RUN[@]}" --out "$WORK/$mode" --view 127.0.0.1:0 --view-wait 60 --view-hz 0 \
        2> "$WORK/$mode.err" &
    run=$!
    url=""
    for _ in $(seq 300); do
        url="$(grep -o 'ws://127\.0\.0\.1:[0-9]*' "$WORK/$mode.err" | head -1 || true)"
        [ -n "$url" ] && break
        sleep 0.1
    done
    [ -n "$url" ] || { cat "$WORK/$mode.err" >&2; log "keylo never said where it listens"; exit 1; }
    node "$HERE/ws-client.mjs" "$url" "$WORK/$mode.json" "$mode" &
    client=$!
    start=$(date +%s)
    if ! timeout 300 tail --pid="$run" -f /dev/null; then
        log "$mode: keylo did not finish within 300 s"; kill "$run" "$client" 2>/dev/null; exit 1
    fi
    rc=0; wait "$run" || rc=$?
    took=$(( $(date +%s) - start ))
    log "$mode: keylo exited $rc after $took s"
    [ "$rc" -eq 0 ] || { cat "$WORK/$mode.err" >&2; exit 1; }
    # The run and its end (the server waits at most 2 s for connections to close) are not
    # held up: the run without a viewer takes a few seconds here.
    [ "$took" -le 60 ] || { log "$mode: the run took $took s with this client"; exit 1; }
    # A stalled client never reads the close: stop it.
    kill "$client" 2>/dev/null || true
    wait "$client" 2>/dev/null || true
done
python3 "$HERE/check_live.py" "$WORK" "$FRAMES"
