#!/usr/bin/env bash
# Submits a keylo study as a Slurm job array of N shards plus a merge job that starts when
# every shard succeeded (`--dependency=afterok`); prints "ARRAY_JOB_ID MERGE_JOB_ID".
#
#   scripts/slurm/submit.sh N OUT [SBATCH_OPTION...] -- KEYLO SUBCOMMAND [ARGS...]
#
# e.g. scripts/slurm/submit.sh 8 /shared/study --partition=cpu --time=02:00:00 -- \
#        /opt/keylo/bin/keylo keypoints sweep --data /shared/tiers_signal --frames 1146
# (no --out and no --shard: each shard gets --shard I/N --out OUT/shard-I; the merge writes
# OUT/merged/).
# OUT must be on a file system every node sees. Logs: OUT/logs/. See docs/scale-out.md.
set -euo pipefail
if [ "$#" -lt 4 ]; then
  echo "usage: $0 N OUT [SBATCH_OPTION...] -- KEYLO SUBCOMMAND [ARGS...]" >&2
  exit 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
n="$1"; out="$2"; shift 2
opts=()
while [ "$#" -gt 0 ] && [ "$1" != "--" ]; do opts+=("$1"); shift; done
[ "${1:-}" = "--" ] || { echo "error: $0: no -- before the keylo command" >&2; exit 2; }
shift
case "$n" in ''|*[!0-9]*|0) echo "error: $0: N must be a positive whole number, not '$n'" >&2; exit 2 ;; esac
mkdir -p "$out/logs"
array=$(sbatch --parsable "${opts[@]}" --array="0-$((n - 1))" \
  --output="$out/logs/shard-%a.out" "$here/shard.sbatch" "$n" "$out" "$@")
array="${array%%;*}"
merge=$(sbatch --parsable "${opts[@]}" --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$out/logs/merge.out" "$here/merge.sbatch" "$n" "$out" "$@")
echo "$array ${merge%%;*}"
