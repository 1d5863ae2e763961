#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# The equipotential particle mesher (Gruber & Wallner 2014; docs/equipotential.md) side by side
# with the tetrahedral polygonizer on the same equipotential field, in one run, through the
# command line as a user runs it (`ramiform mesh --stats --threads 2`).
# Skeletons: the L-systems of the paper's Figures 6 and 7 (examples/data/equipotential_fig*.lsys),
# generated trees of 1,000 and 5,000 segments, and (when ../shared/data/trees exists) the two
# real cylinder models with --fit-radii. For each mesh: seconds (field = charges, lambda and fit;
# mesh = placement, movement, relaxation and triangulation, or the tets polygonizer; total = the
# whole command, reading and writing included; best of three runs for the L-systems, one run for
# the larger skeletons), triangles, particles (= vertices), particles
# placed and converged per second of the mesher, smallest and median triangle angle, radius
# error (median / max, relative to the requested radius) and the deviation from the surface
# (`ramiform check --deviation --surface equipotential`: p50 / p99 of 20,000 area-weighted
# points, relative to the local radius).
# Usage: bench/compare_equipotential.sh [BUILD_DIR] [OUT.md]     (prints a markdown table)
set -euo pipefail
build=${1:-build}
out=${2:-/dev/stdout}
bin="$build/ramiform"
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

# Best of $runs runs: the stats of the fastest are kept in $work/s.json.
runs=3
best_of() {
  local best=""
  for _ in $(seq "$runs"); do
    "$bin" mesh "$@" --threads 2 --stats "$work/t.json" >/dev/null 2>&1
    local t
    t=$(field "$work/t.json" "d['seconds']['total']")
    if [ -z "$best" ] || python3 -c "import sys; sys.exit(0 if $t < $best else 1)"; then
      best=$t
      cp "$work/t.json" "$work/s.json"
    fi
  done
}

row() {  # label, skeleton, method label, then mesh options
  local label=$1 skel=$2 how=$3
  shift 3
  best_of "$skel" -o "$work/m.ply" "$@"
  local fit=""
  case " $* " in *" --fit-radii "*) fit=--fit-radii ;; esac
  "$bin" check "$work/m.ply" --deviation "$skel" --surface equipotential $fit --seed 7 --json \
    >"$work/c.json"
  local particles rate
  particles=$(field "$work/s.json" "d.get('particles', '')")
  rate=$(field "$work/s.json" \
    "'%.0f k' % (d['particles'] / d['seconds']['polygonize'] / 1000) if 'particles' in d else ''")
  printf '| %s | %s | %.3f | %.3f | %.3f | %s | %s | %s | %.1f° | %.1f° | %.1f %% / %.1f %% | %.2f %% / %.2f %% |\n' \
    "$label" "$how" "$(field "$work/s.json" "d['seconds']['field'] + d['seconds'].get('fit', 0)")" \
    "$(field "$work/s.json" "d['seconds']['polygonize']")" \
    "$(field "$work/s.json" "d['seconds']['total']")" "$(field "$work/s.json" "d['triangles']")" \
    "$particles" "$rate" \
    "$(field "$work/s.json" "d['min_angle_deg']")" "$(field "$work/s.json" "d['median_angle_deg']")" \
    "$(field "$work/s.json" "100 * d.get('radius_error_median', float('nan'))")" \
    "$(field "$work/s.json" "100 * d.get('radius_error_max', float('nan'))")" \
    "$(field "$work/c.json" "100 * d['deviation_p50']")" "$(field "$work/c.json" "100 * d['deviation_p99']")"
}

pair() {  # label, skeleton, then options for both methods
  local label=$1 skel=$2
  shift 2
  row "$label" "$skel" "particles" --method particles "$@"
  row "$label" "$skel" "tets" --surface equipotential --radius-error "$@"
}

{
  echo "| skeleton | method | field s | mesh s | total s | triangles | particles | particles/s | min angle | median angle | radius error median / max | deviation p50 / p99 |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  "$bin" lsystem "$root/examples/data/equipotential_fig6.lsys" --iterations 5 -o "$work/fig6.json" >/dev/null
  "$bin" lsystem "$root/examples/data/equipotential_fig7.lsys" --iterations 5 -o "$work/fig7.json" >/dev/null
  "$bin" generate "$work/t1000.json" --segments 1000 --seed 1 >/dev/null
  "$bin" generate "$work/t5000.json" --segments 5000 --seed 1 >/dev/null
  pair "Figure 6 L-system (31 edges)" "$work/fig6.json"
  pair "Figure 7 L-system (121 edges)" "$work/fig7.json"
  runs=1  # the larger ones: one run each
  pair "generated 1,000 segments" "$work/t1000.json"
  pair "generated 5,000 segments" "$work/t5000.json"
  data="$root/../shared/data/trees"
  if [ -d "$data" ]; then
    for t in archi_Tree_1_TreeQSM.txt rtwig_QSM.csv; do
      pair "$t, --fit-radii" "$data/$t" --fit-radii
    done
  else
    echo "(../shared/data/trees not found: the real trees are skipped)"
  fi
} >"$out"
