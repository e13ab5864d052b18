"""A CAD pipeline in Python: a needle-tip trajectory → ncgear (design, teeth, STEP) → build123d
imports the STEP train and adds a shaft through the sun's bore and a hub behind it.

    python examples/python/pipeline.py [OUT_DIR]

Run in CI (scripts/check_python.sh) after the wheel is installed. Lengths in mm, angles in degrees.
"""
import pathlib
import sys
import time

import numpy as np
import build123d as bd

import ncgear

ROOT = pathlib.Path(__file__).resolve().parents[2]
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/python_pipeline")
out.mkdir(parents=True, exist_ok=True)

# 1. The target: the needle-tip trajectory (x_mm, y_mm per carrier degree), as a drawing gives it.
points = np.loadtxt(ROOT / "assets" / "trajectories" / "g1_ellipse.csv", delimiter=",", skiprows=1)

# 2. ncgear, typed results and keyword options: gears designed for module 2 mm (the whole tooth
#    count is a constraint of the fit, so the toothed train traces what the design states) within
#    a 40° pressure-angle limit and 2 mm of the points — whole teeth of module 2 cannot trace this
#    target closer —, their teeth (backlash 0.08 mm), the STEP solids (face width 20 mm, bore 10 mm).
design = ncgear.design(points, center=(0.0, 0.0), module=2.0, tol_mm=2.0, max_pressure_angle=40.0)
assert design.passed, design.verdict.failures
assert design.limits.pressure_angle_deg <= 40.0 and design.roundtrip.max_deviation_mm <= 2.0
train = ncgear.teeth(design, module=2.0, backlash=0.08)  # the design's own tooth count
assert train.passed and train.options.backlash_mm == 0.08, train.verdict.failures
# The toothed train is the designed one: nothing is scaled after the design, the tip path
# moves by less than 1 nm.
assert train.roundtrip.max_tip_shift_mm < 1e-6, train.roundtrip
face_width, bore = 20.0, 10.0
t0 = time.perf_counter()
files = ncgear.write_step(train, out, face_width=face_width, bore=bore)
t_step = time.perf_counter() - t0
print(f"l1 = {design.l1_mm:.3f} mm, l3 = {design.l3_mm:.3f} mm, z = {train.z}, "
      f"pressure angle {design.limits.pressure_angle_deg:.1f}° (≤ {design.limits.max_pressure_angle_deg:g}°), "
      f"max deviation {design.deviations.max():.4f} mm (toothed: {train.roundtrip.hausdorff_mm:.4f} mm)")
print(f"wrote {len(files)} STEP files in {1000 * t_step:.0f} ms: {', '.join(files)}")

# 3. build123d: the train as ncgear placed it, in the design's world frame.
gears = bd.import_step(out / "train.step")
solids = gears.solids()
assert len(solids) == 5, f"expected sun + 2 × (intermediate, planet), got {len(solids)}"

# 4. A shaft through the sun's bore (0.1 mm clearance) and a hub behind the sun, on the carrier
#    axis O; they must fit: no material shared with any gear.
o = train.placements["sun"].center_mm
shaft = bd.Pos(o[0], o[1], -30.0) * bd.Cylinder(
    bore / 2 - 0.1, face_width + 60.0, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN))
hub = bd.Pos(o[0], o[1], -12.0) * bd.Cylinder(
    14.0, 12.0, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN)) - shaft
def shared(a, b):
    common = a & b  # None when nothing is shared
    return 0.0 if common is None else common.volume


for s in solids:
    assert shared(s, shaft) < 1e-9 and shared(s, hub) < 1e-9, "shaft or hub hits a gear"
assembly = bd.Compound(children=[gears, shaft, hub], label="planting_arm_train")
bd.export_step(assembly, str(out / "pipeline.step"))

# 5. A line drawing of the assembled train (visible edges, isometric-ish view).
visible, _hidden = assembly.project_to_viewport((-150.0, -250.0, 220.0), viewport_up=(0, 0, 1))
size = max(*bd.Compound(children=visible).bounding_box().size)
svg = bd.ExportSVG(scale=160.0 / size, precision=2, line_weight=0.1)
svg.add_layer("visible")
svg.add_shape(visible, layer="visible")
svg.write(str(out / "pipeline.svg"))
sun_volume = solids[0].volume
print(f"build123d: {len(solids)} gears + shaft + hub; sun volume {sun_volume:.1f} mm³; "
      f"wrote {out / 'pipeline.step'} and {out / 'pipeline.svg'}")
