#!/usr/bin/env bash
# build.sh OUT_DIR: what CMake runs to build the preview app (see preview/CMakeLists.txt):
# `npm ci` when node_modules is missing or older than package-lock.json, then esbuild
# bundles src/ into OUT_DIR (app.js, style.css, index.html, body.html).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
stamp=node_modules/.package-lock.json   # written by npm ci / npm install
if [[ ! -f $stamp || package-lock.json -nt $stamp || package.json -nt $stamp ]]; then
  echo "preview: npm ci (node $(node --version), npm $(npm --version))"
  npm ci --no-audit --no-fund --loglevel=error
fi
node scripts/build.mjs "$1"
