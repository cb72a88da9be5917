#!/usr/bin/env bash
# Rebuilds three-keylo.min.js from the npm packages (needs node and npm; not run by CI).
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"
npm init -y >/dev/null
npm install --silent --no-audit --no-fund three@0.187.0 esbuild@0.28.2
cp "$HERE/entry.js" .
npx esbuild entry.js --bundle --minify --format=iife --global-name=THREE \
  --legal-comments=none --target=es2020 --outfile="$HERE/three-keylo.min.js"
cp node_modules/three/LICENSE "$HERE/LICENSE"
