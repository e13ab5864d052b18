"""synthesize, tradeoff and redesign from Python equal the CLI: every key and number of
synthesis.json and tradeoff.json; a warm re-design from a Design equals the one from its
design.json; bad input is an NcgearError naming the argument."""
import json

import numpy as np
import pytest

import ncgear
from ncgear import reports

from conftest import G1, ROOT, _same, cli

SPEC = ROOT / "assets" / "synthesis" / "g1_five_poses.toml"


def _without(d, *keys):
    return {k: v for k, v in d.items() if k not in keys}


def test_synthesize_equals_the_cli_synthesis_json(tmp_path):
    s = ncgear.synthesize(SPEC)
    p = cli("synthesize", SPEC, "--out", tmp_path, "--json", check=False)
    ref = json.loads((tmp_path / "synthesis.json").read_text())
    assert s.to_dict() == ref
    _same(s, ref)
    assert isinstance(s, reports.SynthesisReport) and isinstance(s.design, ncgear.Design)
    design = json.loads((tmp_path / "design.json").read_text())
    assert _without(s.design.to_dict(), "timings_ms") == _without(design, "timings_ms")
    assert len(s.poses) == 5 and max(q.error_mm for q in s.poses) < 0.05
    assert s.passed is (p.returncode == 0)


def test_synthesize_takes_a_dict_and_names_a_bad_spec():
    tomllib = pytest.importorskip("tomllib")
    spec = tomllib.loads(SPEC.read_text())
    s = ncgear.synthesize(spec)
    assert s.to_dict() == ncgear.synthesize(SPEC).to_dict()
    with pytest.raises(ncgear.NcgearError, match=r"^spec=spec: .*unknown field `posez`"):
        ncgear.synthesize({"posez": []})
    with pytest.raises(ncgear.NcgearError, match=r"^spec=nowhere\.toml: "):
        ncgear.synthesize("nowhere.toml")


def test_synthesize_for_a_module_and_idler_layout_equals_the_cli(tmp_path):
    """The design options reach each candidate's gears: synthesis.json and design.json of
    ``ncgear synthesize --module 2.5 --idler-offset free`` equal the call's, and the chosen
    gears are made for m = 2.5 with every band met."""
    spec = ROOT / "assets" / "synthesis" / "rice_targets.toml"
    s = ncgear.synthesize(spec, module=2.5, idler_offset="free")
    cli("synthesize", spec, "--out", tmp_path, "--module", "2.5", "--idler-offset", "free")
    assert s.to_dict() == json.loads((tmp_path / "synthesis.json").read_text())
    design = json.loads((tmp_path / "design.json").read_text())
    assert _without(s.design.to_dict(), "timings_ms") == _without(design, "timings_ms")
    assert s.design.module is not None and s.design.module.module_mm == 2.5
    assert s.design.verdict.passed and all(t.margin >= 0.0 for t in s.targets)
    with pytest.raises(ncgear.NcgearError, match=r"^center: the synthesis solves for"):
        ncgear.synthesize(spec, center=(0.0, 0.0))
    with pytest.raises(TypeError, match=r"synthesize\(\) got an unexpected keyword argument 'modul'"):
        ncgear.synthesize(spec, modul=2.5)


def test_tradeoff_equals_the_cli_tradeoff_json(tmp_path):
    t = ncgear.tradeoff(G1)
    cli("tradeoff", G1, "--out", tmp_path)
    ref = json.loads((tmp_path / "tradeoff.json").read_text())
    assert t.to_dict() == ref
    _same(t, ref)
    assert len(t.rows) == 11 and sum(r.is_default for r in t.rows) == 1
    default = next(r for r in t.rows if r.is_default)
    assert default.refused is None and default.designed.max_deviation_mm < 0.05


def test_redesign_from_a_design_equals_redesign_from_its_file(g1, tmp_path):
    pts = np.array(g1.target_points)
    pts[80:100, 0] += 0.3 * np.exp(-(((np.arange(80, 100) - 90) / 5.0) ** 2))
    warm = ncgear.redesign(pts, g1)
    path = tmp_path / "design.json"
    path.write_text(g1.json())
    again = ncgear.redesign(pts, path)
    assert _without(warm.to_dict(), "timings_ms") == _without(again.to_dict(), "timings_ms")
    assert warm.roundtrip.max_deviation_mm < 0.3
    assert np.array_equal(warm.deviations, again.deviations)


def test_redesign_names_a_bad_start():
    with pytest.raises(ncgear.NcgearError, match=r"^start: expected an ncgear\.Design or a design\.json path, got int"):
        ncgear.redesign(G1, 3)  # type: ignore[arg-type]
    with pytest.raises(ncgear.NcgearError, match=r"^start='nowhere\.json': cannot read it"):
        ncgear.redesign(G1, "nowhere.json")
    with pytest.raises(ncgear.NcgearError, match=r"^start=design\.json: not a design report"):
        ncgear.redesign(G1, str(SPEC))
