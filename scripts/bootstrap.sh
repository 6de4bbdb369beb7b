#!/usr/bin/env bash
# bootstrap.sh: installs nomec's build dependencies (Debian 12 packages only) and builds the
# project into build/ with CMake + Ninja. Safe to re-run: the apt step is skipped when every
# package is already installed, and the build is incremental. Works from any directory.
#
# Usage (as root on a fresh Debian 12 machine):   scripts/bootstrap.sh [--sanitize | --threads]
# Afterwards: build/tools/nomec --check FILE...   and   ctest --test-dir build
# With --sanitize it builds build-sanitize/ instead: the `sanitize` preset (clang with
# AddressSanitizer + UndefinedBehaviorSanitizer, and the libFuzzer targets). With --threads it
# builds build-threads/: the `threads` preset (clang with ThreadSanitizer, the kernel and its
# tests only, whose passes run on two threads).
set -euo pipefail

sanitize=0
threads=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=1 ;;
    --threads) threads=1 ;;
    *) echo "bootstrap: unknown argument $arg (usage: scripts/bootstrap.sh [--sanitize | --threads])" >&2; exit 2 ;;
  esac
done

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"

# Keep this list in sync with README.md ("Dependencies") and ARCHITECTURE.md.
packages=(
  antlr4 libantlr4-runtime-dev   # grammar/: ANTLR 4.7.2 tool + C++ runtime
  libfmt-dev                     # formatting everywhere
  libgtest-dev libgmock-dev      # tests/
  libglm-dev                     # kernel/ vector math
  nlohmann-json3-dev             # tools/ JSON output, lsp/
  libcli11-dev                   # tools/ command line
  libboost-dev                   # tools/ `nomec view`: HTTP + WebSocket (Boost.Beast, headers only)
  libosd-dev                     # OpenSubdiv: test oracle and benchmark baseline only
  libbenchmark-dev               # bench/
  libjemalloc-dev                # allocator of nomec (language server speed on large files)
  tcl8.6-dev                     # frontend/tcl: the Tcl 8.6 interpreter SLIDE scenes run in
  libseccomp-dev                 # frontend/tcl: the system-call filter of the Tcl worker process
  admesh                         # STL sanity checks in tests
  cmake ninja-build g++ clang
  libclang-rt-14-dev             # clang's sanitizer and libFuzzer runtimes (build-sanitize/)
  ca-certificates git python3
)

missing=()
for pkg in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
  if [[ "$status" != "install ok installed" ]]; then
    missing+=("$pkg")
  fi
done

if ((${#missing[@]} > 0)); then
  echo "bootstrap: installing ${#missing[@]} missing package(s): ${missing[*]}"
  sudo_cmd=()
  if ((EUID != 0)); then
    if command -v sudo >/dev/null 2>&1; then
      sudo_cmd=(sudo)
    else
      echo "bootstrap: missing packages and not root (no sudo): ${missing[*]}" >&2
      exit 1
    fi
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update
  "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${packages[@]}"
else
  echo "bootstrap: all ${#packages[@]} packages already installed; skipping apt"
fi

# Optional: Node.js and npm for editors/vscode and the preview app (preview/; CMake builds
# and tests them only when node and npm are found), and Chromium for the preview's browser
# tests (label `browser`, registered only when chromium is found). A node already on PATH,
# from any source, is kept as it is.
optional=()
command -v node >/dev/null 2>&1 || optional+=(nodejs npm)
command -v chromium >/dev/null 2>&1 || optional+=(chromium)
if ((${#optional[@]} > 0)); then
  echo "bootstrap: installing ${optional[*]} (editor extension, preview app and its browser tests)"
  node_sudo=(); ((EUID == 0)) || node_sudo=(sudo)
  DEBIAN_FRONTEND=noninteractive "${node_sudo[@]}" apt-get install -y --no-install-recommends "${optional[@]}" \
    || { "${node_sudo[@]}" apt-get update && DEBIAN_FRONTEND=noninteractive "${node_sudo[@]}" apt-get install -y --no-install-recommends "${optional[@]}"; }
fi

if ((sanitize)); then
  cmake --preset sanitize
  cmake --build build-sanitize -j"$(nproc)"
elif ((threads)); then
  cmake --preset threads
  cmake --build build-threads -j"$(nproc)"
else
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
  cmake --build build -j"$(nproc)"
fi
