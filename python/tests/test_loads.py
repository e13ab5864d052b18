"""``ncgear.loads`` and ``ncgear.loads_file``: the CLI's ``loads.json`` typed, and the physics a
wrong binding or scene translation would break — the ω² law, zero net work of a lossless rotor,
the arms as shifted copies of the first, the frame holding the weight — and the errors."""
import dataclasses
import json
import re

import numpy as np
import pytest

import ncgear
from ncgear import reports
from conftest import G1, ROOT, _same, cli

SCENE = ROOT / "assets" / "loads" / "g1_rotor.toml"
G = 9.80665  # m/s², the library's standard gravity


@pytest.fixture(scope="module")
def m2():
    """G1 designed for module 2 and cut with its own 23 teeth."""
    d = ncgear.design(G1, module=2.0)
    return d, ncgear.teeth(d, 2.0)


def scene(rpm=300.0, arms=1, gravity=(0.0, 0.0), **tables):
    """A dict scene: an arm of 0.55 kg, steel gear bodies 20 mm wide with a 10 mm bore."""
    s = {
        "operation": {"carrier_rpm": rpm, "arms": arms, "gravity": list(gravity)},
        "arm": {"mass_kg": 0.55, "com_mm": [35.0, -70.0], "inertia_kg_mm2": 2100.0},
        "gears": {"face_width_mm": 20.0, "density_kg_m3": 7850.0, "bore_mm": 10.0},
    }
    s.update(tables)
    return s


def test_loads_file_is_the_cli_loads_json_typed(tmp_path):
    p = cli("loads", SCENE, "--out", tmp_path / "cli", "--accept-failed", check=False)
    assert p.returncode in (0, 3), p.stderr
    ref = json.loads((tmp_path / "cli" / "loads.json").read_text())
    r = ncgear.loads_file(SCENE)
    # Every key and number of loads.json, and every key a typed field.
    assert r.to_dict() == ref
    assert json.loads(r.json()) == ref
    _same(r, ref)
    assert isinstance(r, reports.LoadsReport) and isinstance(r.rating, reports.RatingReport)
    assert r.design == "g1_m2_design.json" and r.units.torque == "N·m"
    assert (r.operation.arms, r.operation.samples, r.operation.gravity_m_s2) == (2, 720, (0.0, -G))
    assert r.travel_deg.shape == (720,) and r.frame_force_N.shape == (720, 2)
    assert r.meshes.intermediate_planet.pitch_radius_of_curvature_mm.shape == (720, 2)
    si = r.meshes.sun_intermediate
    assert si.root_stress_MPa is not None and sorted(si.root_stress_MPa) == ["intermediate", "sun"]
    assert si.contact_stress_MPa is not None and si.contact_stress_MPa.shape == (720,)
    assert set(np.unique(si.flank)) <= {-1.0, 0.0, 1.0}
    assert sorted(r.rating.gears) == ["intermediate", "planet", "sun"]
    # The summary is the series': peaks, the mean power, the rating's extremes.
    assert r.summary.carrier_torque_peak_Nm == np.abs(r.carrier_torque_Nm).max()
    assert r.summary.frame_force_peak_N == pytest.approx(
        np.hypot(*r.frame_force_N.T).max(), rel=1e-12)
    assert r.summary.mean_power_W == pytest.approx(
        r.carrier_torque_Nm.mean() * r.operation.omega_rad_s, rel=1e-9)
    assert r.summary.min_S_H == r.rating.min_S_H and r.summary.life_h == r.rating.life_h
    meets = (r.rating.min_S_H.value >= r.rating.options.S_H_min
             and r.rating.min_S_F.value >= r.rating.options.S_F_min)
    assert r.passed is r.verdict.passed is meets
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.design = None
    with pytest.raises(ValueError, match="read-only"):
        r.carrier_torque_Nm[0] = 0.0


def test_a_scene_file_on_a_design_in_memory_ignores_its_design_key(m2):
    d, t = m2
    r = ncgear.loads(t, SCENE)  # the scene names g1_m2_design.json: not read
    assert r.design is None and isinstance(r, ncgear.Loads) and r.rating is not None
    # The bundled design is G1 at module 2: the same rotor, its numbers to the file's precision.
    f = ncgear.loads_file(SCENE)
    assert r.summary.carrier_torque_peak_Nm == pytest.approx(f.summary.carrier_torque_peak_Nm, rel=1e-4)
    assert r.rating.min_S_H.value == pytest.approx(f.rating.min_S_H.value, rel=1e-4)


def test_a_design_file_written_from_python_runs_as_the_design_in_memory(m2, tmp_path):
    d, _ = m2
    (tmp_path / "design.json").write_text(d.json())
    s = tmp_path / "scene.toml"
    s.write_text('design = "design.json"\n[operation]\ncarrier_rpm = 300.0\narms = 2\n'
                 'gravity = [0.0, -1.0]\n[arm]\nmass_kg = 0.5\ncom_mm = [0.0, -80.0]\n'
                 'inertia_kg_mm2 = 1000.0\n[gears]\nface_width_mm = 20.0\n')
    f, m = ncgear.loads_file(s), ncgear.loads(d, s)
    assert (f.design, m.design) == ("design.json", None)
    # The file's tables rebuild the train the design holds in memory.
    peak = np.abs(m.carrier_torque_Nm).max()
    np.testing.assert_allclose(f.carrier_torque_Nm, m.carrier_torque_Nm, rtol=0, atol=1e-9 * peak)
    np.testing.assert_allclose(f.frame_force_N, m.frame_force_N, rtol=0, atol=1e-9 * np.abs(m.frame_force_N).max())
    # Its design.json has no teeth block: the stresses are refused, in the file's words.
    rated = tmp_path / "rated.toml"
    rated.write_text(s.read_text() + '[material]\npreset = "steel"\n')
    with pytest.raises(ncgear.NcgearError, match=r"has no teeth: rate a toothed train .*\(write the design file with `ncgear design --module M`\)"):
        ncgear.loads_file(rated)


def test_the_carrier_torque_goes_with_the_square_of_the_speed_and_does_no_net_work(m2):
    _, t = m2
    # No gravity, no needle: every load is inertial, ∝ ω²; a lossless rigid rotor at constant
    # speed gives back over a turn what it takes.
    slow, fast = ncgear.loads(t, scene(300.0)), ncgear.loads(t, scene(600.0))
    assert slow.rating is None and slow.passed and slow.design is None
    assert slow.summary.carrier_torque_peak_Nm > 0.1
    peak = np.abs(slow.carrier_torque_Nm).max()
    np.testing.assert_allclose(fast.carrier_torque_Nm, 4.0 * slow.carrier_torque_Nm,
                               rtol=1e-9, atol=1e-12 * peak)
    np.testing.assert_allclose(fast.meshes.sun_intermediate.normal_force_N,
                               4.0 * slow.meshes.sun_intermediate.normal_force_N, rtol=1e-9, atol=1e-9)
    assert np.array_equal(fast.meshes.intermediate_planet.flank, slow.meshes.intermediate_planet.flank)
    for r in (slow, fast):
        assert abs(r.summary.mean_power_W) < 1e-6
        assert np.all(r.needle_force_N == 0.0)


def test_two_arms_are_the_first_shifted_by_half_a_turn_and_the_frame_holds_the_weight(m2):
    _, t = m2
    tables = {"gravity": (0.0, -1.0), "needle": {"profile": "planting"}}
    one = ncgear.loads(t, scene(arms=1, **tables))
    two = ncgear.loads(t, scene(arms=2, **tables))
    n = one.operation.samples
    assert n == two.operation.samples == 720 and np.array_equal(one.travel_deg, two.travel_deg)
    half = np.roll(np.arange(n), -n // 2)  # sample k + 180° of travel
    np.testing.assert_allclose(two.carrier_torque_Nm, one.carrier_torque_Nm + one.carrier_torque_Nm[half],
                               rtol=1e-12, atol=1e-12)
    # The first arm's own quantities do not change with the second.
    assert np.array_equal(two.planet_mesh_torque_Nm, one.planet_mesh_torque_Nm)
    # The frame force sums the arms; the fixed sun's weight is held once.
    sun_weight = one.gears.sun.mass_kg * np.asarray(one.operation.gravity_m_s2)
    np.testing.assert_allclose(two.frame_force_N, one.frame_force_N + one.frame_force_N[half] + sun_weight,
                               rtol=1e-12, atol=1e-9)
    # Over a turn the bodies' accelerations average out: the frame holds the weight of the sun
    # and of each arm's intermediate, planet and planting arm, and the needle's mean push.
    g = two.gears
    assert g.arm is not None and g.arm.mass_kg == 0.55 and g.face_width_mm == 20.0
    mass = g.sun.mass_kg + 2 * (g.intermediate.mass_kg + g.planet.mass_kg + g.arm.mass_kg)
    assert np.abs(two.needle_force_N).max() > 1.0
    expected = -mass * np.array([0.0, -G]) - 2 * two.needle_force_N.mean(axis=0)
    np.testing.assert_allclose(two.frame_force_N.mean(axis=0), expected, rtol=0, atol=1e-6)


def test_a_design_without_teeth_gives_loads_and_refuses_stresses(m2):
    d, t = m2
    pitch = ncgear.loads(d, scene())
    assert pitch.rating is None and pitch.meshes.sun_intermediate.contact_stress_MPa is None
    assert pitch.meshes.sun_intermediate.root_stress_MPa is None
    # The design's own teeth (scale 1): the same rotor as its pitch curves, within the teeth's
    # remake of the assembly.
    toothed = ncgear.loads(t, scene())
    peak = np.abs(pitch.carrier_torque_Nm).max()
    np.testing.assert_allclose(toothed.carrier_torque_Nm, pitch.carrier_torque_Nm, rtol=0, atol=1e-6 * peak)
    rated = scene(material={"preset": "steel"})
    with pytest.raises(ncgear.NcgearError, match=r"^the scene's \[material\] asks for tooth stresses, "
                       r"and the design has no teeth: .*\(pass the toothed train, ncgear\.teeth") as e:
        ncgear.loads(d, rated)
    assert "--" not in str(e.value)
    r = ncgear.loads(t, rated)
    assert r.rating is not None and r.rating.options.material.name == "steel"
    assert r.rating.face_width_mm == 20.0 and r.rating.module_mm == 2.0
    assert r.summary.min_S_F is not None and r.summary.min_S_F.value > 0.0


@pytest.mark.parametrize("change, message", [
    ({"arm": {"mass_kg": -1.0, "com_mm": [0.0, -80.0], "inertia_kg_mm2": 0.0}},
     r"^scene: `arm\.mass_kg`: -1 must be a mass ≥ 0 in kg$"),
    ({"operation": {"carrier_rpm": 0.0}},
     r"^scene: `operation\.carrier_rpm`: 0 must be a speed in \(0, 3000\] r/min$"),
    ({"operation": {"carrier_rpm": 300.0, "arms": 9}},
     r"^scene: `operation\.arms`: 9 must be a count of trains in 1\.\.=8$"),
    ({"colour": "red"}, r"^scene: unknown field `colour`, expected one of `design`, `operation`"),
    ({"arm": {"mass": 1.0}}, r"^scene: unknown field `mass`, expected one of `mass_kg`"),
    ({"gears": {"face_width_mm": 20.0, "bore_mm": 200.0}},
     r"^scene: `gears\.bore_mm`: a bore of 200 mm does not fit inside the sun gear"),
    ({"rating": {"S_F_min": 2.0}}, r"^scene: `rating`: rates the teeth against a material"),
    ({"arm": {"mass_kg": float("nan"), "com_mm": [0.0, 0.0], "inertia_kg_mm2": 0.0}},
     r"^scene: Out of range float values are not JSON compliant"),
])
def test_a_bad_scene_is_an_ncgear_error_naming_the_key(m2, change, message):
    _, t = m2
    with pytest.raises(ncgear.NcgearError, match=message) as e:
        ncgear.loads(t, scene(**change))
    assert isinstance(e.value, ValueError) and "line 1 column" not in str(e.value)


def test_scene_files_name_themselves_in_their_errors(m2, tmp_path):
    _, t = m2
    bad = tmp_path / "bad.toml"
    bad.write_text("[operation]\ncarrier_rpm = 300.0\n[arm]\nmass_kg = -2.0\ncom_mm = [0.0, 0.0]\n"
                   "inertia_kg_mm2 = 0.0\n")
    with pytest.raises(ncgear.NcgearError, match=rf"^{re.escape(str(bad))}: `arm\.mass_kg`: -2 must be"):
        ncgear.loads(t, bad)
    typo = tmp_path / "typo.toml"
    typo.write_text("[operation]\ncarrier_rpm = 300.0\nspeed = 1.0\n")
    with pytest.raises(ncgear.NcgearError, match=r"unknown field `speed`"):
        ncgear.loads(t, str(typo))
    bare = tmp_path / "bare.toml"
    bare.write_text("[operation]\ncarrier_rpm = 300.0\n")
    with pytest.raises(ncgear.NcgearError, match=r"`design`: the scene names no design"):
        ncgear.loads_file(bare)
    assert ncgear.loads(t, bare).operation.carrier_rpm == 300.0
    with pytest.raises(ncgear.NcgearError, match="cannot read"):
        ncgear.loads_file(tmp_path / "absent.toml")
    with pytest.raises(TypeError, match="design: expected an ncgear.Design or ncgear.Train"):
        ncgear.loads("design.json", scene())  # type: ignore[arg-type]


@pytest.mark.parametrize("target", ["g1_ellipse.csv", "designer_kidney.csv"])
def test_module_auto_sizes_as_the_cli(target, tmp_path):
    """``design(points, module="auto", loads=scene)`` is ``ncgear design --module auto --loads``:
    the same rows (module, teeth, S_H, S_F, to the bit), the same module kept, typed."""
    path = ROOT / "assets" / "trajectories" / target
    scene_file = ROOT / "assets" / "loads" / "rotor.toml"
    cli("design", path, "--module", "auto", "--loads", scene_file, "--out", tmp_path,
        check=False)
    want = json.loads((tmp_path / "design.json").read_text())["sizing"]
    d = ncgear.design(path, module="auto", loads=scene_file)
    assert isinstance(d.sizing, reports.ModuleSizing)
    assert d.sizing.chosen_module_mm == want["chosen_module_mm"] is not None
    assert d.module is not None and d.module.module_mm == want["chosen_module_mm"]
    got = [(r.module_mm, r.teeth, r.S_H, r.S_F, r.passed) for r in d.sizing.rows]
    assert got == [(r["module_mm"], r["teeth"], r["S_H"], r["S_F"], r["passed"])
                   for r in want["rows"]]
    # Without a scene, or a scene for a fixed module, is refused saying what to give.
    with pytest.raises(ncgear.NcgearError, match=r'loads=SCENE'):
        ncgear.design(path, module="auto")
    with pytest.raises(ncgear.NcgearError, match=r'module="auto"'):
        ncgear.design(path, module=2.0, loads=scene_file)
    # The same scene as a dict sizes the same.
    tomllib = pytest.importorskip("tomllib")
    as_dict = tomllib.loads(scene_file.read_text())
    assert ncgear.design(path, module="auto", loads=as_dict).sizing == d.sizing
