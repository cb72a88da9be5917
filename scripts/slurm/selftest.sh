#!/usr/bin/env bash
# The Slurm scripts tested on a real Slurm: starts a one-node cluster on this machine
# (scripts/slurm/cluster.sh: installs Debian's slurm-wlm and munge when missing), submits a
# 4-shard job array of a small `keylo compare` and of a small `keylo keypoints eval`, each with
# its merge job (--dependency=afterok), waits for them, checks that the merged tables are
# those of single-process runs (all but the timing columns), and stops the daemons it started.
#
#   bash scripts/slurm/selftest.sh          # KEYLO=path/to/keylo to test another binary
#
# Needs root (slurmd runs job steps as their user) and a release build (scripts/setup.sh).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
KEYLO="${KEYLO:-$ROOT/target/release/keylo}"
if [ ! -x "$KEYLO" ]; then
  echo "error: $KEYLO: no keylo binary; build it first (bash scripts/setup.sh)" >&2
  exit 2
fi
if [ "$(id -u)" -ne 0 ] && ! sudo -n true 2>/dev/null; then
  # The daemons need root; say so plainly rather than fail a machine that cannot give it.
  echo "slurm selftest: SKIPPED: needs root or password-less sudo (slurmd starts job steps as their user)" >&2
  exit 0
fi
work="$(mktemp -d /tmp/keylo-slurm.XXXXXX)"
# shellcheck source=cluster.sh
source "$ROOT/scripts/slurm/cluster.sh"
cleanup() {
  cluster_stop "$work/cluster"
  if [ -z "${KEEP:-}" ]; then rm -rf "$work"; else echo "kept $work" >&2; fi
}
trap cleanup EXIT
started=$(date +%s)
cluster_start "$work/cluster"
cd "$work"
"$KEYLO" sim --scene lab --frames 40 --out seq --set sensor=os1-64 --set columns=512 -q

compare=("$KEYLO" compare "$ROOT/configs/paper/raw-kiss-icp.toml"
  "$ROOT/configs/examples/corridor-voxel-kiss-icp.toml" --grid registrar.voxel_size=0.5,1.0
  --data seq --no-plots -q)
evaluate=("$KEYLO" keypoints eval --data seq --frames 40 --combos ORB_ORB,FAST_BRIEF,AKAZE_AKAZE
  --no-plots -q)
read -r c_array c_merge <<< "$(bash "$ROOT/scripts/slurm/submit.sh" 4 cmp -- "${compare[@]}")"
read -r e_array e_merge <<< "$(bash "$ROOT/scripts/slurm/submit.sh" 4 kp -- "${evaluate[@]}")"
cluster_log "submitted: compare array $c_array + merge $c_merge, eval array $e_array + merge $e_merge"

# The state of every job record of `id` (an array's tasks are records of their own).
states() { scontrol show job "$1" -o 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2 | sort | uniq -c | tr '\n' ' '; }
finished() { ! scontrol show job "$1" -o 2>/dev/null | grep -qE 'JobState=(PENDING|RUNNING|CONFIGURING|COMPLETING)'; }
for _ in $(seq 1 600); do
  if finished "$c_merge" && finished "$e_merge"; then break; fi
  sleep 1
done
status=0
for id in "$c_array" "$c_merge" "$e_array" "$e_merge"; do
  s="$(states "$id")"
  cluster_log "job $id: $s"
  if [ -z "$s" ] || echo "$s" | grep -qvE '^ *([0-9]+ COMPLETED *)+$'; then status=1; fi
done
if [ "$status" -ne 0 ]; then
  echo "error: a Slurm job did not complete; its log:" >&2
  tail -n 20 cmp/logs/*.out kp/logs/*.out >&2 || true
  exit 1
fi

cluster_log "single-process runs of the same studies"
"${compare[@]}" --out cmp-single
"${evaluate[@]}" --out kp-single
python3 - <<'PY'
import csv, json, sys
def runs(path):
    timing = {"cpu_percent", "peak_rss_mb", "odometry_hz", "rate_vs_raw", "resumed"}
    return [{k: v for k, v in r.items() if k not in timing} for r in json.load(open(path))["runs"]]
def rows(path):
    timing = {"detect_ms", "describe_ms", "match_ms", "time_ms"}
    return [{k: v for k, v in r.items() if k not in timing} for r in csv.DictReader(open(path))]
checks = [("compare", runs("cmp-single/compare.json"), runs("cmp/merged/compare.json")),
          ("keypoints eval", rows("kp-single/per_image.csv"), rows("kp/merged/per_image.csv"))]
for name, single, merged in checks:
    if not single or single != merged:
        sys.exit(f"error: {name}: the merged table differs from the single-process one "
                 f"({len(single)} against {len(merged)} rows)")
    print(f"[slurm] {name}: {len(merged)} rows of 4 shards merged = single process (all but timing columns)",
          file=sys.stderr)
PY
echo "slurm selftest: ok in $(( $(date +%s) - started )) s (compare ${c_array}+${c_merge}, keypoints eval ${e_array}+${e_merge})"
