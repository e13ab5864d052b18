#!/usr/bin/env python3
"""Writes assets/compare/g1_track.csv: a synthetic high-speed-camera record of the bundled G1
design's needle tip (the example of docs/compare.md and scripts/check_schemas.sh).

From the design's traced path (`ncgear simulate assets/transplanter/g1_design.json`,
traced.csv, every 0.1° of carrier angle, interpolated linearly): 2.1 turns at 120 rpm filmed at
500 frames/s, the speed ramping from -2 % to +2 %, image pixels (y down) at 3.2 px/mm, the
camera turned 12°, 0.3 mm Gaussian noise, 2 % of the frames glitching 3-15 mm; frame numbers.
Usage: scripts/make_compare_track.py TRACED.csv > assets/compare/g1_track.csv
"""
import csv
import math
import random
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
xs = [float(r["arm1_x_mm"]) for r in rows]
ys = [float(r["arm1_y_mm"]) for r in rows]
n = len(xs)


def tip(phi):
    f = (phi % (2 * math.pi)) / (2 * math.pi) * n
    k = int(f) % n
    a = f - int(f)
    j = (k + 1) % n
    return xs[k] + a * (xs[j] - xs[k]), ys[k] + a * (ys[j] - ys[k])


rng = random.Random(67)
rpm, fps, turns = 120.0, 500.0, 2.1
w0 = 2 * math.pi * rpm / 60
span = turns * 60 / rpm
theta, px_per_mm, ox, oy = math.radians(12.0), 3.2, -300.0, 150.0
print("frame,x (px),y (px)")
for i in range(int(span * fps)):
    t = i / fps
    phi = 0.9 + w0 * (t + 0.02 * (t * t / span - t))
    x, y = tip(phi)
    x += rng.gauss(0, 0.3)
    y += rng.gauss(0, 0.3)
    if rng.random() < 0.02:
        a, r = rng.uniform(0, 2 * math.pi), rng.uniform(3, 15)
        x, y = x + r * math.cos(a), y + r * math.sin(a)
    # design = R(theta)·(u, -v)/px_per_mm + o  →  image (u, v)
    dx, dy = x - ox, y - oy
    c, s = math.cos(-theta), math.sin(-theta)
    u, v = (c * dx - s * dy) * px_per_mm, (s * dx + c * dy) * px_per_mm
    print(f"{i},{u:.3f},{-v:.3f}")
