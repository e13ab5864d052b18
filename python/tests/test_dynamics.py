"""``ncgear.dynamics`` and ``ncgear.dynamics_file``: the rotor scene's ``dynamics.json`` typed,
the same run from a train in memory, the bundled rotor's knock (it settles, the
intermediate–planet mesh's dynamic factor above 3, impacts every turn), the sweep's rows and the
errors naming the scene's key."""
import dataclasses
import json
import tomllib

import numpy as np
import pytest

import ncgear
from ncgear import reports
from conftest import G1, ROOT, _same, cli

SCENE = ROOT / "assets" / "dynamics" / "rotor_g1.toml"


@pytest.fixture(scope="module")
def from_file():
    return ncgear.dynamics_file(SCENE)


@pytest.fixture(scope="module")
def m2():
    """G1 designed for module 2 and cut with its own teeth: the bundled design."""
    d = ncgear.design(G1, module=2.0)
    return d, ncgear.teeth(d, 2.0)


def scene_dict(**effects):
    """The bundled rotor scene as a dict, its ``[effects]`` updated by ``effects``."""
    s = tomllib.loads(SCENE.read_text())
    s["effects"].update(effects)
    return s


def test_dynamics_file_is_the_cli_dynamics_json_typed(tmp_path, from_file):
    p = cli("dynamics", SCENE, "--out", tmp_path / "cli")
    ref = json.loads((tmp_path / "cli" / "dynamics.json").read_text())
    r = from_file
    assert isinstance(r, ncgear.Dynamics) and isinstance(r, reports.RotorReport)
    # Every key and number of dynamics.json, and every key a typed field.
    assert r.to_dict() == ref and json.loads(r.json()) == ref
    _same(r, ref)
    s, rs = r.summary, ref["summary"]
    for mesh in ("sun_intermediate", "intermediate_planet"):
        m, rm = getattr(s.meshes, mesh), rs["meshes"][mesh]
        assert m.dynamic_factor == rm["dynamic_factor"] and m.iso_K_v == rm["iso_K_v"]
        assert m.impacts_per_turn == rm["impacts_per_turn"] == len(m.impacts)
        assert [i.speed_m_s for i in m.impacts] == [i["speed_m_s"] for i in rm["impacts"]]
    assert s.max_tip_deviation_mm == rs["max_tip_deviation_mm"]
    assert s.impacts_per_turn == rs["impacts_per_turn"] > 0
    assert s.natural_frequencies_hz == tuple(rs["natural_frequencies_hz"])
    assert r.steady.turns == ref["steady"]["turns"] and r.steady.residual == ref["steady"]["residual"]
    n = len(ref["travel_deg"])
    assert r.tip_mm.shape == (n, 2) and np.array_equal(r.tip_mm, np.array(ref["tip_mm"]))
    ip = r.meshes.intermediate_planet
    assert np.array_equal(ip.dynamic_force_n, ref["meshes"]["intermediate_planet"]["dynamic_force_n"])
    assert np.array_equal(r.carrier_torque_nm, ref["carrier_torque_nm"])
    assert len(ip.contact) == n and set(ip.contact) <= {"drive", "coast", "none"}
    # The summary is the series': the peak over the turn, the factor the peaks' ratio.
    assert s.meshes.intermediate_planet.peak_dynamic_n == ip.dynamic_force_n.max()
    assert s.meshes.intermediate_planet.peak_rigid_n == pytest.approx(np.abs(ip.rigid_force_n).max(), rel=1e-12)
    assert s.max_tip_deviation_mm == r.tip_deviation_mm.max()
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.design = ""  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        r.travel_deg[0] = 0.0
    assert p.returncode == 0


def test_the_bundled_rotor_settles_and_knocks(from_file):
    r = from_file
    assert r.steady.settled and r.steady.residual < r.steady.poincare_tol
    assert (r.scene, r.model, r.design) == ("rotor_g1", "rotor", "../loads/g1_m2_design.json")
    ip = r.summary.meshes.intermediate_planet
    assert ip.dynamic_factor > 3.0 and ip.dynamic_factor == ip.peak_dynamic_n / ip.peak_rigid_n
    assert ip.impacts_per_turn > 0 and r.summary.impacts_per_turn > 0
    assert r.summary.max_impact_speed_m_s == max(
        i.speed_m_s for m in (r.summary.meshes.sun_intermediate, ip) for i in m.impacts)
    # The backlash lets the meshes lose contact: some samples of the turn touch no flank.
    assert "none" in r.meshes.intermediate_planet.contact and ip.contact_loss_deg.shape[1:] == (2,)


def test_a_train_in_memory_runs_as_the_bundled_design_file(m2, from_file):
    _, t = m2
    r = ncgear.dynamics(t, scene_dict())
    f = from_file
    assert isinstance(r, ncgear.Dynamics) and r.design == f.design  # only echoed
    assert r.steady.settled and r.travel_deg.shape == f.travel_deg.shape
    assert r.summary.natural_frequencies_hz == pytest.approx(f.summary.natural_frequencies_hz, rel=1e-6)
    for mesh in ("sun_intermediate", "intermediate_planet"):
        a, b = getattr(r.summary.meshes, mesh), getattr(f.summary.meshes, mesh)
        assert a.peak_rigid_n == pytest.approx(b.peak_rigid_n, rel=1e-6)
        # The design file holds the curves to its printed precision: the knock agrees to 1e-6
        # (measured: dynamic factors within 6e-7, the same impacts).
        assert a.dynamic_factor == pytest.approx(b.dynamic_factor, rel=1e-5)
        assert a.impacts_per_turn == b.impacts_per_turn
        assert a.iso_K_v == pytest.approx(b.iso_K_v, rel=1e-6)
    assert r.summary.max_tip_deviation_mm == pytest.approx(f.summary.max_tip_deviation_mm, rel=1e-6)
    assert np.allclose(r.meshes.intermediate_planet.rigid_force_n,
                       f.meshes.intermediate_planet.rigid_force_n, rtol=1e-6, atol=1e-6)
    # The same scene by its path: the path is read, its design key is not; a dict may leave it out.
    p = ncgear.dynamics(t, SCENE)
    assert p.to_dict() == r.to_dict()
    bare = scene_dict()
    del bare["scene"]["design"]
    b = ncgear.dynamics(t, bare)
    assert b.design == "" and b.summary.impacts_per_turn == r.summary.impacts_per_turn
    assert np.array_equal(b.meshes.intermediate_planet.dynamic_force_n,
                          r.meshes.intermediate_planet.dynamic_force_n)


def test_a_sweep_gives_typed_rows(m2):
    _, t = m2
    rows = ncgear.dynamics(t, scene_dict(), sweep_rpm=[300.0])
    f = ncgear.dynamics(t, scene_dict())
    assert isinstance(rows, list) and len(rows) == 1 and isinstance(rows[0], ncgear.SweepRow)
    (row,) = rows
    ip = f.summary.meshes.intermediate_planet
    assert row.carrier_rpm == 300.0 and row.settled and row.turns == f.steady.turns
    assert row.dynamic_factor == (f.summary.meshes.sun_intermediate.dynamic_factor, ip.dynamic_factor)
    assert row.impacts_per_turn == f.summary.impacts_per_turn
    with pytest.raises(ncgear.NcgearError, match=r"^sweep_rpm=\[0\.0\]: 1 to 200 carrier speeds"):
        ncgear.dynamics_file(SCENE, sweep_rpm=[0.0])


def test_a_bad_scene_field_is_named(m2):
    _, t = m2
    with pytest.raises(ncgear.NcgearError, match=r"^scene: `effects\.mesh_damping\.zeta`: \[1\.5, 1\.5\] "
                       r"must be damping ratios in \[0, 1\]") as e:
        ncgear.dynamics(t, scene_dict(mesh_damping={"zeta": 1.5}))
    assert isinstance(e.value, ValueError) and "line 1 column" not in str(e.value)
    with pytest.raises(ncgear.NcgearError, match=r"unknown field `stiffness`"):
        ncgear.dynamics(t, scene_dict(stiffness=1.0))
    with pytest.raises(ncgear.NcgearError, match=r"^scene: `effects\.vibration_damping\.zeta`: -0\.1 must"):
        ncgear.dynamics(t, scene_dict(vibration_damping={"zeta": -0.1}))
    with pytest.raises(TypeError, match="design: expected an ncgear.Design or ncgear.Train"):
        ncgear.dynamics("design.json", scene_dict())  # type: ignore[arg-type]


def test_a_scene_file_without_a_design_is_named(tmp_path):
    s = SCENE.read_text().replace('design = "../loads/g1_m2_design.json"', "")
    assert "design =" not in s
    bare = tmp_path / "bare.toml"
    bare.write_text(s)
    with pytest.raises(ncgear.NcgearError, match=r"bare\.toml: `scene\.design`: the scene names no design"):
        ncgear.dynamics_file(bare)


def test_teeth_backlash_on_a_pitch_only_design_is_named(g1):
    constant = {"kind": "constant", "c_n_per_mm_mm": 14000.0}
    with pytest.raises(ncgear.NcgearError, match=r"^scene: `effects\.backlash`: the backlash reads the "
                       r"design's teeth, and the design has none"):
        ncgear.dynamics(g1, scene_dict(mesh_stiffness=constant))
