#!/usr/bin/env python3
"""Log-log plot (SVG, no dependencies) of grid-refinement errors against the grid spacing.

usage: scripts/plot_refinement.py DATA.csv OUT.svg "title"
DATA.csv: a header row "nodes,<quantity>,<quantity>,..." then one row per grid. The spacing is
h = (nodes_finest / nodes)^(1/3) (h = 1 on the finest grid). Each quantity is drawn with its
points and the observed order between successive grids; a dashed line of slope 2 is the
reference for second order.
"""
import csv
import math
import sys


def main():
    data_path, out_path, title = sys.argv[1], sys.argv[2], sys.argv[3]
    with open(data_path) as f:
        rows = list(csv.reader(f))
    names = rows[0][1:]
    nodes = [float(r[0]) for r in rows[1:]]
    values = [[abs(float(r[1 + q])) for r in rows[1:]] for q in range(len(names))]
    finest = max(nodes)
    h = [(finest / n) ** (1.0 / 3.0) for n in nodes]

    W, H, L, R, T, B = 640, 440, 80, 200, 50, 60
    xs = [math.log10(v) for v in h]
    ys = [math.log10(v) for vals in values for v in vals if v > 0]
    x0, x1 = min(xs) - 0.05, max(xs) + 0.05
    y0, y1 = math.floor(min(ys) - 0.2), math.ceil(max(ys) + 0.2)

    def px(lx):
        return L + (lx - x0) / (x1 - x0) * (W - L - R)

    def py(ly):
        return H - B - (ly - y0) / (y1 - y0) * (H - T - B)

    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>',
           f'<text x="{W / 2 - R / 2}" y="24" text-anchor="middle" font-size="14">{title}</text>',
           f'<rect x="{L}" y="{T}" width="{W - L - R}" height="{H - T - B}" fill="none" stroke="black"/>']
    for e in range(int(y0), int(y1) + 1):
        y = py(e)
        out.append(f'<line x1="{L}" y1="{y}" x2="{W - R}" y2="{y}" stroke="#ddd"/>')
        out.append(f'<text x="{L - 6}" y="{y + 4}" text-anchor="end">1e{e}</text>')
    for v, n in zip(h, nodes):
        x = px(math.log10(v))
        out.append(f'<line x1="{x}" y1="{T}" x2="{x}" y2="{H - B}" stroke="#eee"/>')
        out.append(f'<text x="{x}" y="{H - B + 16}" text-anchor="middle">{v:.2f}</text>')
        out.append(f'<text x="{x}" y="{H - B + 30}" text-anchor="middle" fill="#666">{int(n):,}</text>')
    out.append(f'<text x="{(L + W - R) / 2}" y="{H - 10}" text-anchor="middle">h / h_finest (grid nodes below)</text>')

    legend_y = T + 10
    for q, name in enumerate(names):
        c = colours[q % len(colours)]
        pts = [(px(math.log10(a)), py(math.log10(b))) for a, b in zip(h, values[q]) if b > 0]
        out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' % (c, " ".join(f"{x},{y}" for x, y in pts)))
        for x, y in pts:
            out.append(f'<circle cx="{x}" cy="{y}" r="4" fill="{c}"/>')
        orders = [math.log(values[q][i] / values[q][i + 1]) / math.log(h[i] / h[i + 1]) for i in range(len(h) - 1)]
        out.append(f'<text x="{W - R + 10}" y="{legend_y}" fill="{c}">{name}</text>')
        out.append(f'<text x="{W - R + 10}" y="{legend_y + 15}" fill="{c}">orders: {", ".join(f"{o:.2f}" for o in orders)}</text>')
        legend_y += 40
    # Slope-2 reference through the coarsest point of the first quantity.
    lx, ly = math.log10(h[0]), math.log10(values[0][0]) + 0.15
    ex = math.log10(h[-1])
    out.append(f'<line x1="{px(lx)}" y1="{py(ly)}" x2="{px(ex)}" y2="{py(ly - 2 * (lx - ex))}" stroke="black" stroke-dasharray="5,4"/>')
    out.append(f'<text x="{W - R + 10}" y="{legend_y}">- - - slope 2</text>')
    out.append("</svg>")
    with open(out_path, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
