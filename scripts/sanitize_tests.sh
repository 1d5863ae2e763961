#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# The sanitizer suite within a time budget (CI: .ci/run). `make sanitize` runs every test of
# build-sanitize/ at once; CI stops the whole job at 90 minutes and lands nothing then, so there
# the suite runs in SHARDS interleaved parts (ctest -I k,,SHARDS: every SHARDS-th test from the
# k-th, so each part samples every test program) and a part is started only while the budget
# leaves room for the slowest part so far (times 1.25). Parts left out are named on the output;
# a failing test fails the run whatever the budget.
# Usage: scripts/sanitize_tests.sh BUILD_DIR BUDGET_SECONDS [SHARDS] [JOBS]
# (before the first part has run, a part is taken to need 5 minutes)
set -uo pipefail
build=$1
budget=$2
shards=${3:-6}
jobs=${4:-$(nproc 2>/dev/null || echo 2)}
[ -d "$build" ] || { echo "sanitize_tests.sh: no build directory $build" >&2; exit 2; }
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
start=$SECONDS
slowest=300
first=1
failed=0
for ((k = 1; k <= shards; ++k)); do
  used=$((SECONDS - start))
  if ((used + slowest * 5 / 4 > budget)); then
    echo "sanitize_tests.sh: time budget ($budget s) reached after $used s: parts $k to $shards" \
         "of $shards not run (make sanitize runs them all)"
    break
  fi
  part_start=$SECONDS
  (cd "$build" && ctest --output-on-failure -j "$jobs" --timeout 1200 -I "$k,,$shards") || failed=1
  part=$((SECONDS - part_start))
  if ((first || part > slowest)); then slowest=$part; fi
  first=0
  echo "sanitize_tests.sh: part $k of $shards took $part s"
done
exit $failed
