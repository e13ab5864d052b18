"""Renders a STEP file of ncgear (e.g. train.step) to a shaded PNG: OCCT tessellation, matplotlib.

    python examples/python/render_train.py OUT/train.step docs/train_step.png

Made the README picture; not part of CI (needs matplotlib).
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from OCP.BRep import BRep_Tool
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS

src, dst = sys.argv[1], sys.argv[2]
r = STEPControl_Reader()
assert r.ReadFile(src) == IFSelect_RetDone
r.TransferRoots()
shape = r.OneShape()
BRepMesh_IncrementalMesh(shape, 0.05, False, 0.2, True)
colours = ["#b0b7c3", "#d9a441", "#5b8cc9", "#d9a441", "#5b8cc9"]
fig = plt.figure(figsize=(8, 8), dpi=100)
ax = fig.add_subplot(projection="3d")
light = np.array([-0.4, -0.5, 0.8]) / np.linalg.norm([-0.4, -0.5, 0.8])
sol = TopExp_Explorer(shape, TopAbs_SOLID)
k, lo, hi = 0, np.full(3, np.inf), np.full(3, -np.inf)
while sol.More():
    tris = []
    ex = TopExp_Explorer(sol.Current(), TopAbs_FACE)
    while ex.More():
        f = TopoDS.Face(ex.Current())
        loc = TopLoc_Location()
        t = BRep_Tool.Triangulation_s(f, loc)
        if t is not None:
            tr = loc.Transformation()
            p = [t.Node(i).Transformed(tr) for i in range(1, t.NbNodes() + 1)]
            p = np.array([[q.X(), q.Y(), q.Z()] for q in p])
            for i in range(1, t.NbTriangles() + 1):
                a, b, c = t.Triangle(i).Get()
                tri = p[[a - 1, b - 1, c - 1]]
                if f.Orientation() == TopAbs_REVERSED:
                    tri = tri[::-1]
                tris.append(tri)
        ex.Next()
    tris = np.array(tris)
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True) + 1e-30
    shade = 0.35 + 0.65 * np.clip(n @ light, 0, 1)
    base = np.array(matplotlib.colors.to_rgb(colours[k % len(colours)]))
    ax.add_collection3d(Poly3DCollection(tris, facecolors=np.outer(shade, base), linewidths=0))
    lo, hi = np.minimum(lo, tris.reshape(-1, 3).min(0)), np.maximum(hi, tris.reshape(-1, 3).max(0))
    k += 1
    sol.Next()
c, h = (lo + hi) / 2, (hi - lo).max() / 2
ax.set_xlim(c[0] - h, c[0] + h)
ax.set_ylim(c[1] - h / 2.2, c[1] + h / 2.2)
ax.set_zlim(c[2] - h / 4, c[2] + h / 4)
ax.set_box_aspect((2.2, 1, 0.5), zoom=1.15)
ax.view_init(elev=35, azim=-60)
ax.set_axis_off()
fig.tight_layout()
fig.savefig(dst, bbox_inches="tight", facecolor="white")
print(f"wrote {dst} ({k} solids)")
