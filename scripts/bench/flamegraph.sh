#!/usr/bin/env bash
# Where the time goes (docs/results/profile/): a flame graph (SVG) of `keylo run` for each of
# the raw, AKAZE, SuperPoint and hybrid pipelines on the simulated lab (`ouster` appearance,
# FRAMES frames at 1024×128), sampled with Linux `perf` (DWARF call graphs) and drawn with
# `inferno` (`cargo install inferno`).
#   bash scripts/bench/flamegraph.sh [OUT]      # OUT defaults to docs/results/profile; ~1.5 min
# Needs: perf (Debian `linux-perf`) allowed to sample this process (perf_event_paranoid <= 2),
# inferno-collapse-perf and inferno-flamegraph on PATH (or in ~/.cargo/bin).
set -euo pipefail
cd "$(dirname "$0")/../.."
keylo=${KEYLO:-target/release/keylo}
out=${1:-docs/results/profile}
frames=${FRAMES:-200}
export PATH="$PATH:$HOME/.cargo/bin"
for tool in perf inferno-collapse-perf inferno-flamegraph; do
    command -v "$tool" > /dev/null || { echo "error: $tool not found (see the header of $0)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
"$keylo" -q sim --scene lab --frames "$frames" --set appearance=ouster --out "$work/lab"
P=configs/paper
for name in raw akaze superpoint hybrid; do
    case $name in
        raw) config=$P/raw-kiss-icp.toml ;;
        akaze) config=$P/indoor-akaze-kiss-icp.toml ;;
        superpoint) config=$P/indoor-superpoint-kiss-icp.toml ;;
        hybrid) config=$P/indoor-akaze-hybrid.toml ;;
    esac
    perf record -q -F 199 --call-graph dwarf,16384 -o "$work/perf.data" -- \
        "$keylo" -q run "$config" --data "$work/lab" --out "$work/run-$name" --prefetch 0 2> /dev/null
    perf script -i "$work/perf.data" 2> /dev/null | inferno-collapse-perf > "$work/$name.folded"
    inferno-flamegraph --title "keylo run $(basename "$config") — simulated lab, $frames frames" \
        --width 1400 --minwidth 1.5 < "$work/$name.folded" > "$out/$name.svg"
    # The heaviest keylo functions (time including callees) and the heaviest leaves (self
    # time), for the text of docs/results/profile.md.
    python3 - "$work/$name.folded" <<'PY' | tee "$out/$name-top.txt"
import collections, re, sys
total, incl, leaf = 0, collections.Counter(), collections.Counter()
for line in open(sys.argv[1]):
    stack, n = line.rsplit(" ", 1)
    n = int(n); total += n
    frames = stack.split(";")
    leaf[frames[-1][:120]] += n
    for f in set(frames):
        if re.match(r"<?keylo", f):
            incl[f[:120]] += n
print("keylo functions, time including callees:")
for f, n in incl.most_common(15):
    print(f"{100 * n / total:5.1f} %  {f}")
print("leaves, self time:")
for f, n in leaf.most_common(12):
    print(f"{100 * n / total:5.1f} %  {f}")
PY
    rm -f "$work/perf.data"
    echo "$name -> $out/$name.svg"
done
