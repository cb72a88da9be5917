#!/usr/bin/env bash
# Builds the keylo Python package (crates/keylo-py, maturin) into a virtual environment and
# runs its pytest suite. scripts/test.sh calls it after `cargo test`.
#
#   scripts/python-test.sh [PYTEST_ARGS...]
#
# KEYLO_PY_VENV: the environment (default target/py-venv; created when missing). The build
# uses cargo's dev profile, whose dependencies `cargo test` has already built.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
VENV="${KEYLO_PY_VENV:-$ROOT/target/py-venv}"
cd "$ROOT"
if [ ! -x "$VENV/bin/python" ]; then
    if ! python3 -m venv "$VENV" 2>/dev/null; then
        # Debian's python3 has no ensurepip without python3-venv.
        SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
        echo "[python-test] installing python3-venv" >&2
        $SUDO apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends python3-venv >/dev/null
        rm -rf "$VENV"
        python3 -m venv "$VENV"
    fi
fi
"$VENV/bin/pip" install -q --disable-pip-version-check "maturin>=1.16,<1.17" "numpy>=1.24" "pytest>=7" \
    opencv-python-headless onnxruntime "mcap>=1.2" "mcap-protobuf-support>=0.5" "mcap-ros2-support>=0.5"
VIRTUAL_ENV="$VENV" PATH="$VENV/bin:$PATH" maturin develop -q --locked -m crates/keylo-py/Cargo.toml 2>&1 \
    | grep -v -i patchelf || true
cargo build -q --locked -p keylo-cli
KEYLO_BIN="$ROOT/target/debug/keylo" "$VENV/bin/python" -m pytest -q crates/keylo-py/tests "$@"
