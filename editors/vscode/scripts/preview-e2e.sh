#!/usr/bin/env bash
# preview-e2e.sh: the live preview in a real VS Code (code-server from npm, as
# ../shared/docs/vscode-e2e.md describes), driven by preview-e2e.mjs. Not in ctest: the
# one-time install is ~2 minutes and 300 MB; the protocol it relies on is tested in CI
# (tests/lsp/preview_test.cpp, ctest preview_browser).
#   editors/vscode/scripts/preview-e2e.sh PATH/TO/nomec [SCREENSHOT.png]
# Environment: NOMEC_E2E_DIR (scratch folder, default /tmp/nome-vscode-e2e; code-server is
# installed there once), NOMEC_CHROMIUM (default /usr/bin/chromium). Needs Debian's
# chromium, libkrb5-dev, ripgrep, and the extension's and preview's node_modules.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ext="$here/.."
repo="$(cd "$ext/../.." && pwd)"
nomec="$(realpath "${1:?usage: preview-e2e.sh PATH/TO/nomec [SCREENSHOT.png]}")"
shot="$(realpath -m "${2:-$repo/build/preview-vscode.png}")"
dir="${NOMEC_E2E_DIR:-/tmp/nome-vscode-e2e}"
mkdir -p "$dir"/{tmp,app,home,user,exts,ws}
export HOME="$dir/home" XDG_CONFIG_HOME="$dir/home/.config" XDG_DATA_HOME="$dir/home/.local/share" XDG_CACHE_HOME="$dir/home/.cache"

cs="$dir/app/node_modules/.bin/code-server"
if [[ ! -x $cs ]]; then
  # @vscode/ripgrep would download its binary: give it Debian's rg in the cache it reads.
  cache="$dir/tmp/vscode-ripgrep-cache-1.15.11"
  mkdir -p "$cache"
  (cd "$dir/tmp" && cp "$(command -v rg)" rg && tar czf "$cache/ripgrep-v13.0.0-10-x86_64-unknown-linux-musl.tar.gz" rg && rm rg)
  TMPDIR="$dir/tmp" npm_config_yes=true npm_config_jobs=1 MAKEFLAGS=-j1 \
    npm install --no-audit --no-fund --prefix "$dir/app" code-server@4.100.3 --unsafe-perm
fi

(cd "$ext" && bash scripts/ci.sh setup >/dev/null && rm -f nome.vsix && npm run --silent package >/dev/null)
"$cs" --user-data-dir "$dir/user" --extensions-dir "$dir/exts" --install-extension "$ext/nome.vsix" --force >/dev/null
mkdir -p "$dir/user/User"
cat > "$dir/user/User/settings.json" <<JSON
{ "workbench.startupEditor": "none", "security.workspace.trust.enabled": false,
  "update.mode": "none", "telemetry.telemetryLevel": "off", "extensions.autoUpdate": false,
  "workbench.colorTheme": "Default Light Modern", "nome.server.path": "$nomec" }
JSON
rm -rf "$dir/ws"/* && cp "$repo/examples/funnel_cube.nome" "$dir/ws/"
port=$((20000 + RANDOM % 20000))
"$cs" --auth none --bind-addr "127.0.0.1:$port" --disable-telemetry --disable-update-check \
  --disable-workspace-trust --user-data-dir "$dir/user" --extensions-dir "$dir/exts" "$dir/ws" >"$dir/code-server.log" 2>&1 &
pid=$!
trap 'kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true' EXIT
for _ in $(seq 100); do
  curl -fs "http://127.0.0.1:$port/healthz" >/dev/null 2>&1 && break
  sleep 0.2
done
cd "$here" && node preview-e2e.mjs "http://127.0.0.1:$port" "$dir/ws" "$shot"
