#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# gltf_render_upright: a generated tree's .glb, loaded by three.js in headless Chromium with an
# upright (+Y up) camera looking horizontally, stands up: its three.js bounding box is tallest
# along +Y and the rendered tree is taller than wide on screen; the render is not blank; the
# checkerboard render works too. Skipped without node, tools/web/node_modules or chromium.
#   gltf_render_upright.sh RAMIFORM_BINARY SOURCE_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
need_node
need_chromium

# 40 segments forking at 20 degrees: 10.8 tall, 7.6 x 5.9 wide (at the default 32 degrees the
# crown is wider than the tree is tall, and nothing could tell upright from lying).

run "$ramiform" generate tree.json --segments 40 --seed 1 --branch-angle 20 >/dev/null
run "$ramiform" mesh tree.json -o tree.glb >/dev/null
run node "$web/render.mjs" tree.glb tree.png --width 400 --height 400 --json >render.json
run node "$web/render.mjs" tree.glb checker.png --width 400 --height 400 --texture checker \
  --json >checker.json
run node "$source_dir/tests/web/check_render.mjs" render.json checker.json
