"""The Python API equals the CLI: the typed reports hold every key and number of the CLI's JSON,
the keyword options reach the library, the STEP bytes and error messages agree."""
import dataclasses
import json
import math

import numpy as np
import pytest

import ncgear
from ncgear import reports
from conftest import G1, ROOT, _same, cli


def _without(d, *keys):
    return {k: v for k, v in d.items() if k not in keys}


def test_design_of_g1_is_the_cli_design_json_typed(g1, out):
    cli("design", G1, "--out", out / "cli")
    ref = json.loads((out / "cli" / "design.json").read_text())
    # Every key and number of design.json, bit for bit (timings are wall-clock).
    assert _without(g1.to_dict(), "timings_ms") == _without(ref, "timings_ms")
    _same(g1, {**ref, "timings_ms": g1.to_dict()["timings_ms"]})
    assert isinstance(g1, reports.DesignReport) and isinstance(g1.limits, reports.LimitsSummary)
    assert isinstance(g1.l1_mm, float) and abs(g1.l1_mm - 90.0) < 0.01 and abs(g1.l3_mm - 170.0) < 0.01
    assert isinstance(g1.checks[0], reports.Check) and g1.checks[0].passed is True
    assert g1.gears.sun.pitch.shape == (3600, 2) and g1.gears.sun.angle_at_zero_deg is None
    assert g1.target_points.shape == (360, 2) and g1.fourier.a.ndim == 1
    assert g1.verdict == reports.Verdict(passed=True, failures=())
    # The per-point deviations agree with the report's round trip (3600 vs its own sampling).
    assert g1.deviations.shape == (360,) and g1.deviations.dtype == np.float64
    assert abs(g1.deviations.max() - ref["roundtrip"]["max_deviation_mm"]) < 2e-3
    with pytest.raises(dataclasses.FrozenInstanceError):
        g1.l1_mm = 0.0
    with pytest.raises(ValueError, match="read-only"):
        g1.gears.sun.pitch[0, 0] = 0.0


def test_design_from_an_array_equals_design_from_the_file(g1):
    pts = np.asarray(g1.target_points)
    d = ncgear.design(pts)
    assert d.l1_mm == pytest.approx(g1.l1_mm, rel=1e-9)
    assert d.center_distance_mm == pytest.approx(g1.center_distance_mm, rel=1e-9)
    # Any float array of shape (N, 2) — float32, Fortran order, a list — is the same trajectory.
    assert ncgear.design(np.asfortranarray(pts)).l1_mm == d.l1_mm
    assert ncgear.design(pts.tolist()).l1_mm == d.l1_mm


@pytest.mark.parametrize("options, holds", [
    ({"max_pressure_angle": 40.0}, lambda d: d.limits.max_pressure_angle_deg == pytest.approx(40.0)),
    ({"min_concave_radius": 15.0}, lambda d: d.limits.min_concave_radius_mm == 15.0),
    ({"min_convex_radius": 8.0}, lambda d: d.limits.min_convex_radius_mm == 8.0),
    ({"convexity": True}, lambda d: math.isinf(d.limits.min_concave_radius_mm)),
    ({"ratio_bounds": (0.4, 2.5)}, lambda d: d.limits.ratio_bounds == (0.4, 2.5)),
    ({"limits": False}, lambda d: d.limits.enabled is False),
    ({"module": 2.0}, lambda d: d.module is not None and d.module.module_mm == 2.0),
    ({"samples": 1000}, lambda d: d.gears.planet.pitch.shape == (1000, 2)),
    ({"order": 8}, lambda d: d.fourier.order == 8),
    ({"route": "bd", "w1": 0.7}, lambda d: d.patent_route.note.startswith("route Bd, w1 = 0.7")),
    ({"refine": "on", "refine_order": 8}, lambda d: d.refinement is not None and d.refinement.order == 8),
    ({"refine": "on", "smooth": 40}, lambda d: d.fit is not None and d.fit.start_smoothing_harmonics == 40),
    ({"refine": "on", "smooth": 40, "fit": False}, lambda d: d.fit is None),
])
def test_each_design_keyword_reaches_the_library(options, holds):
    assert holds(ncgear.design(G1, **options)), options


@pytest.mark.parametrize("arg, value", [
    ("order", 0), ("tol_mm", -1.0), ("refine_order", 0), ("w1", 2.0), ("k_max", 1000),
    ("grid", 10), ("dense", 10), ("samples", 10), ("ratio_bounds", (2.0, 3.0)),
    ("center", (math.nan, 0.0)), ("max_pressure_angle", 10.0), ("min_concave_radius", -1.0),
    ("min_convex_radius", -1.0), ("smooth", 1), ("module", 0.0), ("sense", "up"),
    ("refine", "maybe"), ("route", "ab"),
])
def test_a_bad_design_value_is_an_error_naming_its_argument(arg, value):
    with pytest.raises(ncgear.NcgearError, match=rf"^{arg}=") as e:
        ncgear.design(G1, **{arg: value})
    assert "--" not in str(e.value)


def test_keywords_are_checked_as_python_checks_them(g1):
    with pytest.raises(TypeError, match="colour"):
        ncgear.design(G1, colour=1)
    with pytest.raises(TypeError, match="tooth_polcy"):
        ncgear.teeth(g1, 2.0, tooth_polcy="nearest")
    with pytest.raises(TypeError, match="fit"):
        ncgear.design(G1, fit="no")
    with pytest.raises(ncgear.NcgearError, match=r"^min_concave_radius=10: not with convexity"):
        ncgear.design(G1, convexity=True, min_concave_radius=10.0)
    with pytest.raises(ncgear.NcgearError, match=r"^points: expected an \(N, 2\) array"):
        ncgear.design(np.zeros((5, 3)))


def test_a_design_error_quoting_a_flag_names_the_argument():
    # G1 is traced counter-clockwise: the library suggests leaving the sense to be chosen.
    with pytest.raises(ncgear.NcgearError, match='sense="auto"') as e:
        ncgear.design(G1, sense="cw")
    assert "--sense" not in str(e.value)


def test_teeth_equal_the_cli_teeth_block_and_step_bytes(g1_train, out):
    # The Python design was made without the module: the CLI's scaling policy gives its teeth.
    # Scaling moves the tip by 2.48 mm, beyond C12: the CLI writes the files and exits 3.
    p = cli("design", G1, "--module", "2", "--tooth-policy", "scale-up", "--bore", "10", "--out", out / "cli_teeth",
            check=False)
    assert p.returncode == 3, p.stderr
    ref = json.loads((out / "cli_teeth" / "design.json").read_text())["teeth"]
    assert _without(g1_train.to_dict(), "files") == _without(ref, "files")
    _same(g1_train, {**ref, "files": []})  # the CLI's teeth block lists the files it wrote
    assert g1_train.z == 23 and isinstance(g1_train.mesh, reports.TrainMesh)
    assert g1_train.options.policy == {"ScaleCenterDistance": "ScaleUp"}
    # Both meshes pass; the verdict fails on the policy's tip shift, as design.json's does.
    assert not g1_train.passed
    assert [f.split(":")[0] for f in g1_train.verdict.failures] == ["teeth"]
    cli_verdict = json.loads((out / "cli_teeth" / "design.json").read_text())["verdict"]
    assert list(g1_train.verdict.failures) == cli_verdict["failures"]
    assert g1_train.outlines["sun"].shape[1] == 2 and not g1_train.outlines["sun"].flags.writeable
    files = ncgear.write_step(g1_train, out / "py_step", bore=10.0)
    assert [f.rsplit("/", 1)[-1] for f in files] == [
        "sun.step", "intermediate.step", "planet.step", "train.step"]
    for f in files:
        name = f.rsplit("/", 1)[-1]
        cli_bytes = (out / "cli_teeth" / "teeth" / name).read_bytes()
        assert open(f, "rb").read() == cli_bytes, name


def test_tooth_keywords_reach_the_train(g1):
    t = ncgear.teeth(g1, 2.0, teeth=24, pressure_angle=22.5, addendum=0.9, backlash=0.1,
                     chord_tol=0.004, verify_steps=0)
    assert t.z == 24 and t.mesh is None and t.options.verify_steps == 0
    assert t.options.rack.alpha_rad == pytest.approx(math.radians(22.5))
    assert (t.options.rack.addendum, t.options.backlash_mm, t.options.chord_tol_mm) == (0.9, 0.1, 0.004)
    n = ncgear.teeth(g1, 2.0, tooth_policy="nearest", verify_steps=0)
    assert n.options.policy == {"ScaleCenterDistance": "Nearest"}
    # Scaling G1 to 22 teeth moves the tip by 1.54 mm, beyond C12's 0.05 mm: returned, failed.
    assert not n.passed
    assert [f.split(":")[0] for f in n.verdict.failures] == ["teeth"], n.verdict.failures
    assert "tooth-count policy moves the tip by 1.5" in n.verdict.failures[0]
    for kwargs, arg in [({"tooth_policy": "up"}, "tooth_policy"), ({"addendum": -1.0}, "addendum"),
                        ({"backlash": -0.1}, "backlash"), ({"chord_tol": 1.0}, "chord_tol"),
                        ({"teeth": 1}, "teeth")]:
        with pytest.raises(ncgear.NcgearError, match=rf"^{arg}="):
            ncgear.teeth(g1, 2.0, verify_steps=0, **kwargs)
    with pytest.raises(ncgear.NcgearError, match=r"^module=0: "):
        ncgear.teeth(g1, 0.0)


def test_pair_outlines_and_cli_pair_step_agree(out):
    p = ncgear.pair("phi - 0.08*sin(2*phi)", teeth=24, module=1.5)
    assert isinstance(p, reports.PairReport) and p.z == 24 and p.module_mm == 1.5
    assert isinstance(p.mesh, reports.MeshReport) and p.sector is None and p.passed
    assert set(p.outlines) == {"driver", "driven"}
    assert p.placements["driven"].center_mm == (p.center_distance_mm, 0.0)
    cli("pair", "phi - 0.08*sin(2*phi)", "--teeth", 24, "--module", 1.5, "--out", out / "cli_pair")
    [f] = ncgear.write_step(p, out / "py_pair")
    assert open(f, "rb").read() == (out / "cli_pair" / "pair.step").read_bytes()
    assert len(ncgear.write_dxf(p, out / "py_pair")) == 1 and len(ncgear.write_svg(p, out / "py_pair")) == 1
    [r12] = ncgear.write_dxf(p, out / "py_pair_r12", version="r12")
    assert b"LWPOLYLINE" not in open(r12, "rb").read()
    with pytest.raises(ncgear.NcgearError, match=r"^version='r14': expected one of 'r2010', 'r12'"):
        ncgear.write_dxf(p, out / "py_pair", version="r14")


def test_unequal_and_open_pairs_match_the_cli(out):
    p = ncgear.pair("0.5*phi + 0.05*sin(2*phi)", teeth=24, verify_steps=0)
    assert (p.z, p.z_driven) == (24, 48) and p.mesh is None
    assert abs(p.cycle_advance_deg - 180.0) < 1e-9
    s = ncgear.pair("phi - 0.08*sin(2*phi)", teeth=12, module=1.5, drive=(0.0, 180.0), verify_steps=0)
    assert isinstance(s.sector, reports.SectorReport) and abs(s.sector.active_teeth - 12.0) < 1e-6
    assert s.sector.drive_deg == (0.0, 180.0)
    cli("pair", "phi - 0.08*sin(2*phi)", "--teeth", 12, "--module", 1.5, "--verify-steps", 0,
        "--open", "--drive-start", 0, "--drive-end", 180, "--out", out / "cli_sector")
    [f] = ncgear.write_step(s, out / "py_sector")
    assert open(f, "rb").read() == (out / "cli_sector" / "pair.step").read_bytes()
    with pytest.raises(ncgear.NcgearError, match=r"^kind='gear': expected one of 'motion'"):
        ncgear.pair("phi", teeth=12, kind="gear")
    with pytest.raises(ncgear.NcgearError, match=r"^fillet="):
        ncgear.pair("phi - 0.08*sin(2*phi)", teeth=24, fillet=-1.0)


def test_simulate_and_tolerance_are_typed(g1, g1_train):
    f = ncgear.simulate(g1, spacing=140.0)
    assert isinstance(f, reports.Features) and 100.0 < f.height_mm < 150.0
    assert f.plant_spacing_mm == pytest.approx(140.0, rel=1e-9) and len(f.bbox_mm) == 4
    assert ncgear.simulate(g1_train, spacing=140.0).height_mm != f.height_mm  # scaled train (z = 23)
    fast = ncgear.simulate(g1, speed=2.0, rpm=200.0, depth=20.0)
    assert fast.plant_spacing_mm == pytest.approx(2000.0 * 60.0 / 200.0 / 2.0, rel=1e-9)
    assert ncgear.simulate(g1, take_level=f.bbox_mm[3] - 5.0).take_carrier_deg != f.take_carrier_deg
    with pytest.raises(ncgear.NcgearError, match=r"^spacing=0.0: "):
        ncgear.simulate(g1, spacing=0.0)
    with pytest.raises(ncgear.NcgearError, match=r"^spacing=140.0: not with speed"):
        ncgear.simulate(g1, spacing=140.0, speed=1.0)
    path = ROOT / "assets" / "tolerance" / "paper_3k.toml"
    t = ncgear.tolerance(path)
    assert isinstance(t, reports.ToleranceReport) and t.greedy_peak_arcsec > 0.0
    assert t.monte_carlo_um is None and isinstance(t.greedy[0], reports.GreedyStep)
    mc = ncgear.tolerance(path, samples=2000, seed=3)
    assert mc.monte_carlo_um is not None and mc.monte_carlo_um.n == 2000
    assert mc.monte_carlo_um.histogram.shape == (60, 3)


def test_errors_are_ncgear_errors_with_the_cli_message(g1_train, out, tmp_path):
    bad = tmp_path / "two.csv"
    bad.write_text("x,y\n0,0\n1,1\n")
    with pytest.raises(ncgear.NcgearError) as e:
        ncgear.design(bad)
    p = cli("design", bad, "--out", tmp_path / "o", check=False)
    # The CLI draws the same message in a box, wrapped: compare the words.
    words = lambda s: " ".join(s.replace("×", " ").replace("│", " ").split())
    assert p.returncode == 2 and words(str(e.value)) in words(p.stderr)
    with pytest.raises(ValueError, match="`bore` = 100"):
        ncgear.write_step(g1_train, tmp_path, bore=100.0)
    with pytest.raises(ncgear.NcgearError, match=r"^gb=0: "):
        ncgear.set_max_memory_gb(0.0)


def test_a_design_for_the_module_gets_its_own_teeth_unscaled():
    d = ncgear.design(G1, module=2.0)
    # z = 23 with the intermediate axis off the carrier line (l1 = 2a·cos ε) traces G1 exactly;
    # on the line the count would cost 1.5 mm.
    assert d.module is not None and d.module.teeth == 23
    assert d.roundtrip.max_deviation_mm < 1e-3 and 5.0 < abs(d.idler_offset_deg) <= 30.0
    assert d.limits.pressure_angle_deg <= 45.0
    t = ncgear.teeth(d, module=2.0, verify_steps=0)  # policy "design" for a design made for m
    assert t.z == 23 and abs(t.scale - 1.0) < 1e-9 and t.options.policy == "Designed"
    assert abs(t.roundtrip.hausdorff_mm - d.roundtrip.hausdorff_mm) < 2e-3
    collinear = ncgear.design(G1, module=2.0, idler_offset="collinear")
    assert collinear.idler_offset_deg == 0.0 and collinear.roundtrip.max_deviation_mm > 1.0


def test_a_failed_verification_is_returned_with_its_verdict_and_the_cli_exits_3(tmp_path):
    kidney = ROOT / "assets" / "trajectories" / "designer_kidney.csv"
    d = ncgear.design(kidney)
    # No train traces this drawn loop within the default 0.05 mm: C12 fails, the rest pass.
    assert not d.passed
    assert [f.split(":")[0] for f in d.verdict.failures] == ["C12"]
    assert [c.id for c in d.checks if not c.passed] == ["C12"]
    p = cli("design", kidney, "--out", tmp_path / "k", check=False)
    assert p.returncode == 3 and "C12" in p.stderr
    written = json.loads((tmp_path / "k" / "design.json").read_text())
    assert written["verdict"] == d.to_dict()["verdict"]
    # Unasked, both name the alternatives that apply, not designed (no second design).
    assert "alternatives" not in written and d.alternatives == ()
    assert written["warnings"] == list(d.warnings)
    assert "what may pass, not designed: off the carrier line" in p.stderr
    # Asked, both name what comes closer, designed: off the carrier line, the same limits.
    asked = ncgear.design(kidney, alternatives=True)
    p = cli("design", kidney, "--out", tmp_path / "ka", "--alternatives", check=False)
    written = json.loads((tmp_path / "ka" / "design.json").read_text())
    assert written["alternatives"] == asked.to_dict()["alternatives"]
    (alt,) = asked.alternatives
    assert isinstance(alt, reports.Alternative) and alt.flags == "--idler-offset free"
    assert alt.max_deviation_mm < 0.1 < asked.roundtrip.max_deviation_mm
    assert f"traced within {alt.max_deviation_mm:.4f} mm" in p.stderr
    assert cli("design", kidney, "--out", tmp_path / "k2", "--accept-failed").returncode == 0
