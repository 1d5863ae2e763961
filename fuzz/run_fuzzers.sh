#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# Runs every libFuzzer harness of BUILD_DIR/fuzz for SECONDS each, PARALLEL at a time (`make
# fuzz`; docs/fuzzing.md). New inputs go to BUILD_DIR/fuzz-work/<harness>/ (the first corpus
# directory, where libFuzzer writes), never into the checked-in fuzz/corpus/<harness>/; crashes,
# timeouts and out-of-memory inputs to BUILD_DIR/fuzz-findings/<harness>/. Prints executions
# per harness and exits 1 when any harness found something. FUZZ_RUNS=N stops each harness after
# N executions when that comes before SECONDS (a count that does not depend on the machine's load).
set -uo pipefail

build_dir=${1:?usage: run_fuzzers.sh BUILD_DIR SECONDS [PARALLEL]}
seconds=${2:?usage: run_fuzzers.sh BUILD_DIR SECONDS [PARALLEL]}
parallel=${3:-1}
source_dir=$(cd "$(dirname "$0")/.." && pwd)

shopt -s nullglob
fuzzers=("$build_dir"/fuzz/ramiform_fuzz_*)
if [ ${#fuzzers[@]} -eq 0 ]; then
  echo "run_fuzzers: no fuzzers in $build_dir/fuzz (build the target ramiform_fuzzers)" >&2
  exit 1
fi
# FUZZ_ONLY="mesh_off curve2:900": only these harnesses (every one when empty or unset), each
# for SECONDS or for the seconds given after its name.
if [ -n "${FUZZ_ONLY:-}" ]; then
  chosen=()
  for entry in $FUZZ_ONLY; do
    name=${entry%%:*}
    if [ ! -x "$build_dir/fuzz/ramiform_fuzz_$name" ]; then
      echo "run_fuzzers: no harness '$name' in $build_dir/fuzz (FUZZ_ONLY)" >&2
      exit 2
    fi
    chosen+=("$build_dir/fuzz/ramiform_fuzz_$entry")
  done
  fuzzers=("${chosen[@]}")
fi
if command -v llvm-symbolizer-14 >/dev/null 2>&1; then
  export ASAN_SYMBOLIZER_PATH=${ASAN_SYMBOLIZER_PATH:-$(command -v llvm-symbolizer-14)}
fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

run_one() {
  local entry=${1##*/ramiform_fuzz_} seconds=$seconds
  local name=${entry%%:*} fuzzer=${1%%:*}
  [ "$entry" != "$name" ] && seconds=${entry#*:}
  local work=$build_dir/fuzz-work/$name findings=$build_dir/fuzz-findings/$name
  local log=$build_dir/fuzz-logs/$name.log
  mkdir -p "$work" "$findings" "$build_dir/fuzz-logs"
  # -timeout: an input taking 10 s is a finding (no harness input may take seconds);
  # -rss_limit_mb: libFuzzer's default, stated.
  local runs=()
  [ -n "${FUZZ_RUNS:-}" ] && runs=(-runs="$FUZZ_RUNS")
  "$fuzzer" -max_total_time="$seconds" "${runs[@]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$findings/" "$work" "$source_dir/fuzz/corpus/$name" >"$log" 2>&1
  local rc=$?
  local execs
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -1 | grep -o '[0-9]*$')
  local status=ok
  [ $rc -ne 0 ] && status="FINDING (exit $rc, see $log and $findings/)"
  printf '%-16s %12s executions in %ss  %s\n' "$name" "${execs:-?}" "$seconds" "$status"
  return $rc
}
export -f run_one
export build_dir seconds source_dir

if ! printf '%s\n' "${fuzzers[@]}" | xargs -P "$parallel" -I{} bash -c 'run_one "$@"' _ {}; then
  echo "run_fuzzers: findings (inputs in $build_dir/fuzz-findings/)" >&2
  exit 1
fi
