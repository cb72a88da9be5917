#!/usr/bin/env bash
# Fuzzes every parser of keylo with cargo-fuzz (libFuzzer) on stable Rust, each target for
# SECONDS_PER_TARGET seconds (default 15: 15 targets, about 4 min of fuzzing plus the build).
#
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]
#
# Targets: fuzz/targets.txt (functions in crates/keylo-fuzz). Seeds are read from
# fuzz/corpus/<target>/ and fuzz/regressions/<target>/ (both committed, never written);
# new inputs go to fuzz/target/work/<target>/, crashes to fuzz/artifacts/<target>/.
# A panic, an allocation or RSS over RSS_LIMIT_MB, or one input running over TIMEOUT_S
# seconds is a failure: the script reports every failing target and exits 1.
#
# FUZZ_SANITIZER=address (local runs; CI has no nightly) builds with AddressSanitizer on the
# nightly toolchain, into fuzz/target/asan/ (so the stable build is kept), logs to
# fuzz/target/logs/address/. Unset (or `none`): no sanitizer, stable, as in CI.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SECONDS_PER_TARGET="${1:-15}"
shift || true
RSS_LIMIT_MB="${RSS_LIMIT_MB:-2048}"
TIMEOUT_S="${TIMEOUT_S:-10}"

if ! command -v cargo-fuzz > /dev/null; then
    cargo install cargo-fuzz --locked
fi
cd "$ROOT/fuzz"
if [ "$#" -gt 0 ]; then
    targets=("$@")
else
    mapfile -t targets < targets.txt
fi

# Default, no sanitizer: keylo's parsers are safe Rust, and `-Zsanitizer` needs nightly; with
# `--sanitizer none` cargo-fuzz builds on stable (no RUSTC_BOOTSTRAP). Debug assertions (-a)
# make integer overflow a crash.
case "${FUZZ_SANITIZER:-none}" in
    none)
        TOOLCHAIN=+stable
        FUZZ_FLAGS=(--sanitizer none -O -a)
        LOGS=target/logs
        ;;
    address)
        TOOLCHAIN=+nightly
        FUZZ_FLAGS=(--sanitizer address -O -a --target-dir target/asan)
        LOGS=target/logs/address
        ;;
    *)
        echo "FUZZ_SANITIZER=$FUZZ_SANITIZER: expected none or address" >&2
        exit 2
        ;;
esac
cargo "$TOOLCHAIN" fuzz build "${FUZZ_FLAGS[@]}"

# Inputs big enough for a few lidar packets or messages; text and small files need less.
max_len() {
    case "$1" in
        ouster_pcap | ros1_bag | mcap | ros2_db3) echo 262144 ;;
        *) echo 65536 ;;
    esac
}

failed=()
mkdir -p "$LOGS"
for t in "${targets[@]}"; do
    mkdir -p "target/work/$t" "corpus/$t" "regressions/$t"
    log="$LOGS/$t.log"
    echo "== $t: ${SECONDS_PER_TARGET} s"
    if cargo "$TOOLCHAIN" fuzz run "${FUZZ_FLAGS[@]}" "$t" "target/work/$t" "corpus/$t" "regressions/$t" -- \
        -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb="$RSS_LIMIT_MB" \
        -timeout="$TIMEOUT_S" -max_len="$(max_len "$t")" -print_final_stats=1 > "$log" 2>&1; then
        grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$log" | tr '\n' ' '
        echo
    else
        failed+=("$t")
        echo "!! $t failed; last lines of $log:"
        tail -40 "$log"
    fi
done

if [ "${#failed[@]}" -gt 0 ]; then
    echo "fuzzing found crashes in: ${failed[*]} (inputs in fuzz/artifacts/)"
    exit 1
fi
echo "fuzzing: no crash in ${#targets[@]} targets"
