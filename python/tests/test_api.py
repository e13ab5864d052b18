"""The Python API equals the CLI: same design.json numbers, same teeth block, same STEP bytes,
same error messages."""
import json

import numpy as np
import pytest

import ncgear
from conftest import G1, cli


def _without(d, *keys):
    return {k: v for k, v in d.items() if k not in keys}


def test_design_of_g1_equals_the_cli_design_json(g1, out):
    cli("design", G1, "--out", out / "cli")
    ref = json.loads((out / "cli" / "design.json").read_text())
    # Every key and number of design.json, bit for bit (timings are wall-clock).
    assert _without(g1.report, "timings_ms") == _without(ref, "timings_ms")
    assert g1.l1 == ref["l1"] and g1.l3 == ref["l3"]
    assert abs(g1.l1 - 90.0) < 0.01 and abs(g1.l3 - 170.0) < 0.01
    # The per-point deviations agree with the report's round trip (3600 vs its own sampling).
    assert g1.deviations.shape == (len(ref["target_points"]),)
    assert abs(g1.deviations.max() - ref["roundtrip"]["max_deviation_mm"]) < 2e-3
    for name, c in g1.pitch_curves.items():
        assert c.shape == (1440, 2), name
        assert np.all(np.isfinite(c))


def test_design_from_points_equals_design_from_the_file(g1):
    pts = np.asarray(g1.report["target_points"])
    d = ncgear.design(pts)
    assert d.l1 == pytest.approx(g1.l1, rel=1e-9)
    assert d.report["center_distance"] == pytest.approx(g1.report["center_distance"], rel=1e-9)


def test_teeth_equal_the_cli_teeth_block_and_step_bytes(g1_train, out):
    # The Python design was made without the module: the CLI's scaling policy gives its teeth.
    cli("design", G1, "--module", "2", "--tooth-policy", "scale-up", "--bore", "10", "--out", out / "cli_teeth")
    ref = json.loads((out / "cli_teeth" / "design.json").read_text())["teeth"]
    assert _without(g1_train.report, "files", "timings_ms") == _without(ref, "files", "timings_ms")
    assert g1_train.report["z"] == 23
    files = ncgear.write_step(g1_train, out / "py_step", bore=10.0)
    assert [f.rsplit("/", 1)[-1] for f in files] == [
        "sun.step", "intermediate.step", "planet.step", "train.step"]
    for f in files:
        name = f.rsplit("/", 1)[-1]
        cli_bytes = (out / "cli_teeth" / "teeth" / name).read_bytes()
        assert open(f, "rb").read() == cli_bytes, name


def test_pair_outlines_and_cli_pair_step_agree(out):
    p = ncgear.pair("phi - 0.08*sin(2*phi)", teeth=24, module=1.5)
    assert p.report["z"] == 24 and p.report["module_mm"] == 1.5
    assert set(p.outlines) == {"driver", "driven"}
    assert p.placements["driven"]["centre_mm"][0] == p.report["centre_distance_mm"]
    cli("pair", "phi - 0.08*sin(2*phi)", "--teeth", 24, "--module", 1.5, "--out", out / "cli_pair")
    [f] = ncgear.write_step(p, out / "py_pair")
    assert open(f, "rb").read() == (out / "cli_pair" / "pair.step").read_bytes()
    assert len(ncgear.write_dxf(p, out / "py_pair")) == 1 and len(ncgear.write_svg(p, out / "py_pair")) == 1


def test_unequal_and_open_pairs_match_the_cli(out):
    p = ncgear.pair("0.5*phi + 0.05*sin(2*phi)", teeth=24, verify_steps=0)
    assert (p.report["z"], p.report["z_driven"]) == (24, 48)
    assert abs(p.report["cycle_advance_deg"] - 180.0) < 1e-9
    s = ncgear.pair("phi - 0.08*sin(2*phi)", teeth=12, module=1.5, drive=(0.0, 180.0), verify_steps=0)
    assert abs(s.report["sector"]["active_teeth"] - 12.0) < 1e-6
    cli("pair", "phi - 0.08*sin(2*phi)", "--teeth", 12, "--module", 1.5, "--verify-steps", 0,
        "--open", "--drive-start", 0, "--drive-end", 180, "--out", out / "cli_sector")
    [f] = ncgear.write_step(s, out / "py_sector")
    assert open(f, "rb").read() == (out / "cli_sector" / "pair.step").read_bytes()


def test_simulate_and_tolerance_return_the_cli_keys(g1, g1_train):
    f = ncgear.simulate(g1, spacing=140.0)
    assert 100.0 < f["height_mm"] < 150.0
    assert f["plant_spacing_mm"] == pytest.approx(140.0, rel=1e-9)
    ft = ncgear.simulate(g1_train, spacing=140.0)
    assert ft["height_mm"] != f["height_mm"]  # the toothed train is scaled (z = 23)
    from conftest import ROOT
    t = ncgear.tolerance(ROOT / "assets" / "tolerance" / "paper_3k.toml")
    assert t["greedy_peak_arcsec"] > 0.0


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
    with pytest.raises(ncgear.NcgearError, match="unknown option `colour`"):
        ncgear.design(G1, colour=1)
    with pytest.raises(ncgear.NcgearError, match="expected an \\(N, 2\\) array"):
        ncgear.design(np.zeros((5, 3)))


def test_a_design_for_the_module_gets_its_own_teeth_unscaled():
    d = ncgear.design(G1, module=2.0)
    assert d.report["module"]["teeth"] == 22  # the closer of 22 and 23 within the 25 mm hollow limit
    assert d.report["limits"]["pressure_angle_deg"] <= 45.0
    t = ncgear.teeth(d, module=2.0, verify_steps=0)  # policy "design" for a design made for m
    assert t.report["z"] == 22 and abs(t.report["scale"] - 1.0) < 1e-9
    assert abs(t.report["roundtrip"]["hausdorff_mm"] - d.report["roundtrip"]["hausdorff_mm"]) < 2e-3


def test_a_failed_verification_is_returned_with_its_verdict_and_the_cli_exits_3(tmp_path):
    from conftest import ROOT
    kidney = ROOT / "assets" / "trajectories" / "designer_kidney.csv"
    d = ncgear.design(kidney)
    # No train traces this drawn loop within the default 0.05 mm: C12 fails, the rest pass.
    assert not d.passed
    assert [f.split(":")[0] for f in d.verdict["failures"]] == ["C12"]
    p = cli("design", kidney, "--out", tmp_path / "k", check=False)
    assert p.returncode == 3 and "C12" in p.stderr
    written = json.loads((tmp_path / "k" / "design.json").read_text())
    assert written["verdict"] == d.verdict
    assert cli("design", kidney, "--out", tmp_path / "k2", "--accept-failed").returncode == 0
    # A pair whose mesh verifies passes.
    assert ncgear.pair("phi - 0.08*sin(2*phi)", teeth=24, module=1.5).passed
