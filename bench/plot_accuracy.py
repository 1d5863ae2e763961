#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""Plots the first table of bench/compare_accuracy.sh as an SVG: deviation p99 (and max, as a
bar above it) against triangle count, log-log, one mark per mesh.

Usage: bench/plot_accuracy.py TABLE.md OUT.svg
"""
import math
import sys


def rows(path):
    out = []
    for line in open(path, encoding="utf-8"):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 9 or not cells[3].replace(",", "").isdigit():
            if out:
                break  # the first table only
            continue
        out.append({"label": cells[0], "seconds": float(cells[1]),
                    "triangles": int(cells[3].replace(",", "")),
                    "p99": float(cells[7]), "max": float(cells[8])})
    return out


def main():
    data = rows(sys.argv[1])
    w, h, left, right, top, bottom = 900, 440, 70, 330, 30, 60
    tx = [math.log10(r["triangles"]) for r in data]
    x0, x1 = math.floor(min(tx) * 2) / 2, math.ceil(max(tx) * 2) / 2
    y0, y1 = -2.0, 0.5  # deviation 1 % .. 316 %

    def sx(t):
        return left + (math.log10(t) - x0) / (x1 - x0) * (w - left - right)

    def sy(d):
        return top + (y1 - math.log10(max(d, 1e-3))) / (y1 - y0) * (h - top - bottom)

    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
           'font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>']
    for e in range(int(x0 * 2), int(x1 * 2) + 1):
        x = left + (e / 2 - x0) / (x1 - x0) * (w - left - right)
        svg.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{h - bottom}" stroke="#ddd"/>')
        label = f"{10 ** (e / 2) / 1e6:.2g} M"
        svg.append(f'<text x="{x:.1f}" y="{h - bottom + 16}" text-anchor="middle">{label}</text>')
    for d in (0.01, 0.02, 0.05, 0.1, 0.25, 0.5, 1, 2):
        y = sy(d)
        svg.append(f'<line x1="{left}" y1="{y:.1f}" x2="{w - right}" y2="{y:.1f}" stroke="#ddd"/>')
        svg.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">{100 * d:g} %</text>')
    svg.append(f'<text x="{(left + w - right) / 2}" y="{h - 15}" text-anchor="middle">'
               'triangles (log)</text>')
    svg.append(f'<text transform="translate(16 {(top + h - bottom) / 2}) rotate(-90)" '
               'text-anchor="middle">deviation / local radius: p99 (dot), max (tick)</text>')
    for i, r in enumerate(data):
        colour = "#c0392b" if r["label"].startswith("OpenVDB") else "#1f6fb2"
        x, yp, ym = sx(r["triangles"]), sy(r["p99"]), sy(r["max"])
        svg.append(f'<line x1="{x:.1f}" y1="{yp:.1f}" x2="{x:.1f}" y2="{ym:.1f}" '
                   f'stroke="{colour}" stroke-width="1.5"/>')
        svg.append(f'<line x1="{x - 5:.1f}" y1="{ym:.1f}" x2="{x + 5:.1f}" y2="{ym:.1f}" '
                   f'stroke="{colour}" stroke-width="1.5"/>')
        svg.append(f'<circle cx="{x:.1f}" cy="{yp:.1f}" r="4.5" fill="{colour}"/>')
        svg.append(f'<text x="{x + 8:.1f}" y="{yp + 4:.1f}" fill="{colour}">{i + 1}</text>')
        svg.append(f'<text x="{w - right + 14}" y="{top + 14 + 18 * i}" fill="{colour}">'
                   f'{i + 1}. {r["label"]}, {r["seconds"]:.2f} s</text>')
    svg.append("</svg>")
    open(sys.argv[2], "w", encoding="utf-8").write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
