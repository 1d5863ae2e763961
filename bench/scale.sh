#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# How the tolerance mesher's cost grows with the tree: `ramiform generate --segments N` (the
# generator's defaults otherwise, seed 1) meshed at the default tolerance, each in its own
# process, for N = 1,500, 10,000 and 100,000 (and 1,000,000 with --big). Reports wall time, peak
# memory (GNU time's maximum resident set), triangles, the measured deviation, the time per
# stage and per segment, and the field evaluations per triangle, as a markdown table.
# Usage: bench/scale.sh [BUILD_DIR] [--big]
set -euo pipefail
build=${1:-build}
big=${2:-}
bin="$build/ramiform"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ ! -x /usr/bin/time ]; then
  echo "scale.sh: needs GNU time (apt-get install time)" >&2
  exit 2
fi

sizes=(1500 10000 100000)
[ "$big" = "--big" ] && sizes+=(1000000)

field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

echo "| segments | wall s | s per 1k segments | peak GB | triangles | triangles per segment | evaluations per triangle | tets s | refine s | improve s | measure s | deviation p99 | max |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
  "$bin" generate "$work/t.json" --segments "$n" --seed 1 >/dev/null
  /usr/bin/time -f '%e %M' -o "$work/time" "$bin" mesh "$work/t.json" -o "$work/t.ply" \
    --stats "$work/s.json" >/dev/null
  read -r wall kb <"$work/time"
  tri=$(field "$work/s.json" "d['triangles']")
  printf '| %s | %.1f | %.2f | %.2f | %s | %.0f | %.2f | %.2f | %.2f | %.2f | %.2f | %.3f | %.3f |\n' \
    "$n" "$wall" "$(python3 -c "print($wall / $n * 1000)")" "$(python3 -c "print($kb / 1048576)")" \
    "$tri" "$(python3 -c "print($tri / $n)")" \
    "$(field "$work/s.json" "d['field_evals'] / d['triangles']")" \
    "$(field "$work/s.json" "d['tolerance_seconds']['tets']")" \
    "$(field "$work/s.json" "d['tolerance_seconds']['refine']")" \
    "$(field "$work/s.json" "d['tolerance_seconds'].get('improve', 0)")" \
    "$(field "$work/s.json" "d['tolerance_seconds']['measure']")" \
    "$(field "$work/s.json" "d['deviation_p99']")" "$(field "$work/s.json" "d['deviation_max']")"
done
