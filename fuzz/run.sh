#!/usr/bin/env bash
# run.sh: runs the libFuzzer targets of a fuzzing build for a while each, seeded from the
# examples and (when it is beside the repository) the shared corpus, with the input size
# each target is meant for. Prints each run's executions and executions per second, and
# fails on any finding (a crash, a sanitizer report, a timeout, an out-of-memory input),
# leaving the input in DIR/fuzz-artifacts/TARGET/ and the log in DIR/fuzz-TARGET.log.
#
# Usage: fuzz/run.sh [--build DIR] [--seconds N] [--jobs J] [TARGET...]
#   DIR: a build with -DNOMEC_FUZZ=ON (default build-sanitize, the `sanitize` preset)
#   N: seconds per target (default 60); J: fuzzing processes (libFuzzer's -fork=J; default
#   1, one process); TARGET: frontend_fuzzer, parse_fuzzer, pipeline_fuzzer, slide_fuzzer,
#   lsp_fuzzer (default all five)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$repo/build-sanitize"
seconds=60
jobs=1
targets=()
while (($#)); do
  case "$1" in
    --build) build="$(cd "$2" && pwd)"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    -*) echo "run.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
((${#targets[@]})) || targets=(frontend_fuzzer parse_fuzzer pipeline_fuzzer slide_fuzzer lsp_fuzzer)

seeds=("$repo/examples")
for d in nome1 nome3 slide; do
  if [[ -d "$repo/../shared/corpus/$d" ]]; then seeds+=("$repo/../shared/corpus/$d"); fi
done
# No allocation stacks (a finding is re-run to see them): allocation is most of the cost.
export ASAN_OPTIONS="${ASAN_OPTIONS:-malloc_context_size=0}"

for t in "${targets[@]}"; do
  # The front end is fuzzed on short texts (a few statements: fast, and where the grammar's
  # corners are); the pipeline on longer ones, which its own limits keep fast.
  # The SLIDE target starts from SLIDE files; the language server's from its own transcripts
  # (fuzz/lsp_seeds: a first byte choosing the shape, then messages).
  target_seeds=("${seeds[@]}")
  dict="$repo/fuzz/nome.dict"
  case "$t" in
    frontend_fuzzer | parse_fuzzer) max_len=128 ;;
    pipeline_fuzzer) max_len=1024 ;;
    slide_fuzzer)
      max_len=1024
      target_seeds=()
      if [[ -d "$repo/../shared/corpus/slide" ]]; then target_seeds+=("$repo/../shared/corpus/slide"); fi
      target_seeds+=("$repo/tests/check/testdata")
      ;;
    lsp_fuzzer)
      max_len=8192
      target_seeds=("$repo/fuzz/lsp_seeds")
      dict="$repo/fuzz/lsp.dict"
      ;;
    *) echo "run.sh: unknown target $t" >&2; exit 2 ;;
  esac
  binary="$build/fuzz/$t"
  [[ -x "$binary" ]] || { echo "run.sh: $binary is not built (configure with the sanitize preset)" >&2; exit 2; }
  work="$build/fuzz-corpus/$t"
  artifacts="$build/fuzz-artifacts/$t/"
  log="$build/fuzz-$t.log"
  mkdir -p "$work" "$artifacts"
  fork=()
  if ((jobs > 1)); then fork=(-fork="$jobs"); fi
  if ! "$binary" "${fork[@]}" -max_total_time="$seconds" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 \
      -dict="$dict" -artifact_prefix="$artifacts" -print_final_stats=1 \
      "$work" "${target_seeds[@]}" >"$log" 2>&1; then
    echo "run.sh: $t found a problem; input in $artifacts, log $log" >&2
    # The report, the stack (its first frames) and what a differential check printed.
    grep -E "ERROR|SUMMARY|==[0-9]+==|^    #[0-9] |_fuzzer: " "$log" | head -40 >&2 || true
    exit 1
  fi
  # One process prints its final stats; with -fork the parent's last `#N:` line is the total.
  runs="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)"
  if ((jobs > 1)) || [[ -z "$runs" ]]; then
    runs="$(grep -oE '^#[0-9]+:' "$log" | tail -1 | tr -d '#:' || true)"
  fi
  runs="${runs:-0}"
  echo "run.sh: $t: $runs executions in $seconds s ($((runs / seconds)) per second), corpus $work"
done
