#!/usr/bin/env python3
"""Draws the G1 target loop (assets/trajectories/g1_ellipse.csv) as DXF and SVG files made by
other tools than ncgear (ezdxf, svgwrite), the fixtures of tests/it/drawings.rs.

Run once, from the repository root, in a virtual environment:

    python3 -m venv /tmp/venv-draw && /tmp/venv-draw/bin/pip install ezdxf svgwrite
    /tmp/venv-draw/bin/python scripts/make_drawings.py

Writes assets/drawings/:

- g1_spline.dxf     a SPLINE: cubic B-spline interpolating the 360 points (chord-length
                    parameters, ezdxf.math.global_bspline_interpolation), stored as control
                    points + knots (a real B-spline, no fit points), $INSUNITS = mm
- g1_bulge.dxf      a closed LWPOLYLINE through every other point, each pair of segments the
                    circular arc through three consecutive points (bulges), $INSUNITS = mm
- g1_lines.dxf      360 LINE entities end to end, $INSUNITS = cm (coordinates / 10)
- g1_layers.dxf     the loop on layer TARGET plus two circles on layer SKETCH
- g1_open.dxf       the loop without its last 30 points, not closed (bad)
- g1_unitless.dxf   the loop with $INSUNITS = 0 (bad unless --units is given)
- g1_figure8.dxf    a closed figure eight (self-intersecting, bad)
- g1_bezier.svg     one <path> of cubic Béziers (Catmull-Rom through the points), width/height
                    in mm, viewBox in mm, y flipped (SVG y points down)
- g1_px.svg         the same path in shifted mm coordinates under a transform
                    scale(96/25.4) translate(...), root size in px (96 px per inch)
- g1_unitless.svg   the path with a root width/height without units and no viewBox (bad)
- g1_open.svg       the path without its closing segment and last 30 points (bad)

and, from assets/trajectories/g1_looped.csv (a loop that crosses itself; `make_drawings.py
looped` writes these only):

- g1_looped_spline.dxf    as g1_spline.dxf
- g1_looped_bulge.dxf     as g1_bulge.dxf
- g1_looped_lines.dxf     360 LINE entities end to end, mm, in travel order
- g1_looped_px.svg        as g1_px.svg (px, under a transform)
- g1_looped_junction.dxf  the LINEs and one more LINE from a vertex (three ends meet, bad)
- g1_looped_spike.dxf     the closed LWPOLYLINE with a 20 mm spike out and back at vertex 100 (bad)
"""
import csv
import math
import sys
from pathlib import Path

import ezdxf
import svgwrite
from ezdxf.math import global_bspline_interpolation

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "assets" / "drawings"


def g1_points(name="g1_ellipse.csv"):
    with open(ROOT / "assets" / "trajectories" / name) as f:
        rows = list(csv.reader(f))
    return [(float(r[0]), float(r[1])) for r in rows[1:] if r]


def new_doc(units):
    doc = ezdxf.new("R2010", units=units)
    return doc, doc.modelspace()


def circle_center(a, b, c):
    ax, ay = a
    bx, by = b
    cx, cy = c
    d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    ux = ((ax * ax + ay * ay) * (by - cy) + (bx * bx + by * by) * (cy - ay) + (cx * cx + cy * cy) * (ay - by)) / d
    uy = ((ax * ax + ay * ay) * (cx - bx) + (bx * bx + by * by) * (ax - cx) + (cx * cx + cy * cy) * (bx - ax)) / d
    return ux, uy


def bulge(center, p, q):
    """Bulge of the arc about `center` from p to q (the short way): tan(θ/4), θ signed, CCW > 0."""
    (cx, cy), (px, py), (qx, qy) = center, p, q
    u, v = (px - cx, py - cy), (qx - cx, qy - cy)
    theta = math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1])
    return math.tan(theta / 4)


def bulge_vertices(pts):
    n = len(pts)
    out = []
    for i in range(0, n, 2):
        a, m, b = pts[i], pts[(i + 1) % n], pts[(i + 2) % n]
        c = circle_center(a, m, b)
        out.append((a[0], a[1], 0, 0, bulge(c, a, m)))
        out.append((m[0], m[1], 0, 0, bulge(c, m, b)))
    return out


def write_spline_and_bulge(pts, prefix):
    """``<prefix>_spline.dxf`` and ``<prefix>_bulge.dxf`` of the points, mm."""
    doc, msp = new_doc(4)
    bs = global_bspline_interpolation(pts + [pts[0]], degree=3, method="chord")
    msp.add_open_spline(bs.control_points, degree=3, knots=bs.knots())
    doc.saveas(OUT / f"{prefix}_spline.dxf")

    doc, msp = new_doc(4)
    msp.add_lwpolyline(bulge_vertices(pts), format="xyseb", close=True)
    doc.saveas(OUT / f"{prefix}_bulge.dxf")


def write_dxfs(pts):
    write_spline_and_bulge(pts, "g1")

    doc, msp = new_doc(5)
    cm = [(x / 10, y / 10) for x, y in pts]
    for i in range(len(cm)):
        msp.add_line(cm[i], cm[(i + 1) % len(cm)])
    doc.saveas(OUT / "g1_lines.dxf")

    doc, msp = new_doc(4)
    doc.layers.add("TARGET")
    doc.layers.add("SKETCH")
    msp.add_lwpolyline(pts, close=True, dxfattribs={"layer": "TARGET"})
    for cx in (0.0, 300.0):
        circle = [(cx + 20 * math.cos(t * math.tau / 90), 20 * math.sin(t * math.tau / 90)) for t in range(90)]
        msp.add_lwpolyline(circle, close=True, dxfattribs={"layer": "SKETCH"})
    doc.saveas(OUT / "g1_layers.dxf")

    doc, msp = new_doc(4)
    msp.add_lwpolyline(pts[:-30], close=False)
    doc.saveas(OUT / "g1_open.dxf")

    doc, msp = new_doc(0)
    msp.add_lwpolyline(pts, close=True)
    doc.saveas(OUT / "g1_unitless.dxf")

    doc, msp = new_doc(4)
    eight = [(150 + 40 * math.sin(2 * t * math.tau / 200), 40 * math.sin(t * math.tau / 200)) for t in range(200)]
    msp.add_lwpolyline(eight, close=True)
    doc.saveas(OUT / "g1_figure8.dxf")


def bezier_d(pts, closed=True, fmt="{:.9f}"):
    """Uniform Catmull-Rom through the points as cubic Béziers: controls P_i + (P_{i+1} − P_{i−1})/6
    and P_{i+1} − (P_{i+2} − P_i)/6."""
    n = len(pts)
    f = lambda p: fmt.format(p[0]) + "," + fmt.format(p[1])
    d = ["M" + f(pts[0])]
    last = n if closed else n - 1
    for i in range(last):
        p0, p1, p2, p3 = pts[(i - 1) % n], pts[i], pts[(i + 1) % n], pts[(i + 2) % n]
        c1 = (p1[0] + (p2[0] - p0[0]) / 6, p1[1] + (p2[1] - p0[1]) / 6)
        c2 = (p2[0] - (p3[0] - p1[0]) / 6, p2[1] - (p3[1] - p1[1]) / 6)
        d.append("C" + f(c1) + " " + f(c2) + " " + f(p2))
    if closed:
        d.append("Z")
    return " ".join(d)


def write_looped(pts):
    write_spline_and_bulge(pts, "g1_looped")

    for name, extra in (("g1_looped_lines.dxf", False), ("g1_looped_junction.dxf", True)):
        doc, msp = new_doc(4)
        for i in range(len(pts)):
            msp.add_line(pts[i], pts[(i + 1) % len(pts)])
        if extra:
            msp.add_line(pts[200], (pts[200][0] + 15.0, pts[200][1] + 5.0))
        doc.saveas(OUT / name)

    doc, msp = new_doc(4)
    (x, y), (x1, y1) = pts[100], pts[101]
    n = math.hypot(y1 - y, x - x1)
    tip = (x + 20 * (y1 - y) / n, y + 20 * (x - x1) / n)
    msp.add_lwpolyline(pts[:101] + [tip] + pts[100:], close=True)
    doc.saveas(OUT / "g1_looped_spike.dxf")

    write_px_svg(pts, "g1_looped_px.svg")


def write_px_svg(pts, name):
    """The loop as Béziers in shifted mm coordinates under scale(96/25.4) translate(...), root in px."""
    flipped = [(x, -y) for x, y in pts]
    xs, ys = [p[0] for p in flipped], [p[1] for p in flipped]
    x0, y0 = min(xs) - 10, min(ys) - 10
    w, h = max(xs) - x0 + 10, max(ys) - y0 + 10
    px = 96 / 25.4
    dx, dy = -x0 + 7, -y0 + 3  # the path is drawn shifted; its transform shifts it back
    shifted = [(x + dx, y + dy) for x, y in flipped]
    svg = svgwrite.Drawing(OUT / name, size=(f"{w * px:.3f}px", f"{h * px:.3f}px"), profile="full")
    g = svg.g(transform=f"scale({px!r})")
    g.add(svg.path(d=bezier_d(shifted), id="target", transform=f"translate({-dx!r} {-dy!r})", fill="none", stroke="black"))
    svg.add(g)
    svg.save()


def write_svgs(pts):
    flipped = [(x, -y) for x, y in pts]  # SVG y points down
    xs, ys = [p[0] for p in flipped], [p[1] for p in flipped]
    x0, y0 = min(xs) - 10, min(ys) - 10
    w, h = max(xs) - x0 + 10, max(ys) - y0 + 10

    svg = svgwrite.Drawing(OUT / "g1_bezier.svg", size=(f"{w:.6f}mm", f"{h:.6f}mm"), profile="full")
    svg.viewbox(x0, y0, w, h)
    svg.add(svg.path(d=bezier_d(flipped), id="target", fill="none", stroke="black", stroke_width=0.2))
    svg.save()

    write_px_svg(pts, "g1_px.svg")

    svg = svgwrite.Drawing(OUT / "g1_unitless.svg", size=(f"{w:.3f}", f"{h:.3f}"), profile="full")
    svg.add(svg.path(d=bezier_d(flipped), id="target", fill="none", stroke="black"))
    svg.save()

    svg = svgwrite.Drawing(OUT / "g1_open.svg", size=(f"{w:.6f}mm", f"{h:.6f}mm"), profile="full")
    svg.viewbox(x0, y0, w, h)
    svg.add(svg.path(d=bezier_d(flipped[:-30], closed=False), id="target", fill="none", stroke="black"))
    svg.save()


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    looped = g1_points("g1_looped.csv")
    assert len(looped) == 360
    write_looped(looped)
    if sys.argv[1:] == ["looped"]:
        return
    pts = g1_points()
    assert len(pts) == 360
    write_dxfs(pts)
    write_svgs(pts)


if __name__ == "__main__":
    main()
