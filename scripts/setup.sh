#!/usr/bin/env bash
# One idempotent setup for a fresh Debian machine with Rust: the system packages keylo's
# keypoint front end builds against (OpenCV + clang/libclang for the `opencv` crate; installed
# now so that every later crate finds them), the ONNX Runtime shared library for SuperPoint
# (from the PyPI `onnxruntime` wheel into .cache/; nothing is downloaded at run time), and a
# release build of the `keylo` binary. Quick when everything is already there.
#
#   scripts/setup.sh [--no-release-build]
#
# --no-release-build: the system packages and ONNX Runtime only (scripts/test.sh: the tests build
# what they run, so the release build would be a second build of the whole workspace).
set -euo pipefail
release_build=1
for arg in "$@"; do
  case "$arg" in
    --no-release-build) release_build=0 ;;
    *) echo "scripts/setup.sh: unknown argument '$arg' (expected --no-release-build)" >&2; exit 2 ;;
  esac
done
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"

log() { echo "[setup] $*" >&2; }

apt_packages=(libopencv-dev clang libclang-dev pkg-config)
missing=()
for p in "${apt_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  log "installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  log "system packages present"
fi

ORT_DIR="$ROOT/.cache/onnxruntime"
ORT_VERSION="1.32.0"
if ! ls "$ORT_DIR"/libonnxruntime.so* >/dev/null 2>&1 && ! python3 -m pip --version >/dev/null 2>&1; then
  log "python3 -m pip is missing: installing python3-pip"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends python3-pip >/dev/null
fi
if ! ls "$ORT_DIR"/libonnxruntime.so* >/dev/null 2>&1; then
  log "fetching the ONNX Runtime library from the onnxruntime wheel"
  tmp="$(mktemp -d)"
  python3 -m pip download -q --no-deps --only-binary :all: -d "$tmp" "onnxruntime==${ORT_VERSION}" >&2
  mkdir -p "$ORT_DIR"
  python3 - "$tmp" "$ORT_DIR" <<'PY'
import sys, zipfile, glob, os
wheel = glob.glob(os.path.join(sys.argv[1], "onnxruntime-*.whl"))[0]
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        if name.startswith("onnxruntime/capi/libonnxruntime.so"):
            target = os.path.join(sys.argv[2], os.path.basename(name))
            with open(target, "wb") as out:
                out.write(z.read(name))
PY
  rm -rf "$tmp"
else
  log "ONNX Runtime library present"
fi

if [ "$release_build" -eq 1 ]; then
  log "building keylo (release)"
  cargo build --release --locked -q -p keylo-cli --manifest-path "$ROOT/Cargo.toml"
  log "ready: $ROOT/target/release/keylo"
else
  log "ready (no release build asked for)"
fi
