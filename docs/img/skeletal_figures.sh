#!/bin/sh
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# Remakes the pictures of docs/skeletal.md (docs/img/skeletal_*.png): the figures of Rigaudière,
# Gesquière & Faudot 2000, "Shape Modelling with Skeleton based Implicit Primitives", from the
# scripts examples/rigaudiere_fig*.rf (each run once more, saving a .glb instead of its .ply),
# the subdivision of a superquadric skeleton and a skeleton with curved edges; every picture is
# drawn by tools/web/render_grid.mjs (three.js in headless Chromium, docs/viewing.md). Run from
# the repository root:
#
#   sh docs/img/skeletal_figures.sh            # RAMIFORM=path/to/ramiform to pick a binary
#
# glTF coordinates are +Y up: a ramiform point (x, y, z) is (x, z, -y).
set -eu
R=${RAMIFORM:-build/ramiform}
IMG=docs/img
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
grid() { node tools/web/render_grid.mjs "$@" >/dev/null; }
ln -s "$(pwd)/examples/data" "$T/data"

# The ten figures: each example script with its `save_mesh ... figNN.ply` saving figNN.glb.
FIGS="03b 04 05 08 09 10 15 16 17 18"
for n in $FIGS; do
  sed "s/\(save_mesh shape fig$n\)\.ply/\1.glb/" examples/rigaudiere_fig$n.rf >"$T/fig$n.rf"
  "$R" run "$T/fig$n.rf" --out "$T" --quiet
done
grid $IMG/skeletal_figures.png "$T/fig03b.glb" "$T/fig04.glb" "$T/fig05.glb" "$T/fig08.glb" \
  "$T/fig09.glb" "$T/fig10.glb" "$T/fig15.glb" "$T/fig16.glb" "$T/fig17.glb" "$T/fig18.glb" \
  --cols 5 --frame each --color b08a64 --width 300 --height 260 \
  --azimuth 0,0,0,0,0,20,-30,-30,20,-25 --elevation 10,10,10,10,75,20,35,30,35,35 \
  --labels "Fig. 3b|Fig. 4|Fig. 5|Fig. 8|Fig. 9|Fig. 10|Fig. 15|Fig. 16|Fig. 17|Fig. 18"
# The curvature-adaptive subdivision of §4.1 (the paper's Figures 12 and 13): a superquadric
# skeleton (e1 = e2 = 0.4, a rounded cube) skinned thinly (radius 0.01, flat shading) shows its
# flat sub-patches: 256 at depth 4, 2,560 at depth 6 (refined only where the sides turn by more
# than epsilon = 10 degrees: along the rounded edges). A thin shell is hollow (two components);
# fine for a picture.
for d in 4 6; do
  printf 'superquadric q 1 1 1 e1=0.4 e2=0.4 radius=0.01 depth=%s\nsave_mesh q depth%s.glb resolution=200\n' \
    $d $d >"$T/depth$d.rf"
  "$R" run "$T/depth$d.rf" --out "$T" --quiet
done
grid $IMG/skeletal_subdivision.png "$T/depth4.glb" "$T/depth6.glb" --flat --width 400 --height 400 \
  --azimuth 30 --elevation 25 --labels "depth=4: 256 sub-patches|depth=6: 2,560 sub-patches"

# A skeleton with curved edges (examples/data/curved_tree.json), meshed by `ramiform mesh`, next
# to the same nodes joined by straight edges.
node -e '
const fs = require("fs");
const s = JSON.parse(fs.readFileSync(process.argv[1], "utf8"));
s.edges = s.edges.map((e) => (Array.isArray(e) ? e : e.nodes));
fs.writeFileSync(process.argv[2], JSON.stringify(s));' examples/data/curved_tree.json "$T/straight_tree.json"
"$R" mesh "$T/straight_tree.json" -o "$T/straight_tree.glb" >/dev/null
"$R" mesh examples/data/curved_tree.json -o "$T/curved_tree.glb" >/dev/null
grid $IMG/skeletal_curve_tree.png "$T/straight_tree.glb" "$T/curved_tree.glb" --color b08a64 \
  --width 400 --height 450 --elevation 5 \
  --labels "the same nodes, straight edges|curved_tree.json: Bezier edges with radii"
ls -l $IMG/skeletal_*.png
