#!/usr/bin/env bash
# Real data through its own map, backwards (docs/maps.md, "Localisation"): `keylo run` saves a
# map of a KITTI-style sequence, then `keylo localise` plays the same scans in reverse order
# (a folder of links, times counting up again) from the mapping run's last pose perturbed by
# 0.2 m and 3°, and the poses are compared with the mapping run's.
#
#   scripts/bench/localise_backwards.sh SEQUENCE_DIR OUT_DIR [LOCALISE_ARGS...]
#   e.g. ../shared/data/kitti_mini/00 /tmp/kback --set localise.method=ndt
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
SEQ="$(cd "${1:?usage: localise_backwards.sh SEQUENCE_DIR OUT_DIR}" && pwd)"
OUT="${2:?usage: localise_backwards.sh SEQUENCE_DIR OUT_DIR}"
shift 2
BIN="$ROOT/target/release/keylo"
cd "$ROOT"
cargo build -q --release --locked -p keylo-cli
rm -rf "$OUT" && mkdir -p "$OUT/rev/velodyne"
"$BIN" -q run --data "$SEQ" --out "$OUT/run" --map-out "$OUT/map" --set output.exact=true
scans=("$SEQ"/velodyne/*.bin)
n=${#scans[@]}
for ((i = 0; i < n; i++)); do
    ln -s "${scans[n - 1 - i]}" "$OUT/rev/velodyne/$(printf '%06d' "$i").bin"
    awk -v i="$i" 'BEGIN { printf "%e\n", 0.1 * i }' >> "$OUT/rev/times.txt"
done
cp "$SEQ/calib.txt" "$OUT/rev/" 2> /dev/null || true
# The mapping run's last pose, moved 0.2 m along x and turned 3° about z.
start=$(python3 - "$OUT/run/trajectory.tum" <<'PY'
import math, sys
rows = [l.split() for l in open(sys.argv[1]) if l.strip() and not l.startswith("#")]
x, y, z, qx, qy, qz, qw = map(float, rows[-1][1:])
h = math.radians(3) / 2
dq = (0.0, 0.0, math.sin(h), math.cos(h))  # q · dq (a turn about the sensor's z)
nx = qw * dq[0] + qx * dq[3] + qy * dq[2] - qz * dq[1]
ny = qw * dq[1] - qx * dq[2] + qy * dq[3] + qz * dq[0]
nz = qw * dq[2] + qx * dq[1] - qy * dq[0] + qz * dq[3]
nw = qw * dq[3] - qx * dq[0] - qy * dq[1] - qz * dq[2]
print(x + 0.2, y, z, nx, ny, nz, nw)
PY
)
"$BIN" localise "$OUT/map" --data "$OUT/rev" --initial-pose "$start" --out "$OUT/loc" "$@"
python3 - "$OUT/run/trajectory.tum" "$OUT/loc/trajectory.tum" <<'PY'
import math, sys
read = lambda p: [list(map(float, l.split())) for l in open(p) if l.strip() and not l.startswith("#")]
run, loc = read(sys.argv[1]), read(sys.argv[2])
loc = loc[::-1]  # frame k of the reversed run is scan n-1-k
err = [math.dist(a[1:4], b[1:4]) for a, b in zip(run, loc)]
ang = [2 * math.degrees(math.acos(min(1.0, abs(sum(p * q for p, q in zip(a[4:], b[4:])))))) for a, b in zip(run, loc)]
print(f"{len(err)} scans backwards: position vs the mapping run's: max {max(err):.3f} m, "
      f"mean {sum(err) / len(err):.3f} m (first localised scan {err[-1]:.3f} m); "
      f"rotation max {max(ang):.2f} deg")
PY
