#!/usr/bin/env bash
# Soak: N simulated lab frames (default 10000) through the raw-cloud and the AKAZE keypoint
# pipelines, both at once; then a table of resident memory and local-map size every STEP frames
# from each run's frames.csv (written frame by frame, so the table also works on a run that is
# still going or was stopped).
#   scripts/soak.sh [FRAMES] [OUT] [STEP]      (keylo from target/release, or $KEYLO)
# SOAK_PIPELINES="akaze" runs (or tabulates) one pipeline only; SOAK_SET="--set K=V ..." adds
# overrides to every run (e.g. SOAK_SET="--set registrar.max_voxel_age=300").
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
N="${1:-10000}"; OUT="${2:-/tmp/keylo-soak}"; STEP="${3:-1000}"
K="${KEYLO:-$ROOT/target/release/keylo}"
P="$ROOT/configs/paper"
PIPELINES="${SOAK_PIPELINES:-raw akaze}"
read -r -a EXTRA <<< "${SOAK_SET:-}"
SIM=(--set source.kind=sim --set source.scene=lab --set source.frames="$N" --set source.columns=1024 "${EXTRA[@]}")
if [ "${SOAK_TABLE_ONLY:-0}" != 1 ]; then
  mkdir -p "$OUT"
  for run in $PIPELINES; do
    case "$run" in
      raw) args=("$P/raw-kiss-icp.toml") ;;
      akaze) args=("$P/indoor-akaze-kiss-icp.toml" --set detector.threshold=0.0001) ;;
      *) echo "unknown pipeline $run (raw, akaze)" >&2; exit 2 ;;
    esac
    /usr/bin/time -v "$K" run "${args[@]}" "${SIM[@]}" --out "$OUT/$run" -q > "$OUT/$run.log" 2>&1 &
  done
  wait
fi
for run in $PIPELINES; do
  echo "== $run: frame, RSS MB (max over the block), map points (at its end), mean odometry ms"
  awk -F, -v step="$STEP" 'NR == 1 { next }
    { b = int($1 / step); if ($8 > rss[b]) rss[b] = $8; map[b] = $6; ms[b] += $7; n[b]++; last = b }
    END { for (i = 0; i <= last; i++) if (n[i])
            printf "%6d-%-6d %8.1f %10d %8.1f\n", i * step, i * step + n[i] - 1, rss[i], map[i], ms[i] / n[i] }' \
    "$OUT/$run/frames.csv"
done
