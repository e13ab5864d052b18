#!/usr/bin/env bash
# Draws the G1 target loop (assets/trajectories/g1_ellipse.csv) with real CAD and vector-graphics
# programs, as their users' files come: the fixtures under assets/drawings/ that tests/it/drawings.rs
# reads as "drawings nobody here made". Run once by hand (not in CI); the files are committed.
#
# Needs Debian's freecad (0.20.2), inkscape (1.2.2) and, for Inkscape's DXF extension,
# python3-cssselect python3-lxml python3-numpy:
#   apt-get install -y --no-install-recommends freecad inkscape python3-cssselect python3-lxml python3-numpy
#
# Writes assets/drawings/:
# - g1_freecad_spline.dxf  FreeCAD's DXF exporter (C++, AC1014) of a periodic B-spline
#                          interpolating the 360 points (Part.BSplineCurve.interpolate): one
#                          SPLINE, knots and control points written to 6 significant digits
# - g1_freecad_lines.dxf   FreeCAD's exporter of the polygon through the points: 360 LINEs,
#                          coordinates to 3 decimals
# - g1_inkscape.svg        Inkscape SVG: an A3 page in mm, the loop in layer TARGET and a
#                          carrier circle, frame and text (converted to paths) in layer SKETCH,
#                          both layers translate(210, 148.5) (the carrier axis at the page
#                          centre); Inkscape rewrote the loop in relative commands, 8 digits
# - g1_inkscape_px.svg     the same drawing in a px document: width/height bare numbers (px to
#                          the SVG specification; ncgear asks for --units px), the layers
#                          translate(793.7, 561.26) scale(3.7795...)
# - g1_inkscape.dxf        Inkscape's "Desktop Cutting Plotter" DXF (dxf_outlines, R14) of
#                          g1_inkscape.svg: the loop as 360 open SPLINE pieces on layer TARGET,
#                          y up, the page's lower left corner at the origin
set -euo pipefail
cd "$(dirname "$0")/.."
out=assets/drawings
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cat > "$tmp/export_g1.py" <<PY
import csv
import FreeCAD, Part, importDXF
with open("assets/trajectories/g1_ellipse.csv") as f:
    rows = list(csv.reader(f))[1:]
pts = [FreeCAD.Vector(float(x), float(y), 0) for x, y in rows]
doc = FreeCAD.newDocument("g1")
spline = Part.BSplineCurve()
spline.interpolate(pts, PeriodicFlag=True)
loop = doc.addObject("Part::Feature", "TargetLoop")
loop.Shape = spline.toShape()
poly = doc.addObject("Part::Feature", "TargetPolyline")
poly.Shape = Part.makePolygon(pts + [pts[0]])
doc.recompute()
importDXF.export([loop], "$out/g1_freecad_spline.dxf")
importDXF.export([poly], "$out/g1_freecad_lines.dxf")
PY
rm -f "$out"/g1_freecad_*.dxf
freecadcmd "$tmp/export_g1.py" > /dev/null

# The input an Inkscape user would have drawn: the loop as a Catmull-Rom Bézier path (as
# scripts/make_drawings.py draws it), y down, beside a sketch layer.
python3 - "$tmp" <<'PY'
import csv, sys
tmp = sys.argv[1]
rows = list(csv.reader(open("assets/trajectories/g1_ellipse.csv")))[1:]
pts = [(float(x), -float(y)) for x, y in rows]
n = len(pts)
f = lambda p: f"{p[0]:.6f},{p[1]:.6f}"
d = ["M" + f(pts[0])]
for i in range(n):
    p0, p1, p2, p3 = pts[(i - 1) % n], pts[i], pts[(i + 1) % n], pts[(i + 2) % n]
    c1 = (p1[0] + (p2[0] - p0[0]) / 6, p1[1] + (p2[1] - p0[1]) / 6)
    c2 = (p2[0] - (p3[0] - p1[0]) / 6, p2[1] - (p3[1] - p1[1]) / 6)
    d.append("C" + f(c1) + " " + f(c2) + " " + f(p2))
d = " ".join(d) + " Z"
def page(size, layer):
    return f'''<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" {size}>
  <g id="layer1" inkscape:groupmode="layer" inkscape:label="TARGET" transform="{layer}">
    <path id="target" d="{d}" style="fill:none;stroke:#000000;stroke-width:0.3"/>
  </g>
  <g id="layer2" inkscape:groupmode="layer" inkscape:label="SKETCH" transform="{layer}">
    <circle id="carrier_circle" cx="0" cy="0" r="95" style="fill:none;stroke:#0000ff;stroke-width:0.2"/>
    <rect id="frame" x="-200" y="-140" width="400" height="280" style="fill:none;stroke:#888888;stroke-width:0.2"/>
    <text id="label" x="-190" y="-125" style="font-size:8px;font-family:sans-serif">G1 needle-tip loop</text>
  </g>
</svg>
'''
open(f"{tmp}/mm.svg", "w").write(page('width="420mm" height="297mm" viewBox="0 0 420 297"', "translate(210,148.5)"))
s = 96 / 25.4
open(f"{tmp}/px.svg", "w").write(page(
    f'width="{420 * s:.4f}" height="{297 * s:.4f}" viewBox="0 0 {420 * s:.4f} {297 * s:.4f}"',
    f"translate({210 * s:.4f},{148.5 * s:.4f}) scale({s!r})"))
PY
# Inkscape converts the shapes and text to paths and rewrites the moved loop in its own notation.
actions="select-all:all;object-to-path;select-clear;select-by-id:target;transform-translate:10,0;transform-translate:-10,0"
inkscape "$tmp/mm.svg" --actions="$actions" --export-type=svg --export-filename="$out/g1_inkscape.svg" 2> /dev/null
inkscape "$tmp/px.svg" --actions="$actions" --export-type=svg --export-filename="$out/g1_inkscape_px.svg" 2> /dev/null
/usr/bin/python3 /usr/share/inkscape/extensions/dxf_outlines.py "$out/g1_inkscape.svg" > "$out/g1_inkscape.dxf"
# freecadcmd exits 0 when its script raises: check that every file came.
for f in g1_freecad_spline.dxf g1_freecad_lines.dxf g1_inkscape.svg g1_inkscape_px.svg g1_inkscape.dxf; do
    [ -s "$out/$f" ] || { echo "make_exporter_drawings: $out/$f was not written" >&2; exit 1; }
done
echo "wrote $out/g1_freecad_spline.dxf g1_freecad_lines.dxf g1_inkscape.svg g1_inkscape_px.svg g1_inkscape.dxf"
