#!/usr/bin/env bash
# keylo NDT vs PCL 1.13 NDT on the fixture pairs (tests/fixtures/ndt), one run: pose
# difference, iterations, ms per alignment (target build + align, median of REPEAT runs) and
# the ratio PCL/keylo, for keylo on all cores and on one thread. "PCL self" is how far PCL's
# own result moves when the source is shifted by 10 µm (its path sensitivity).
#   scripts/bench/ndt_vs_pcl.sh [CASES_FILE]   (default: every pair × res × eps below)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
fx="$root/tests/fixtures/ndt"
pcl="$(bash "$root/../shared/peers/pcl_ndt/build.sh")"
cargo build -q --release -p keylo-registration --example ndt_pair --manifest-path "$root/Cargo.toml"
keylo="$root/target/release/examples/ndt_pair"
cmp="python3 $root/scripts/bench/compare_poses.py"
repeat="${REPEAT:-3}"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT

median_ms() { # CMD... → median of the "ms" field over $repeat runs; pose of the last run in $tmp/pose
  local t=()
  for _ in $(seq "$repeat"); do
    "$@" 2>/dev/null > "$tmp/out"
    t+=("$(sed -n 2p "$tmp/out" | awk '{print $4}')")
  done
  head -1 "$tmp/out" > "$tmp/pose"; sed -n 2p "$tmp/out" | awk '{print $2}' > "$tmp/iters"
  printf '%s\n' "${t[@]}" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'
}

echo "| pair | res | eps | PCL iters | keylo iters | Δt (m) | Δr (°) | PCL self Δt / Δr | PCL ms | keylo ms | ratio | keylo 1-thread ms | ratio |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for pair in real lab road; do
  for res in 0.5 1.0 2.0; do
    for eps in 0.01 0.001 0.0001; do
      opts=(--res "$res" --step 0.1 --eps "$eps" --iters 35)
      src="$fx/${pair}_source.bin"; tgt="$fx/${pair}_target.bin"
      pms="$(median_ms "$pcl" pair "$src" "$tgt" "${opts[@]}")"; cp "$tmp/pose" "$tmp/pcl"; pit="$(cat "$tmp/iters")"
      kms="$(median_ms "$keylo" pair "$src" "$tgt" "${opts[@]}")"; cp "$tmp/pose" "$tmp/keylo"; kit="$(cat "$tmp/iters")"
      k1="$(median_ms "$keylo" pair "$src" "$tgt" "${opts[@]}" --threads 1)"
      python3 "$root/scripts/bench/perturb_bin.py" "$src" "$tmp/shift.bin" 0.00001
      "$pcl" pair "$tmp/shift.bin" "$tgt" "${opts[@]}" 2>/dev/null | head -1 > "$tmp/pcl_shift"
      d="$($cmp "$tmp/pcl" "$tmp/keylo")"; s="$($cmp "$tmp/pcl" "$tmp/pcl_shift")"
      dt="$(echo "$d" | awk '{print $4}')"; dr="$(echo "$d" | awk '{print $6}')"
      st="$(echo "$s" | awk '{print $4}')"; sr="$(echo "$s" | awk '{print $6}')"
      r="$(awk -v a="$pms" -v b="$kms" 'BEGIN {printf "%.1f", a / b}')"
      r1="$(awk -v a="$pms" -v b="$k1" 'BEGIN {printf "%.1f", a / b}')"
      echo "| $pair | $res | $eps | $pit | $kit | $dt | $dr | $st / $sr | $pms | $kms | $r× | $k1 | $r1× |"
    done
  done
done
