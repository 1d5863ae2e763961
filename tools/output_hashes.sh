#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# Runs `ramiform demo`, every script in examples/ and a ladder of CLI commands, and prints one
# SHA-256 per output file (sorted by name). A refactoring that must not change behaviour keeps
# this list identical: run it before and after and diff.
#   tools/output_hashes.sh BUILD/ramiform OUTDIR > hashes.txt
set -euo pipefail
bin=$(realpath "$1")
out=$2
src=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$out"
mkdir -p "$out"
cd "$out"
"$bin" demo --out demo >/dev/null
for s in "$src"/examples/*.rf; do
  name=$(basename "$s" .rf)
  mkdir -p "$out/examples/$name"
  (cd "$src/examples" && "$bin" run "$s" --out "$out/examples/$name" >/dev/null)
done
mkdir -p cli
cd cli
"$bin" generate tree.json --segments 300 --seed 3 >/dev/null
"$bin" mesh tree.json -o tets.ply --threads 1 >/dev/null
"$bin" mesh tree.json -o tets2.ply --threads 2 --levels 1 --fit-radii >/dev/null
"$bin" mesh tree.json -o mc.ply --method mc --resolution 96 >/dev/null
"$bin" mesh tree.json -o dist.glb --surface distance --levels 1 >/dev/null
"$bin" check tets.ply --skeleton tree.json --json > check.json
"$bin" lsystem monopodial --iterations 6 -o plant.json >/dev/null
"$bin" sample "$src/examples/drilled_sphere.rf" s3 --dist poisson --count 800 -o pts.txt >/dev/null 2>&1 || true
"$bin" grow --points pts.txt --step 0.2 --influence 1.5 --kill 0.4 -o grown.json >/dev/null 2>&1 || true
printf '0 0 0\n0 0 1\n0.1 0.2 2\n' > q.txt
"$bin" eval tree.json --points q.txt --gradient > eval.txt
cd "$out"
find . -type f ! -name '*stats*' -print0 | sort -z | xargs -0 sha256sum
