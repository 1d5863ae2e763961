#!/bin/sh
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
#
# Remakes the pictures of docs/equipotential.md (docs/img/equipotential_*.png): every mesh is
# made by the commands below, every picture by tools/web/render_grid.mjs (three.js in headless
# Chromium, docs/viewing.md). Run from the repository root:
#
#   sh docs/img/equipotential_figures.sh            # RAMIFORM=path/to/ramiform to pick a binary
#
# glTF coordinates are +Y up: a ramiform point (x, y, z) is (x, z, -y) in a close-up's FILE@X,Y,Z,R.
set -eu
R=${RAMIFORM:-build/ramiform}
IMG=docs/img
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
Y=examples/data/y.json
F=examples/data/fork.json
grid() { node tools/web/render_grid.mjs "$@" >/dev/null; }
mesh() { "$R" mesh "$@" >/dev/null; }

# Figure 4: lambda, 0.5 lambda, 0.2 lambda (alpha 4, one charge value 0.25).
for s in 1 0.5 0.2; do mesh $Y -o "$T/lambda_$s.glb" --method particles --charge 0.25 --lambda-scale $s; done
grid $IMG/equipotential_lambda.png "$T/lambda_1.glb" "$T/lambda_0.5.glb" "$T/lambda_0.2.glb" \
  --ortho --color b08a64 --width 320 --height 400 --labels "λ (eq. 2)|0.5 λ|0.2 λ"

# Figure 5: alpha 2, 3, 5 (one charge value 0.25, lambda by eq. 2).
for a in 2 3 5; do mesh $Y -o "$T/alpha_$a.glb" --method particles --alpha $a --charge 0.25; done
grid $IMG/equipotential_alpha.png "$T/alpha_2.glb" "$T/alpha_3.glb" "$T/alpha_5.glb" \
  --ortho --color b08a64 --width 320 --height 400 --labels "α = 2|α = 3|α = 5"

# The triangulation of the fork: rings, the junction patch, a closed cap.
mesh $F -o "$T/fork.glb" --method particles
grid $IMG/equipotential_triangulation.png "$T/fork.glb" "$T/fork.glb@0,3.9,0,1.1" \
  "$T/fork.glb@1.4,4.85,0,0.55" --ortho --flat --wireframe --width 320 --height 400 \
  --azimuth 20 --elevation 15 --frame each \
  --labels "fork.json: 851 particles|the junction patch|a closed leaf: its cap"

# Open and closed ends.
mesh $Y -o "$T/closed.glb" --method particles
mesh $Y -o "$T/open.glb" --method particles --open-ends
grid $IMG/equipotential_ends.png "$T/closed.glb" "$T/open.glb" "$T/closed.glb@1.05,3.25,0,0.45" \
  "$T/open.glb@1.05,3.25,0,0.45" --ortho --flat --wireframe --width 240 --height 320 \
  --elevation 30 --azimuth 30 --labels "closed (default)|--open-ends|closed: a cap|open: the last ring"

# Figures 6 and 7: the L-system skeletons of examples/data/equipotential_fig{6,7}.lsys.
for n in 6 7; do
  "$R" lsystem examples/data/equipotential_fig$n.lsys --iterations 5 -o "$T/fig$n.json" >/dev/null
  mesh "$T/fig$n.json" -o "$T/fig$n.glb" --method particles
done
grid $IMG/equipotential_fig6.png "$T/fig6.glb" "$T/fig6.glb@0,1.15,0,0.45" --ortho --flat \
  --wireframe-panels 2 --width 400 --height 400 --azimuth 30,30 --elevation 10,10 --frame each \
  --labels "4,052 particles, 8,100 triangles|the first fork"
grid $IMG/equipotential_fig7.png "$T/fig7.glb" "$T/fig7.glb@0,1.05,-0.05,0.26" --ortho --flat \
  --wireframe-panels 2 --width 400 --height 400 --azimuth 0,0 --elevation 10,40 --frame each \
  --labels "23,976 particles, 47,948 triangles|a 3-way branch"

# n_circ and n_sphere.
for n in 6 12 24; do mesh $F -o "$T/nc_$n.glb" --method particles --n-circ $n; done
grid $IMG/equipotential_n_circ.png "$T/nc_6.glb" "$T/nc_12.glb" "$T/nc_24.glb" --ortho --flat \
  --wireframe --width 320 --height 400 --azimuth 20 --elevation 15 \
  --labels "n_circ = 6: 395 particles|12 (default): 851|24: 1,955"
for n in 24 48 192; do mesh $F -o "$T/ns_$n.glb" --method particles --n-sphere $n; done
grid $IMG/equipotential_n_sphere.png "$T/ns_24.glb@0,3.9,0,1.1" "$T/ns_48.glb@0,3.9,0,1.1" \
  "$T/ns_192.glb@0,3.9,0,1.1" --ortho --flat --wireframe --width 320 --height 320 --azimuth 20 \
  --elevation 15 --labels "n_sphere = 24: 835 particles|48 (default): 851|192: 960"

# The placement radius R.
for r in 0.2 0.8 1.5; do mesh $F -o "$T/R_$r.glb" --method particles --placement-radius $r; done
grid $IMG/equipotential_placement_radius.png "$T/R_0.2.glb" "$T/fork.glb" "$T/R_0.8.glb" \
  "$T/R_1.5.glb" --ortho --flat --wireframe --width 240 --height 340 --azimuth 20 --elevation 15 \
  --labels "R = 0.2|R = radii (default)|R = 0.8|R = 1.5"

# The charge spacing d_c: the particle mesh (rings at the charges) and the tets mesh of the
# same field, which shows the surface between the charges.
for d in 0.125 0.25 0.5 0.75; do
  mesh $Y -o "$T/dc_$d.glb" --method particles --charge 0.25 --charge-spacing $d
  mesh $Y -o "$T/dc_tets_$d.glb" --surface equipotential --charge 0.25 --charge-spacing $d 2>/dev/null
done
grid $IMG/equipotential_charge_spacing.png "$T/dc_0.125.glb" "$T/dc_0.25.glb" "$T/dc_0.5.glb" \
  "$T/dc_0.75.glb" "$T/dc_tets_0.125.glb" "$T/dc_tets_0.25.glb" "$T/dc_tets_0.5.glb" \
  "$T/dc_tets_0.75.glb" --cols 4 --ortho --color b08a64 --width 200 --height 250 \
  --labels "particles, d_c = 0.125|0.25|0.5|0.75|tets, d_c = 0.125|0.25|0.5|0.75"

# The charge values c_i^q: one for every edge, per edge from the radii, fitted to the radii.
mesh $F -o "$T/q_one.glb" --method particles --charge 0.35 --charge-spacing 0.15
mesh $F -o "$T/q_fit.glb" --method particles --fit-radii
grid $IMG/equipotential_charges.png "$T/q_one.glb" "$T/fork.glb" "$T/q_fit.glb" --ortho \
  --color b08a64 --width 320 --height 400 --azimuth 20 --elevation 10 \
  --labels "--charge 0.35 --charge-spacing 0.15|per edge from the radii|--fit-radii"

# Relaxation in the crotch of the thick Y (0.2 lambda).
for r in 0 2 50; do mesh $Y -o "$T/relax_$r.glb" --method particles --charge 0.25 --lambda-scale 0.2 --relax $r; done
grid $IMG/equipotential_relax.png "$T/relax_0.glb@0,2.75,0,0.75" "$T/relax_2.glb@0,2.75,0,0.75" \
  "$T/relax_50.glb@0,2.75,0,0.75" --ortho --flat --wireframe --width 320 --height 320 \
  --elevation 30 --labels "--relax 0 (the paper)|--relax 2 (default)|--relax 50"

# The same field by three polygonizers: the first fork of Figure 6.
mesh "$T/fig6.json" -o "$T/fig6_tets.glb" --surface equipotential
mesh "$T/fig6.json" -o "$T/fig6_mc.glb" --surface equipotential --method mc --resolution 100
grid $IMG/equipotential_methods.png "$T/fig6.glb@0,1.1,0,0.3" "$T/fig6_tets.glb@0,1.1,0,0.3" \
  "$T/fig6_mc.glb@0,1.1,0,0.3" --ortho --flat --wireframe --width 320 --height 320 \
  --azimuth 30 --elevation 10 --labels "--method particles|--method tets|--method mc --resolution 100"
# A neuron (examples/data/neuron_small.swc, made by tests/support/neuron_fixture.cpp): the
# soma joined to its neurites, a junction with one hole per neurite.
mesh examples/data/neuron_small.swc -o "$T/neuron.glb" --method particles
grid $IMG/equipotential_neuron.png "$T/neuron.glb" "$T/neuron.glb@0,0,0,9" --ortho --flat \
  --wireframe-panels 2 --width 400 --height 400 --azimuth 30,30 --elevation 10,10 --frame each \
  --color b08a64 --labels "neuron_small.swc, one piece|the soma: one hole per neurite"

ls -l $IMG/equipotential_*.png
