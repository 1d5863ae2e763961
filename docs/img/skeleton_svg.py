#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Draws skeleton JSON files side by side as an SVG, projected on the x-z plane (z up).

Used for docs/img/demo_cleanup.svg and docs/img/demo_cleanup_detail.svg (docs/growth.md):
  python3 docs/img/skeleton_svg.py OUT.svg "title A" A.json "title B" B.json [--box x0 z0 x1 z1]
Edges are drawn as lines as wide as the node radii; tips are marked with dots.
"""
import json
import sys


def load(path):
    d = json.load(open(path))
    return [n["position"] for n in d["nodes"]], [n["radius"] for n in d["nodes"]], d["edges"]


def main(argv):
    out = argv[1]
    box = None
    if "--box" in argv:
        k = argv.index("--box")
        box = [float(v) for v in argv[k + 1:k + 5]]
        argv = argv[:k]
    panels = [(argv[i], load(argv[i + 1])) for i in range(2, len(argv), 2)]
    if box is None:
        xs = [p[0] for _, (P, _, _) in panels for p in P]
        zs = [p[2] for _, (P, _, _) in panels for p in P]
        box = [min(xs), min(zs), max(xs), max(zs)]
    x0, z0, x1, z1 = box
    w, h, pad = 420.0, 420.0 * (z1 - z0) / (x1 - x0), 20.0
    s = w / (x1 - x0)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{len(panels) * (w + 2 * pad):.0f}" '
           f'height="{h + 2 * pad + 20:.0f}" font-family="sans-serif" font-size="14">',
           '<rect width="100%" height="100%" fill="white"/>']
    for k, (title, (P, R, E)) in enumerate(panels):
        ox = k * (w + 2 * pad) + pad
        svg.append(f'<text x="{ox + w / 2:.1f}" y="16" text-anchor="middle">{title}</text>')
        svg.append(f'<g transform="translate({ox:.1f},{pad + 20:.1f})">')
        svg.append(f'<clipPath id="c{k}"><rect width="{w:.1f}" height="{h:.1f}"/></clipPath>')
        svg.append(f'<g clip-path="url(#c{k})" stroke="#5a3d1e" stroke-linecap="round" fill="none">')
        X = lambda p: (p[0] - x0) * s
        Z = lambda p: (z1 - p[2]) * s
        for a, b in E:
            width = max(0.6, (R[a] + R[b]) * s)
            svg.append(f'<line x1="{X(P[a]):.2f}" y1="{Z(P[a]):.2f}" x2="{X(P[b]):.2f}" '
                       f'y2="{Z(P[b]):.2f}" stroke-width="{width:.2f}"/>')
        deg = [0] * len(P)
        for a, b in E:
            deg[a] += 1
            deg[b] += 1
        svg.append('</g><g fill="#2a8a2a" stroke="none">')
        for i, p in enumerate(P):
            if i != 0 and deg[i] == 1:
                svg.append(f'<circle cx="{X(p):.2f}" cy="{Z(p):.2f}" r="1.8"/>')
        svg.append('</g></g>')
    svg.append('</svg>')
    open(out, "w").write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main(sys.argv)
