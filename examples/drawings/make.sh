#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# Remakes the drawings of this folder (docs/drawing.md) from the shared models and trees
# (../shared/data beside the project, or DATA=DIR) with the ramiform binary (RAMIFORM=PATH,
# default build/ramiform), and the demo's grown tree.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${DATA:-$root/../shared/data}
ramiform=${RAMIFORM:-$root/build/ramiform}
if [ ! -d "$data/models" ]; then
  echo "make.sh: no shared data at $data (set DATA=DIR)" >&2
  exit 2
fi
for m in bunny.ply cow.off kitten.xyz oni.pwn; do
  n=${m%.*}
  "$ramiform" draw "$data/models/$m" -o "$here/$n.svg" --count 15000
  "$ramiform" draw "$data/models/$m" -o "$here/${n}_azimuth-60.svg" --count 15000 \
      --azimuth -60 --elevation 25
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$ramiform" demo --out "$tmp" > /dev/null
"$ramiform" draw "$tmp/skeleton.json" -o "$here/demo_tree.svg" --count 30000 --elevation 10
"$ramiform" draw "$data/trees/archi_Tree_1_TreeQSM.txt" --skeleton -o "$here/archi_Tree_1.svg" \
    --count 40000 --elevation 5
