#!/usr/bin/env python3
"""Independent check of the DXF files written by the tests: every DXF under the given
directory (default target/test-dxf) must open with ezdxf, carry $INSUNITS = 4 (mm) when it is R2000+,
and hold closed polylines (LWPOLYLINE for R2010, POLYLINE for R12) with >= 3 vertices and no
duplicated end vertex (an open sector pair's pitch arcs, in files named `*sector*`, are open). If a `<name>_points/` CSV is next to it, the outline polylines must match
those points within the chord tolerance (vertices of the DXF are a subset of the CSV points).

Usage: python tests/ezdxf_check.py [DIR]
"""
import csv
import glob
import math
import os
import sys

import ezdxf
from ezdxf import recover


def check(path):
    try:
        doc = ezdxf.readfile(path)
    except Exception:
        doc, _auditor = recover.readfile(path)
    msp = doc.modelspace()
    ver = doc.dxfversion
    polys = []
    for e in msp:
        t = e.dxftype()
        if t == "LWPOLYLINE":
            pts = [(p[0], p[1]) for p in e.get_points("xy")]
            polys.append((e.dxf.layer, pts, e.closed))
        elif t == "POLYLINE":
            pts = [(v.dxf.location.x, v.dxf.location.y) for v in e.vertices]
            polys.append((e.dxf.layer, pts, e.is_closed))
        elif t == "SPLINE":
            raise AssertionError(f"{path}: SPLINE entity found")
    assert polys, f"{path}: no polylines"
    if ver != "AC1009":
        assert doc.header.get("$INSUNITS") == 4, f"{path}: $INSUNITS = {doc.header.get('$INSUNITS')}"
        assert all(msp.query("LWPOLYLINE")), f"{path}: R2000+ file without LWPOLYLINE"
    for layer, pts, closed in polys:
        # Only an open sector's pitch curve is an arc; every outline is closed.
        sector_arc = "sector" in os.path.basename(path) and layer.endswith("_PITCH")
        assert closed or sector_arc, f"{path}: open polyline on {layer}"
        assert len(pts) >= 3, f"{path}: polyline on {layer} has {len(pts)} vertices"
        assert math.dist(pts[0], pts[-1]) > 1e-9, f"{path}: duplicated end vertex on {layer}"
    return ver, len(polys), polys


def match_points(path, polys):
    """DXF vertices must be a subset (within 1e-6 mm) of the unsimplified points written by the
    test next to it (`<prefix>_points/<layer lower-case>.txt`, `x y 0` per line)."""
    import bisect

    stem = os.path.splitext(os.path.basename(path))[0]
    checked = 0
    for d in glob.glob(os.path.join(os.path.dirname(path), "*_points")):
        prefix = os.path.basename(d)[: -len("_points")]
        if not stem.startswith(prefix):
            continue
        for layer, pts, _closed in polys:
            txt = os.path.join(d, layer.lower() + ".txt")
            if not os.path.exists(txt):
                continue
            ref = sorted(tuple(map(float, line.split()[:2])) for line in open(txt) if line.strip())
            xs = [p[0] for p in ref]
            for x, y in pts:
                i = bisect.bisect_left(xs, x - 1e-6)
                ok = False
                while i < len(ref) and ref[i][0] <= x + 1e-6:
                    if abs(ref[i][1] - y) <= 1e-6:
                        ok = True
                        break
                    i += 1
                assert ok, f"{path}: vertex ({x}, {y}) on {layer} is not on the outline in {txt}"
            checked += 1
    return checked


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join("target", "test-dxf")
    files = sorted(glob.glob(os.path.join(root, "**", "*.dxf"), recursive=True))
    if not files:
        print(f"no DXF files under {root}", file=sys.stderr)
        return 1
    for f in files:
        ver, n, polys = check(f)
        m = match_points(f, polys)
        print(f"ok {f}: {ver}, {n} closed polylines, {m} matched against the point lists")
    return 0


if __name__ == "__main__":
    sys.exit(main())
