#!/usr/bin/env bash
# test.sh: installs what is needed, builds and runs every test: the whole suite (build/),
# the whole suite again under AddressSanitizer + UndefinedBehaviorSanitizer
# (build-sanitize/, the `sanitize` preset; the VS Code and browser end-to-end tests run
# once, in the first pass), the kernel's tests under ThreadSanitizer (build-threads/, the
# `threads` preset: the kernel's passes run on two threads), then a short run of each
# libFuzzer target from the corpus (fuzz/run.sh).
# This is README's test command and what CI runs (.ci/run). Works from any directory.
#
# Usage: scripts/test.sh        (NOMEC_FUZZ_SECONDS=N sets each fuzzer's run, default 45)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

start=$(date +%s)
stage() { echo "test.sh: $1 (at $(( $(date +%s) - start )) s)"; }

stage "build"
scripts/bootstrap.sh
stage "test suite"
ctest --test-dir build --output-on-failure --no-tests=error -j2
stage "sanitizer build"
scripts/bootstrap.sh --sanitize
stage "test suite under ASan + UBSan"
ctest --test-dir build-sanitize --output-on-failure --no-tests=error -j2 -LE 'vscode|browser'
stage "kernel build under ThreadSanitizer"
scripts/bootstrap.sh --threads
stage "kernel tests under TSan"
ctest --test-dir build-threads --output-on-failure --no-tests=error -j2
stage "fuzz smoke runs"
fuzz/run.sh --build build-sanitize --seconds "${NOMEC_FUZZ_SECONDS:-45}"
stage "done"
