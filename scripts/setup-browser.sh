#!/usr/bin/env bash
# Installs Debian's `chromium` for the report's browser test (crates/keylo-cli/tests/report.rs
# opens `keylo report`'s page in headless Chromium). Only the test command needs it; the demo
# does not. Without root or sudo, or where apt cannot install it, it says so and the test is
# skipped with a message.
set -euo pipefail
log() { echo "[setup-browser] $*" >&2; }
if command -v chromium >/dev/null 2>&1; then
  log "chromium present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if sudo -n true 2>/dev/null; then SUDO="sudo"; else
    log "no root or sudo: chromium not installed; the report's browser test will be skipped"
    exit 0
  fi
fi
log "installing chromium"
if ! { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq \
    --no-install-recommends chromium >/dev/null; }; then
  log "apt could not install chromium; the report's browser test will be skipped"
fi
