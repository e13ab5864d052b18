"""Every STEP file read back by OCCT (cadquery-ocp): one valid closed solid per gear, volume =
outline area × face width (minus the bore) within 1e-6 relative, boxes and placements as
designed, and the train's gears not intersecting at carrier angle 0."""
import itertools
import math

import numpy as np
import pytest

import ncgear
from occt import bbox, closed_shells, common_volume, is_valid, read_solids, volume

W, BORE = 20.0, 10.0


def area(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def placed(p, centre, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.column_stack([centre[0] + c * p[:, 0] - s * p[:, 1], centre[1] + s * p[:, 0] + c * p[:, 1]])


def expected_box(p):
    return (p[:, 0].min(), p[:, 1].min(), 0.0, p[:, 0].max(), p[:, 1].max(), W)


def check_solid(solid, outline, box_points):
    assert is_valid(solid) and closed_shells(solid) == [True]
    v = area(outline) * W - math.pi * (BORE / 2) ** 2 * W
    assert volume(solid) == pytest.approx(v, rel=1e-6)
    assert np.allclose(bbox(solid), expected_box(box_points), atol=1e-6)


@pytest.fixture(scope="module")
def train_files(g1_train, out):
    files = ncgear.write_step(g1_train, out / "step", face_width=W, bore=BORE)
    return {f.rsplit("/", 1)[-1][:-5]: f for f in files}


@pytest.mark.parametrize("gear", ["sun", "intermediate", "planet"])
def test_each_gear_is_one_valid_solid_of_the_outline_volume_about_its_centre(g1_train, train_files, gear):
    shape, solids = read_solids(train_files[gear])
    assert len(solids) == 1
    o = g1_train.outlines[gear]
    check_solid(solids[0], o, o)


def check_assembly(path, parts, placements):
    shape, solids = read_solids(path)
    assert is_valid(shape)
    assert len(solids) == len(placements)
    # Match each occurrence to the solid with its designed box (centre and angle as designed).
    left = list(solids)
    for occ, pl in placements.items():
        world = placed(parts[pl.part], pl.center_mm, pl.angle_rad)
        want = expected_box(world)
        k = min(range(len(left)), key=lambda i: np.abs(np.subtract(bbox(left[i]), want)).max())
        check_solid(left[k], parts[pl.part], world)
        left.pop(k)
    # No two gears overlap in the assembled position.
    v = volume(solids[0])
    for a, b in itertools.combinations(solids, 2):
        assert abs(common_volume(a, b)) < 1e-9 * v


def test_train_step_is_the_whole_train_at_carrier_angle_0_without_intersections(g1_train, train_files):
    assert set(g1_train.placements) == {
        "sun", "arm1_intermediate", "arm1_planet", "arm2_intermediate", "arm2_planet"}
    check_assembly(train_files["train"], g1_train.outlines, g1_train.placements)


def test_pair_step_is_the_pair_at_its_start(out):
    p = ncgear.pair("phi - 0.08*sin(2*phi)", teeth=24, module=1.5)
    [f] = ncgear.write_step(p, out / "pair_step", face_width=W, bore=BORE)
    check_assembly(f, p.outlines, p.placements)
