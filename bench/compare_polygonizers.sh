#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# tets against mc on generated trees (and the real cylinder models when ../shared/data/trees
# exists): time, field evaluations, triangles, components and the fraction of edge midpoints
# inside the mesh ("twigs kept": a twig that marching cubes loses leaves its midpoint outside;
# nodes are not used because a free end of a convolution surface pulls in to about its tip
# node, which then sits on the surface). mc runs at the coarsest cell that still keeps every
# midpoint inside (searched by halving from the smallest node radius x 4, not below 1/1024 of
# the tree's longest side) and at the cell that gives about tets' triangle count.
# Usage: bench/compare_polygonizers.sh [BUILD_DIR] [OUT.md]     (prints a markdown table)
set -euo pipefail
build=${1:-build}
out=${2:-/dev/stdout}
bin="$build/ramiform"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
root=$(cd "$(dirname "$0")/.." && pwd)

# The edge midpoints of a skeleton as a skeleton of isolated nodes (for `ramiform check`).
midpoints() {
  python3 - "$1" "$2" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
n = s["nodes"]
mids = [{"position": [(n[a]["position"][k] + n[b]["position"][k]) / 2 for k in range(3)],
         "radius": min(n[a]["radius"], n[b]["radius"])} for a, b in s["edges"]]
json.dump({"nodes": mids, "edges": []}, open(sys.argv[2], "w"))
PY
}

json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

row() {  # name method skeleton extra-args...
  local name=$1 method=$2 skel=$3
  shift 3
  if ! "$bin" mesh "$skel" --method "$method" "$@" -o "$work/m.ply" --stats "$work/s.json" \
      >/dev/null 2>"$work/err.txt"; then
    printf '| %s | %s %s | failed: %s | | | | | |\n' "$name" "$method" "$*" "$(head -c 120 "$work/err.txt")"
    return 0
  fi
  "$bin" check "$work/m.ply" --skeleton "${skel%.json}.mid.json" --json >"$work/c.json"
  printf '| %s | %s %s | %.2f | %s | %s | %s | %s | %.4f |\n' "$name" "$method" "$*" \
    "$(json "$work/s.json" "d['seconds']['polygonize']")" "$(json "$work/s.json" "d['field_evals']")" \
    "$(json "$work/s.json" "d['triangles']")" "$(json "$work/c.json" "d['watertight']")" \
    "$(json "$work/c.json" "d['components']")" "$(json "$work/c.json" "d['skeleton_nodes_inside']")"
}

inside() {  # skeleton cell -> fraction of midpoints inside the mc mesh (0 if mc fails)
  "$bin" mesh "$1" --method mc --cell "$2" -o "$work/p.ply" >/dev/null 2>&1 || { echo 0; return; }
  "$bin" check "$work/p.ply" --skeleton "${1%.json}.mid.json" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['skeleton_nodes_inside'])"
}

compare() {  # name skeleton levels... (mc is matched to the last level's triangle count)
  local name=$1 skel=$2
  shift 2
  local rmin cell tris levels last
  last=${*: -1}
  midpoints "$skel" "${skel%.json}.mid.json"
  rmin=$(python3 -c "import json,sys; print(min(n['radius'] for n in json.load(open(sys.argv[1]))['nodes']))" "$skel")
  for levels in "$@"; do row "$name" tets "$skel" --levels "$levels"; done
  # Coarsest mc cell keeping every node inside: halve from 4 x the smallest radius, but not
  # below 1/1024 of the tree's longest side (finer grids take minutes to hours).
  local floor
  floor=$(python3 -c "import json,sys; p=[n['position'] for n in json.load(open(sys.argv[1]))['nodes']]; print(max(max(q[k] for q in p)-min(q[k] for q in p) for k in range(3)) / 1024)" "$skel")
  cell=$(python3 -c "print(4 * $rmin)")
  for _ in 1 2 3 4 5 6; do
    [ "$(inside "$skel" "$cell")" = "1.0" ] && break
    if python3 -c "import sys; sys.exit(0 if $cell / 2 < $floor else 1)"; then
      cell=$floor
      break
    fi
    cell=$(python3 -c "print($cell / 2)")
  done
  row "$name" mc "$skel" --cell "$cell"
  # mc at about the triangle count of tets at the last level: triangles scale as 1 / cell^2.
  "$bin" mesh "$skel" --levels "$last" -o "$work/t.ply" --stats "$work/t.json" >/dev/null
  tris=$(json "$work/t.json" "d['triangles']")
  if ! "$bin" mesh "$skel" --method mc --cell "$cell" -o "$work/p.ply" --stats "$work/p.json" \
      >/dev/null 2>&1; then
    return 0  # mc cannot run at that cell (the row above says why)
  fi
  cell=$(python3 -c "import math; print($cell * math.sqrt($(json "$work/p.json" "d['triangles']") / $tris))")
  row "$name" mc "$skel" --cell "$cell"
}

# TREES selects the rows (default: all): gen1000 gen5000 gen20000 archi rtwig.
trees_wanted=${TREES:-"gen1000 gen5000 gen20000 archi rtwig"}
want() { [[ " $trees_wanted " == *" $1 "* ]]; }

{
  echo "| tree | method | polygonize s | field evals | triangles | watertight | components | midpoints inside |"
  echo "|---|---|---|---|---|---|---|---|"
  for n in 1000 5000 20000; do
    "$bin" generate "$work/tree$n.json" --segments "$n" --seed 1 >/dev/null
  done
  if want gen1000; then compare "generated 1000" "$work/tree1000.json" 2 3; fi
  if want gen5000; then compare "generated 5000" "$work/tree5000.json" 1 2; fi
  if want gen20000; then compare "generated 20000" "$work/tree20000.json" 1; fi
  trees="$root/../shared/data/trees"
  if [ -d "$trees" ]; then
    "$bin" convert "$trees/archi_Tree_1_TreeQSM.txt" "$work/archi.json" >/dev/null
    "$bin" convert "$trees/rtwig_QSM.csv" "$work/rtwig.json" >/dev/null
    if want archi; then compare "archi_Tree_1 (TreeQSM)" "$work/archi.json" 2; fi
    if want rtwig; then compare "rtwig (SimpleForest)" "$work/rtwig.json" 2 3; fi
  else
    echo "(real trees skipped: $trees not found)" >&2
  fi
} >"$out"
