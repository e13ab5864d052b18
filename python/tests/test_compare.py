"""``ncgear.compare``: the bundled synthetic track of G1 (assets/compare/g1_track.csv: 500
frames/s, 3.2 px/mm, the camera turned 12°, 0.3 mm noise, 2 % glitches) registered in-process,
``compare.json`` number for number as the CLI writes it, the frames as arrays, the camera
recovered, and the options read by the library (its keys and checks) naming the keyword at
fault."""
import json

import numpy as np
import pytest

import ncgear
from conftest import ROOT, cli

TRACK = ROOT / "assets" / "compare" / "g1_track.csv"
DESIGN = ROOT / "assets" / "transplanter" / "g1_design.json"
OPTS = dict(fps=500, px_per_mm=3.2, spacing=140)


@pytest.fixture(scope="module")
def c():
    return ncgear.compare(TRACK, DESIGN, **OPTS)


def test_compare_is_the_cli_compare_json_typed(tmp_path, c):
    cli("compare", TRACK, "--design", DESIGN, "--fps", 500, "--px-per-mm", 3.2, "--spacing", 140,
        "--out", tmp_path)
    ref = json.loads((tmp_path / "compare.json").read_text())
    got = c.to_dict()
    ref.pop("files", None)
    assert got == ref
    # Typed: the fields of compare.json as the report classes.
    assert isinstance(c, ncgear.reports.CompareReport)
    assert c.registration.rotation_deg.value == ref["registration"]["rotation_deg"]["value"]


def test_compare_recovers_the_camera_and_flags_the_glitches(c):
    r = c.registration
    assert abs(r.rotation_deg.value - 12.0) < 0.05
    assert abs(r.rpm.value - 120.0) < 0.1
    assert abs(r.noise_mm - 0.3) < 0.02
    n = c.track.frames
    assert c.frame_tip_mm.shape == (n, 2) and c.frame_residual_mm.shape == (n, 2)
    assert c.frame_carrier_rad.shape == (n,) and c.frame_outlier.dtype == bool
    assert int(c.frame_outlier.sum()) == r.outliers > 0
    # The good frames' residuals are the noise: their RMS is the fit's σ per axis (×√2).
    good = c.frame_residual_mm[~c.frame_outlier]
    rms = float(np.sqrt((good**2).sum(axis=1).mean()))
    assert abs(rms - c.deviation.frame_rms_mm) < 1e-9
    # No deviation above the noise on a track of the design itself.
    assert c.deviation.rms_mm < 2.0 * c.deviation.noise_floor_mm
    assert c.dynamics is None


def test_compare_options_are_the_librarys():
    with pytest.raises(ncgear.NcgearError, match="px_pr_mm"):
        ncgear.compare(TRACK, DESIGN, fps=500, px_pr_mm=3.2)
    with pytest.raises(ncgear.NcgearError, match="calibration"):
        ncgear.compare(TRACK, DESIGN, fps=500, calibration=(0.0, 0.0, 1.0))
    with pytest.raises(ncgear.NcgearError, match="px_per_mm"):
        ncgear.compare(TRACK, DESIGN, fps=500, px_per_mm=3.2, fit_scale=True)
    with pytest.raises(ncgear.NcgearError, match="pixels"):
        ncgear.compare(TRACK, DESIGN, fps=500)
    # numpy values are taken as numbers.
    d = ncgear.compare(TRACK, DESIGN, fps=np.float64(500), px_per_mm=np.float32(3.2),
                       columns=np.array(["1", "2", "3"]), drift_order=1)
    assert d.registration.drift_deg == ()
