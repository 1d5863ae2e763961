#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# Accuracy and time, side by side in one run: ramiform's tetrahedral polygonizer refined to a
# tolerance (`mesh --tolerance`), the paper's uniform levels, and OpenVDB's narrow-band level set
# + volumeToMesh, each in its own process under the protocol of bench/bench_openvdb.cpp (best of
# three warm runs, plus the first, cold one). Deviation is measured the same way for every mesh
# (mesh/deviation.h: 20000 area-weighted points projected onto the surface the mesh approximates,
# relative to the local skeleton radius): ramiform's meshes against the convolution surface,
# OpenVDB's against the union of round cones it meshes.
# Then the real cylinder models (when ../shared/data/trees exists) through the command line:
# `ramiform mesh --fit-radii --stats` and `ramiform check --deviation --fit-radii` with a
# seed the mesher did not use; and archi_Tree_1 side by side with OpenVDB at a 10 mm voxel under
# the benchmark's protocol (ramiform with --fit-radii: the split and the fit are timed too;
# OpenVDB meshes the skeleton's own round cones, which need no fit).
# Usage: bench/compare_accuracy.sh [BUILD_DIR] [OUT.md]     (prints markdown tables)
set -euo pipefail
build=${1:-build}
out=${2:-/dev/stdout}
bin="$build/ramiform"
vdb="$build/bench/ramiform_bench_openvdb"
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

field() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

{
  echo "| mesh | warm s | cold s | triangles | pieces | nodes inside | deviation p50 | p99 | max | < 10° | < 1° |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
  "$bin" generate "$work/tree.json" --segments 1500 --tip-radius 0.004 --trunk-length 1 --seed 1 >/dev/null
  row() {  # label, skeleton, then the benchmark's arguments
    local label=$1 skeleton=$2
    shift 2
    "$vdb" "$skeleton" "$@" >"$work/r.json"
    printf '| %s | %.2f | %.2f | %s | %s | %s | %.3f | %.3f | %.3f | %.2f %% | %.3f %% |\n' "$label" \
      "$(field "$work/r.json" "d['seconds']['total']")" \
      "$(field "$work/r.json" "d['seconds']['first_total']")" \
      "$(field "$work/r.json" "d['triangles']")" "$(field "$work/r.json" "d['components']")" \
      "$(field "$work/r.json" "d['nodes_inside']")" \
      "$(field "$work/r.json" "d['deviation_p50']")" "$(field "$work/r.json" "d['deviation_p99']")" \
      "$(field "$work/r.json" "d['deviation_max']")" \
      "$(field "$work/r.json" "100 * d['triangles_below_10_deg']")" \
      "$(field "$work/r.json" "100 * d['triangles_below_1_deg']")"
  }
  if [ -x "$vdb" ]; then
    row "OpenVDB, voxel 4 mm (= twig radius)" "$work/tree.json" 0.004
    row "OpenVDB, voxel 2 mm" "$work/tree.json" 0.002
    row "ramiform --tolerance 0.1" "$work/tree.json" 1 --tets 1 --tolerance 0.1
    row "ramiform --tolerance 0.05 (default)" "$work/tree.json" 1 --tets 1 --tolerance 0.05
    row "ramiform --tolerance 0.025" "$work/tree.json" 1 --tets 1 --tolerance 0.025
    row "ramiform --levels 1 (uniform)" "$work/tree.json" 1 --tets 1
    row "ramiform --levels 2 (uniform)" "$work/tree.json" 1 --tets 2
  else
    echo "| (no $vdb: configure with OpenVDB, scripts/install-deps.sh --bench) | | | | | | | | | | |"
  fi
  echo
  data="$root/../shared/data/trees"
  if [ -d "$data" ]; then
    echo "| tree | seconds | triangles | pieces | nodes inside | deviation p50 | p99 | max | < 10° | < 1° |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    for t in archi_Tree_1_TreeQSM.txt rtwig_QSM.csv; do
      "$bin" mesh "$data/$t" --fit-radii -o "$work/m.ply" --stats "$work/s.json" >/dev/null 2>&1
      "$bin" check "$work/m.ply" --skeleton "$data/$t" --deviation "$data/$t" --fit-radii \
        --seed 7 --json >"$work/c.json"
      printf '| %s | %.2f | %s | %s | %.4f | %.3f | %.3f | %.3f | %.2f %% | %.3f %% |\n' "$t" \
        "$(field "$work/s.json" "d['seconds']['total']")" "$(field "$work/c.json" "d['triangles']")" \
        "$(field "$work/c.json" "d['components']")" \
        "$(field "$work/c.json" "d['skeleton_nodes_inside']")" \
        "$(field "$work/c.json" "d['deviation_p50']")" "$(field "$work/c.json" "d['deviation_p99']")" \
        "$(field "$work/c.json" "d['deviation_max']")" \
        "$(field "$work/c.json" "100 * d['triangles_below_10_deg']")" \
        "$(field "$work/c.json" "100 * d['triangles_below_1_deg']")"
    done
    if [ -x "$vdb" ]; then
      echo
      echo "| archi_Tree_1, same protocol | warm s | cold s | triangles | pieces | nodes inside | deviation p50 | p99 | max | < 10° | < 1° |"
      echo "|---|---|---|---|---|---|---|---|---|---|---|"
      archi="$data/archi_Tree_1_TreeQSM.txt"
      row "OpenVDB, voxel 10 mm" "$archi" 0.01
      row "ramiform --tolerance 0.05 --fit-radii (default)" "$archi" 1 --tets 1 --tolerance 0.05 \
        --fit-radii
    fi
  else
    echo "(../shared/data/trees not found: the real trees are skipped)"
  fi
} >"$out"
