#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# studio_e2e: `ramiform studio` in headless Chromium (web/studio/e2e/studio_e2e.mjs says what
# it checks). Skipped (exit 77) without node, web/studio/node_modules (npm ci), Chromium, or a
# binary built with the page (web/studio/dist, made by `npm run build` at build time).
#   studio_e2e.sh RAMIFORM_BINARY SOURCE_DIR WORK_DIR
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 RAMIFORM_BINARY SOURCE_DIR WORK_DIR" >&2
  exit 1
fi
ramiform=$(realpath "$1")
studio=$(realpath "$2")/web/studio
work=$(realpath -m "$3")
skip() {
  echo "SKIP: $* (scripts/install-deps.sh installs them; docs/studio.md)"
  exit 77
}
command -v node >/dev/null 2>&1 || skip "node is not installed (Debian: nodejs)"
[ -d "$studio/node_modules/playwright-core" ] ||
  skip "$studio/node_modules is missing or incomplete (run: cd $studio && npm ci)"
[ -x /usr/bin/chromium ] || skip "/usr/bin/chromium is not installed (Debian: chromium)"
[ -f "$studio/dist/index.html" ] ||
  skip "$studio/dist is not built (run: cd $studio && npm run build, then rebuild ramiform)"
echo "+ node $studio/e2e/studio_e2e.mjs $ramiform $work" >&2
# Chromium's own complaints (no D-Bus, GPU stalls) go to a file; the test's lines to the log.
mkdir -p "$work"
node "$studio/e2e/studio_e2e.mjs" "$ramiform" "$work/run" 2>"$work/stderr.txt" || status=$?
status=${status:-0}
if [ "$status" -ne 0 ] && [ "$status" -ne 77 ]; then
  grep -v -E '\]\[err\]|^\[pid=' "$work/stderr.txt" | tail -40 >&2 || true
fi
exit "$status"
