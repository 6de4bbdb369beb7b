#!/usr/bin/env bash
# ci.sh: the steps CTest runs for editors/vscode (see vscode.cmake). Works from any directory.
#   ci.sh setup            npm ci when node_modules is missing or older than the lock file
#                          (or package.json), then compile the TypeScript into out/ and
#                          bundle the preview app into media/preview/
#   ci.sh package          npm run package, then check the .vsix: manifest, grammar, language
#                          configuration, compiled client and its runtime dependency, no tests
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

case "${1:-}" in
  setup)
    stamp=node_modules/.package-lock.json   # written by npm ci / npm install
    if [[ ! -f $stamp || package-lock.json -nt $stamp || package.json -nt $stamp ]]; then
      echo "ci.sh: npm ci (node $(node --version), npm $(npm --version))"
      npm ci --no-audit --no-fund --loglevel=error
    else
      echo "ci.sh: node_modules is up to date with package-lock.json"
    fi
    npm run --silent compile
    # The preview app (preview/), bundled into media/preview/ for the webview.
    bash ../../preview/scripts/build.sh "$PWD/media/preview"
    ;;
  package)
    rm -f nome.vsix
    [[ -f media/preview/app.js ]] || bash ../../preview/scripts/build.sh "$PWD/media/preview"
    npm run --silent package
    python3 - nome.vsix <<'PY'
import json, sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as z:
    names = set(z.namelist())
    need = ["extension/package.json", "extension/syntaxes/nome.tmLanguage.json",
            "extension/language-configuration.json", "extension/README.md",
            "extension/out/src/extension.js", "extension/out/src/preview.js",
            "extension/media/preview/app.js", "extension/media/preview/body.html",
            "extension/media/preview/style.css",
            "extension/node_modules/vscode-languageclient/package.json",
            "extension.vsixmanifest"]
    missing = [n for n in need if n not in names]
    assert not missing, f"missing from the .vsix: {missing}"
    extra = sorted(n for n in names if n.startswith(("extension/out/test/", "extension/src/",
                   "extension/node_modules/typescript/", "extension/node_modules/@vscode/vsce/")))
    assert not extra, f"development files in the .vsix: {extra[:5]}"
    manifest = json.loads(z.read("extension/package.json"))
    (lang,) = manifest["contributes"]["languages"]
    assert lang["id"] == "nome" and sorted(lang["extensions"]) == [".anom", ".nom", ".nome", ".slf"], lang
    (grammar,) = manifest["contributes"]["grammars"]
    assert grammar["scopeName"] == "source.nome", grammar
    tm = json.loads(z.read("extension/" + grammar["path"].lstrip("./")))
    assert tm["scopeName"] == "source.nome" and "patterns" in tm and "repository" in tm
    conf = json.loads(z.read("extension/language-configuration.json"))
    assert conf["comments"] == {"lineComment": "#", "blockComment": ["(*", "*)"]}, conf["comments"]
    assert manifest["main"] == "./out/src/extension.js"
    commands = {c["command"] for c in manifest["contributes"]["commands"]}
    assert "nome.openPreviewToSide" in commands, commands
    assert manifest["contributes"]["menus"]["editor/title"][0]["command"] == "nome.openPreviewToSide"
    print(f"ci.sh: {sys.argv[1]} holds {len(names)} files, manifest, grammar and client")
PY
    ;;
  *)
    echo "usage: ci.sh setup|package" >&2
    exit 2
    ;;
esac
