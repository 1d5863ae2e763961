#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# How the tolerance mesher's cost grows with the tree: `ramiform generate --segments N` (the
# generator's defaults otherwise, seed 1) meshed at the default tolerance, each in its own
# process, for N = 1,500, 10,000 and 100,000 (and 1,000,000 with --big). Reports wall time, peak
# memory (GNU time's maximum resident set), triangles, the measured deviation, the time per
# stage and per segment, and the field evaluations per triangle, as a markdown table. "CPU s" is
# the process's user time: on a shared machine the wall times drift with the load, the CPU times
# much less.
#   --big       adds 1,000,000 segments (about 1 h and 10-25 GB on 2 cores).
#   --sizes "3000 10000 30000"   other sizes.
#   --forest    K side-by-side copies of the 1,500-segment tree (60 m apart, out of each other's
#               reach) instead of one tree of N segments, K = N / 1,500: the pipeline's own
#               growth, without the generator's crowding (its crown keeps its size as N grows,
#               see docs/benchmarks.md, "Scale").
# Usage: bench/scale.sh [BUILD_DIR] [--big] [--forest] [--sizes "N ..."]
set -euo pipefail
build=${1:-build}
shift || true
big=""
forest=""
sizes=(1500 10000 100000)
while [ $# -gt 0 ]; do
  case "$1" in
    --big) big=1 ;;
    --forest) forest=1 ;;
    --sizes) shift; read -r -a sizes <<<"$1" ;;
    *) echo "scale.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
bin="$build/ramiform"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ ! -x /usr/bin/time ]; then
  echo "scale.sh: needs GNU time (apt-get install time)" >&2
  exit 2
fi

[ -n "$big" ] && sizes+=(1000000)

field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

# K copies of the skeleton $1, 60 m apart on a grid, into $3.
forest_of() {
  python3 - "$@" <<'PY'
import json, sys
src, k, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
d = json.load(open(src))
n = len(d['nodes'])
nodes, edges = [], []
for c in range(k):
    dx, dy = 60.0 * (c % 8), 60.0 * (c // 8)
    for nd in d['nodes']:
        m = dict(nd)
        p = nd['position']
        m['position'] = [p[0] + dx, p[1] + dy, p[2]]
        nodes.append(m)
    edges += [[a + c * n, b + c * n] for a, b in d['edges']]
d['nodes'], d['edges'] = nodes, edges
json.dump(d, open(out, 'w'))
PY
}

echo "| segments | wall s | CPU s | CPU s per 1k segments | peak GB | triangles | triangles per segment | evaluations per triangle | tets s | of which polyhedron s | refine s | improve s | measure s | deviation p99 | max |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for n in "${sizes[@]}"; do
  if [ -n "$forest" ]; then
    "$bin" generate "$work/one.json" --segments 1500 --seed 1 >/dev/null
    forest_of "$work/one.json" $(((n + 749) / 1500)) "$work/t.json"
    n=$(((n + 749) / 1500 * 1500))
  else
    "$bin" generate "$work/t.json" --segments "$n" --seed 1 >/dev/null
  fi
  /usr/bin/time -f '%e %U %M' -o "$work/time" "$bin" mesh "$work/t.json" -o "$work/t.ply" \
    --stats "$work/s.json" >/dev/null
  read -r wall cpu kb <"$work/time"
  tri=$(field "$work/s.json" "d['triangles']")
  printf '| %s | %.1f | %.1f | %.2f | %.2f | %s | %.0f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.3f | %.3f |\n' \
    "$n" "$wall" "$cpu" "$(python3 -c "print($cpu / $n * 1000)")" "$(python3 -c "print($kb / 1048576)")" \
    "$tri" "$(python3 -c "print($tri / $n)")" \
    "$(field "$work/s.json" "d['field_evals'] / d['triangles']")" \
    "$(field "$work/s.json" "d['tolerance_seconds']['tets']")" \
    "$(field "$work/s.json" "d['tets_seconds']['polyhedron']")" \
    "$(field "$work/s.json" "d['tolerance_seconds']['refine']")" \
    "$(field "$work/s.json" "d['tolerance_seconds'].get('improve', 0)")" \
    "$(field "$work/s.json" "d['tolerance_seconds']['measure']")" \
    "$(field "$work/s.json" "d['deviation_p99']")" "$(field "$work/s.json" "d['deviation_max']")"
done
