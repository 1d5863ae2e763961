# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# Shared by the .glb tests (tests/web/*.sh): argument handling and the checks that skip a test
# (exit 77, ctest's SKIP_RETURN_CODE) when the web tools of tools/web are not installed.
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 RAMIFORM_BINARY SOURCE_DIR WORK_DIR" >&2
  exit 1
fi
ramiform=$(realpath "$1")
source_dir=$(realpath "$2")
web=$source_dir/tools/web
work=$(realpath -m "$3")
skip() {
  echo "SKIP: $* (scripts/install-deps.sh installs them; docs/viewing.md)"
  exit 77
}
need_node() {
  command -v node >/dev/null 2>&1 || skip "node is not installed (Debian: nodejs)"
  [ -d "$web/node_modules/gltf-validator" ] && [ -d "$web/node_modules/three" ] &&
    [ -d "$web/node_modules/playwright-core" ] ||
    skip "$web/node_modules is missing or incomplete (run: cd $web && npm ci)"
}
need_chromium() {
  [ -x /usr/bin/chromium ] || skip "/usr/bin/chromium is not installed (Debian: chromium)"
}
# Runs a command, echoing it first (on stderr, so that redirecting its output keeps the echo).
run() {
  echo "+ $*" >&2
  "$@"
}
rm -rf "$work"
mkdir -p "$work"
cd "$work"
