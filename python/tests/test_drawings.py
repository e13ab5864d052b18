"""`ncgear.read_trajectory`: the target loop read from DXF and SVG drawings as `ncgear design`
reads it (layer, id, units), and the drawings' refusals in the Python API's words."""
import json

import numpy as np
import pytest

import ncgear
from conftest import G1, ROOT, cli

DRAWINGS = ROOT / "assets" / "drawings"


def _csv_points():
    return np.loadtxt(G1, delimiter=",", skiprows=1)


def test_a_polygon_on_the_named_layer_is_the_csv_points():
    # The G1 polygon drawn by ezdxf on layer TARGET, beside two circles on SKETCH: its 360 vertices
    # are kept as drawn (a loop of straight segments is not resampled).
    pts = ncgear.read_trajectory(DRAWINGS / "g1_layers.dxf", layer="TARGET")
    assert pts.shape == (360, 2) and pts.dtype == np.float64
    assert np.abs(pts - _csv_points()).max() < 1e-9


def test_units_given_for_a_unitless_drawing_scale_it():
    mm = ncgear.read_trajectory(DRAWINGS / "g1_unitless.dxf", units="mm")
    cm = ncgear.read_trajectory(DRAWINGS / "g1_unitless.dxf", units="cm")
    assert np.abs(mm - _csv_points()).max() < 1e-9
    assert np.abs(cm - 10.0 * mm).max() < 1e-9


def test_a_curve_is_resampled_and_designs_as_the_cli_designs_the_file(tmp_path):
    spline = DRAWINGS / "g1_spline.dxf"
    pts = ncgear.read_trajectory(spline)
    assert pts.shape == (720, 2)
    # Uniform in arc length: the chords equal the arc spacing (a chord is shorter only where the
    # loop turns sharply: G1's tightest turn, radius ≈ 1 mm, shortens a few chords, by ≤ 3 %).
    chords = np.hypot(*np.diff(np.vstack([pts, pts[:1]]), axis=0).T)
    assert np.median(chords) == pytest.approx(chords.max(), rel=1e-4)
    short = np.flatnonzero(chords < 0.999 * chords.max())
    assert len(short) <= 5 and short.max() - short.min() < 8 and chords.min() > 0.96 * chords.max()
    d = ncgear.design(pts)
    cli("design", spline, "--out", tmp_path)
    ref = json.loads((tmp_path / "design.json").read_text())
    assert d.l1_mm == ref["l1_mm"] and d.l3_mm == ref["l3_mm"]
    assert d.center_distance_mm == ref["center_distance_mm"]


def test_an_svg_in_px_with_a_transform_is_the_mm_drawing():
    # The same Bézier path written in px inside a transformed group, and in mm: the same points
    # (its root size in px, the path drawn shifted under a scale and a translation).
    px = ncgear.read_trajectory(DRAWINGS / "g1_px.svg")
    mm = ncgear.read_trajectory(DRAWINGS / "g1_bezier.svg")
    assert px.shape == mm.shape == (720, 2)
    assert np.abs(px - mm).max() < 1e-4


@pytest.mark.parametrize("name, kwargs, says", [
    ("g1_layers.dxf", {}, 'pick one with layer="NAME"'),
    ("g1_layers.dxf", {"layer": "NOPE"}, 'no closed loop with layer "NOPE"'),
    ("g1_unitless.dxf", {}, 'units="mm"|"cm"|"m"|"in"|"px"'),
    ("g1_open.dxf", {}, "is open"),
    ("g1_looped_spike.dxf", {}, "runs back along itself"),
    ("g1_looped_junction.dxf", {}, '3 ends meet'),
    ("g1_looped_junction.dxf", {}, 'layer="NAME"'),
])
def test_a_bad_drawing_is_an_error_in_python_words(name, kwargs, says):
    with pytest.raises(ncgear.NcgearError) as e:
        ncgear.read_trajectory(DRAWINGS / name, **kwargs)
    assert says in str(e.value) and "--" not in str(e.value)


def test_an_unknown_unit_names_the_argument():
    with pytest.raises(ncgear.NcgearError, match=r'units="furlong".*mm, cm, m, in or px'):
        ncgear.read_trajectory(DRAWINGS / "g1_unitless.dxf", units="furlong")


LOOPED = ROOT / "assets" / "trajectories" / "g1_looped.csv"


@pytest.mark.parametrize("name", [
    "g1_looped_spline.dxf", "g1_looped_bulge.dxf", "g1_looped_lines.dxf", "g1_looped_px.svg",
])
def test_a_looped_drawing_designs_as_its_csv(name):
    """A path that crosses itself (a small loop) drawn four ways designs the CSV's train: l1 and
    l3 within 1e-3 mm of the CSV's (the LINEs exactly: their vertices are the CSV's points)."""
    csv = ncgear.design(LOOPED)
    assert abs(csv.l1_mm - 90.0) < 1e-3 and abs(csv.l3_mm - 260.0) < 1e-3
    d = ncgear.design(ncgear.read_trajectory(DRAWINGS / name))
    assert abs(d.l1_mm - csv.l1_mm) < 1e-3 and abs(d.l3_mm - csv.l3_mm) < 1e-3
    if name == "g1_looped_lines.dxf":
        assert d.l1_mm == csv.l1_mm and d.l3_mm == csv.l3_mm
