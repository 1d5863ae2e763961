#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
# gltf_validator: every kind of .glb the CLI writes passes the Khronos glTF validator with no
# error and no warning (infos are printed, allowed). Skipped without node or tools/web/node_modules.
#   gltf_validator.sh RAMIFORM_BINARY SOURCE_DIR WORK_DIR
source "$(dirname "$0")/common.sh"
need_node

# 1. A generated tree meshed by the tetrahedral polygonizer (the default method).
run "$ramiform" generate tree.json --segments 40 --seed 1 --branch-angle 20 >/dev/null
run "$ramiform" mesh tree.json -o tree.glb >/dev/null
# 2. The same tree by marching cubes (its twigs come apart on this grid: a warning, and many
#    components in one primitive), and an OBJ of it for the scene below.
run "$ramiform" mesh tree.json -o tree_mc.glb --method mc --resolution 48 >/dev/null
run "$ramiform" mesh tree.json -o tree.obj >/dev/null
# 3. An empty mesh: one edge a billionth of its radius long, whose convolution surface does not
#    form; `mesh` writes the empty mesh and exits 3 (a script refuses to save one).
cat > speck.json <<'JSON'
{"nodes": [{"position": [0, 0, 0], "radius": 1}, {"position": [1e-9, 0, 0], "radius": 1}],
 "edges": [[0, 1]]}
JSON
rc=0
"$ramiform" mesh speck.json -o empty.glb >/dev/null 2>&1 || rc=$?
if [ $rc -ne 3 ]; then
  echo "FAIL: mesh of speck.json exited $rc, not 3 (the mesh is empty)"
  exit 1
fi
# 4. Scene scripts: a tiny mesh (a sphere on a 2-cell grid: 8 triangles), a CSG shape, a
#    skeleton meshed by tets, and the OBJ above as a shape.
cat > scene.rf <<'RF'
sphere ball 1
save_mesh ball tiny.glb resolution=2
sphere s1 1
line s2
diff s1 s2 drilled
save_mesh drilled drilled.glb resolution=24
skeleton fork tree.json
save_mesh fork fork.glb method=tets levels=1
mesh_shape obj tree.obj
save_mesh obj obj.glb resolution=32
RF
run "$ramiform" run scene.rf --out . --quiet
# 5. The demo's tree (what `make run` writes), on fewer points than its default.
run "$ramiform" demo --out demo --points 600 >/dev/null

files=(tree.glb tree_mc.glb tiny.glb empty.glb drilled.glb fork.glb obj.glb demo/tree.glb)
# 6. Levels of detail in one file (MSFT_lod: the validator reports it as the info
#    UNSUPPORTED_EXTENSION, and the coarser nodes, outside the scene, as UNUSED_OBJECT infos).
if "$ramiform" mesh --help | grep -q -- '--lod'; then
  run "$ramiform" mesh tree.json -o tree_lod.glb --lod 0.05,0.15,0.4 >/dev/null
  files+=(tree_lod.glb)
else
  echo "note: this ramiform has no mesh --lod: no MSFT_lod file checked"
fi
status=0
run node "$web/validate.mjs" "${files[@]}" || status=$?

# The check must be able to fail: a copy of tree.glb whose POSITION max is wrong (ACCESSOR_MAX_MISMATCH)
# and a file that is not glTF at all.
node - tree.glb broken.glb <<'JS'
const fs = require('fs');
const [src, dst] = process.argv.slice(2);
const b = fs.readFileSync(src);
const jsonLength = b.readUInt32LE(12);
const json = JSON.parse(b.subarray(20, 20 + jsonLength).toString());
json.accessors[json.meshes[0].primitives[0].attributes.POSITION].max[1] += 1;
let text = JSON.stringify(json);
while (text.length % 4) text += ' ';
const head = Buffer.alloc(20);
const rest = b.subarray(20 + jsonLength);
head.writeUInt32LE(0x46546c67, 0); head.writeUInt32LE(2, 4);
head.writeUInt32LE(20 + text.length + rest.length, 8);
head.writeUInt32LE(text.length, 12); head.writeUInt32LE(0x4e4f534a, 16);
fs.writeFileSync(dst, Buffer.concat([head, Buffer.from(text), rest]));
JS
echo "not a glb" > junk.glb
rc=0
node "$web/validate.mjs" broken.glb >broken.log 2>&1 || rc=$?
if [ $rc -ne 1 ] || ! grep -q ACCESSOR_MAX_MISMATCH broken.log; then
  cat broken.log
  echo "FAIL: validate.mjs did not report the wrong POSITION max of broken.glb (exit $rc)"
  status=1
fi
rc=0
node "$web/validate.mjs" junk.glb missing.glb >junk.log 2>&1 || rc=$?
if [ $rc -ne 2 ]; then
  cat junk.log
  echo "FAIL: validate.mjs exited $rc, not 2, on unreadable input"
  status=1
fi
if [ $status -ne 0 ]; then
  echo "FAIL: the glTF validator reported errors or warnings (above)"
  exit 1
fi
echo "PASS: ${#files[@]} .glb files without validator errors or warnings"
