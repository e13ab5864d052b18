"""The reports of ncgear as frozen dataclasses: the keys of the CLI's JSON files (``design.json``,
its ``teeth`` block, ``tolerance.json``, ``loads.json``, a rotor scene's ``dynamics.json``, the
simulation features), typed, nested as in the file.

Units are in the field names (``_mm``, ``_deg``, ``_rad``, ``_um``, ``_arcsec``, ``_ms``, ``_N``,
``_Nm``, ``_MPa``, ``_h``); a bare length is in mm and a bare angle in degrees where the JSON says
so (``units``). Point lists are read-only float64 ``numpy.ndarray`` of shape (N, 2), mm, and so
are ``[x, y]`` series (forces, N); other number lists are tuples or 1-D arrays. A number JSON
writes as ``null`` because it is not finite (an unbounded check value or radius, an unlimited
life) reads as ``math.inf``. The JSON key ``pass`` is the field ``passed``.
"""
from __future__ import annotations

import dataclasses
import math
import typing
from dataclasses import dataclass, field
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

Points = npt.NDArray[np.float64]
"""Read-only float64 array of shape (N, 2), mm."""
Numbers = npt.NDArray[np.float64]
"""Read-only 1-D float64 array."""
Vectors = npt.NDArray[np.float64]
"""Read-only float64 array of shape (N, 2): ``[x, y]`` (a force, N) or a pair of values per
sample."""

T = typing.TypeVar("T")


def _array(v: Any) -> np.ndarray:
    a = np.array(v, dtype=np.float64)
    a.flags.writeable = False
    return a


def _value(tp: Any, v: Any) -> Any:
    """``v`` (JSON-shaped, number arrays possibly numpy already) as type ``tp``."""
    origin, args = typing.get_origin(tp), typing.get_args(tp)
    if origin is Union:
        inner = [a for a in args if a is not type(None)]
        if v is None and len(inner) < len(args):
            return None
        return _value(inner[0], v) if len(inner) == 1 else v
    if isinstance(tp, type) and dataclasses.is_dataclass(tp):
        return build(tp, v)
    if tp is np.ndarray or origin is np.ndarray:
        return _array(v if v is not None else [])
    if origin is tuple:
        items = [] if v is None else list(v)
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_value(args[0], x) for x in items)
        return tuple(_value(a, x) for a, x in zip(args, items))
    if origin is dict:
        return {k: _value(args[1], x) for k, x in v.items()}
    if tp is float:
        return math.inf if v is None else float(v)
    if tp in (int, bool, str):
        return tp(v)
    return v


def build(cls: typing.Type[T], obj: Dict[str, Any], **extra: Any) -> T:
    """An instance of dataclass ``cls`` from the JSON object ``obj`` (keys missing from it —
    fields the library leaves out when empty — read as ``None``, empty or ``inf`` by type);
    ``extra`` gives fields that are not report keys."""
    hints = typing.get_type_hints(cls)
    values = {}
    for f in dataclasses.fields(typing.cast(Any, cls)):
        key = f.metadata.get("key", f.name)
        if f.name in extra:
            values[f.name] = extra[f.name]
        elif f.metadata.get("null_is_inf") and key in obj and obj[key] is None:
            values[f.name] = math.inf  # an optional number present but not finite
        else:
            values[f.name] = _value(hints[f.name], obj.get(key))
    return cls(**values)


def json_key(f: dataclasses.Field) -> str:  # type: ignore[type-arg]
    """The JSON key of report field ``f``."""
    return str(f.metadata.get("key", f.name))


@dataclass(frozen=True)
class Verdict:
    """Whether a result passed its own verification, and what failed (``"C12: …"``)."""

    passed: bool
    failures: Tuple[str, ...]


@dataclass(frozen=True)
class Units:
    """Units of the design report's bare numbers."""

    length: str
    angle: str


@dataclass(frozen=True)
class Carrier:
    """The carrier: axis O (mm) and sense (+1 CCW, −1 CW)."""

    center_mm: Tuple[float, float]
    direction: int


@dataclass(frozen=True, eq=False)
class GearCurve:
    """One pitch curve: points in the body frame (mm), size and gear limits."""

    pitch: Points
    angle_at_zero_deg: Optional[float]
    perimeter_mm: float
    min_radius_of_curvature_mm: float
    min_concave_radius_mm: Optional[float]
    concave_fraction: float
    max_pressure_angle_deg: float


@dataclass(frozen=True, eq=False)
class Gears:
    """The three pitch curves."""

    sun: GearCurve
    intermediate: GearCurve
    planet: GearCurve


@dataclass(frozen=True)
class RoundTrip:
    """The round trip from the output curves to the traced path."""

    max_deviation_mm: float
    rms_deviation_mm: float
    hausdorff_mm: float
    max_mesh_error_mm: float
    estimated_curve_deviation_mm: Optional[float]
    samples: int


@dataclass(frozen=True)
class TrajectorySummary:
    """The target trajectory as read."""

    points: int
    rho_max_mm: float
    rho_min_mm: float
    reference_carrier_angle_deg: float
    needle_swing_deg: float
    i31_range: Tuple[float, float]
    noise_sigma_mm: float


@dataclass(frozen=True)
class Compatibility:
    """The compatibility condition of the train."""

    tau_deg: float
    residual_rad: float
    tip_equivalent_mm: float
    endpoint_product: float
    origins_deg: Tuple[float, ...]


@dataclass(frozen=True, eq=False)
class Route:
    """The patent route or the refinement: order, deviation, iterations; ``order_scan`` rows
    (order, max deviation mm)."""

    order: int
    max_deviation_mm: float
    j0: Optional[float]
    j1: Optional[float]
    iterations: int
    note: str
    order_scan: Numbers


@dataclass(frozen=True, eq=False)
class Fit:
    """The final fit to the points; ``order_scan`` rows (order, rms mm, max mm)."""

    order: int
    rms_mm: float
    max_mm: float
    start_rms_mm: float
    start_max_mm: float
    noise_sigma_mm: float
    start_smoothing_harmonics: Optional[int]
    iterations: int
    order_scan: Numbers


@dataclass(frozen=True, eq=False)
class Fourier:
    """The sun ratio's Fourier series: coefficients ``a``, ``b`` (1-D arrays)."""

    order: int
    a: Numbers
    b: Numbers
    sun_phase_deg: float
    i21_range: Tuple[float, float]


@dataclass(frozen=True, eq=False)
class ModuleSummary:
    """A design made for a module: its tooth count; ``candidates`` rows (teeth, max deviation mm,
    perimeter mm)."""

    module_mm: float
    teeth: int
    perimeter_mm: float
    free_teeth: float
    free_max_deviation_mm: float
    candidates: Numbers


@dataclass(frozen=True)
class Limits:
    """The gear limits the design was made within and where it stands."""

    enabled: bool
    max_pressure_angle_deg: float
    min_concave_radius_mm: float
    min_convex_radius_mm: Optional[float]
    ratio_bounds: Tuple[float, float]
    pressure_angle_deg: float
    tightest_concave_radius_mm: Optional[float]
    tightest_convex_radius_mm: float
    ratio_range: Tuple[float, float]
    binding: Tuple[str, ...]


@dataclass(frozen=True)
class Check:
    """One of the checks C1–C13."""

    id: str
    name: str
    value: float
    limit: float
    passed: bool = field(metadata={"key": "pass"})


@dataclass(frozen=True)
class Timings:
    """Stage timings, ms."""

    inverse: float
    compat: float
    patent: float
    refine: float
    fit: float
    module: float
    outputs: float
    total: float
    alternatives: float
    teeth: float
    verification: float
    cad_files: float
    command: float


@dataclass(frozen=True)
class Mesh:
    """The verification of one mesh over its steps."""

    steps: int
    interference_steps: int
    max_penetration_mm: float
    min_nominal_clearance_mm: float
    min_backlash_mm: float
    max_backlash_mm: float
    max_overlap_area_mm2: float
    max_overlap_at_deg: float
    max_transmission_error_deg: float
    transmission_error_p2p_deg: float


@dataclass(frozen=True)
class TrainMesh:
    """Both meshes of the train."""

    sun_intermediate: Mesh
    intermediate_planet: Mesh


@dataclass(frozen=True)
class Rack:
    """The basic rack: pressure angle (rad) and factors of the module."""

    alpha_rad: float
    addendum: float
    clearance: float
    fillet: float


@dataclass(frozen=True)
class TeethOptions:
    """The tooth options the train was cut with; ``policy`` as the library writes it
    (``"Designed"``, ``{"ScaleCenterDistance": "ScaleUp"}`` …)."""

    policy: Union[str, Dict[str, Any]]
    module_mm: float
    rack: Rack
    backlash_mm: float
    chord_tol_mm: float
    verify_chord_tol_mm: float
    verify_steps: int
    cutter_teeth: Optional[int]
    refuse_undercut: bool
    roundtrip_samples: int
    wire_edm: bool
    accuracy_mm: Optional[float]


@dataclass(frozen=True)
class TeethRoundTrip:
    """How far the toothed train traces from the target, against the designed gears."""

    before_max_deviation_mm: float
    max_deviation_mm: float
    hausdorff_mm: float
    before_hausdorff_mm: float
    max_tip_shift_mm: float


@dataclass(frozen=True)
class Flank:
    """Undercut of one tooth flank."""

    tooth: int
    side: str
    s_mm: float
    min_rho_mm: float
    cusp_depth_mm: float
    flank_depth_mm: float
    undercut: bool
    undercut_mm: float
    concave: bool
    form_depth_mm: float
    contact_ratio_loss: float
    root_thickness_mm: Optional[float]


@dataclass(frozen=True)
class Undercut:
    """Undercut of one gear."""

    flanks: Tuple[Flank, ...]
    min_rho_mm: float
    required_rho_mm: float
    max_module_mm: float
    undercut_count: int
    concave_count: int
    max_undercut_mm: float
    max_contact_ratio_loss: float
    min_root_thickness_mm: Optional[float]


@dataclass(frozen=True)
class TrainUndercut:
    """Undercut of the three gears."""

    sun: Undercut
    intermediate: Undercut
    planet: Undercut


@dataclass(frozen=True)
class Process:
    """How one gear is cut: ``process`` ``"rack"``, ``"shaper"`` or ``"wire-edm"``."""

    process: str
    cutter_teeth: Optional[int]
    cutter_pitch_radius_mm: Optional[float]
    min_concave_rho_mm: Optional[float]
    tried_cutter_teeth: Tuple[int, ...]
    rejected: Tuple[str, ...]
    undercut_flanks: int
    min_tip_width_mm: Optional[float]
    relieved_teeth: int
    max_tip_relief_mm: float
    reach_topped_teeth: int


@dataclass(frozen=True)
class TrainProcess:
    """How the three gears are cut."""

    sun: Process
    intermediate: Process
    planet: Process


@dataclass(frozen=True)
class TeethReport:
    """The ``teeth`` block of ``design.json``: the toothed train."""

    options: TeethOptions
    z: int
    module_mm: float
    ratio_amplitude: float
    needle_angle_deg: Optional[float]
    sun_phase_deg: Optional[float]
    warnings: Tuple[str, ...]
    z_raw: float
    scale: float
    perimeter_mm: float
    center_distance_mm: float
    l1_mm: float
    radial_shift_mm: float
    roundtrip: TeethRoundTrip
    phase_mm: Tuple[float, float, float]
    undercut: TrainUndercut
    mesh: Optional[TrainMesh]
    files: Tuple[str, ...]
    process: Optional[TrainProcess]


@dataclass(frozen=True)
class Alternative:
    """A failed design's nearest alternative, designed: what changes (``label``), the CLI flags
    that ask for it, its largest distance from the target (mm), pressure angle and idler offset
    (degrees), whether it passes and what still fails."""

    label: str
    flags: str
    max_deviation_mm: float
    pressure_angle_deg: float
    idler_offset_deg: float
    passed: bool
    failures: Tuple[str, ...]


@dataclass(frozen=True)
class SizingRow:
    """One module designed and rated by the sizing: its figures (absent when the design failed)
    and which limit fails (``None`` when the row passes)."""

    module_mm: float
    passed: bool
    teeth: Optional[int]
    face_width_mm: Optional[float]
    max_deviation_mm: Optional[float]
    S_H: Optional[float]
    S_F: Optional[float]
    life_h: Optional[float]
    carrier_torque_peak_Nm: Optional[float]
    gears_mass_kg: Optional[float]
    fails: Optional[str]


@dataclass(frozen=True)
class ModuleSizing:
    """The module sized by strength (``ncgear design --module auto --loads``): the safety
    targets, the face width rule (``"auto"`` or mm), the modules tried (smallest first) and the
    one kept (``None`` when none meets the targets)."""

    S_H_min: float
    S_F_min: float
    face_width: str
    rows: Tuple[SizingRow, ...]
    chosen_module_mm: Optional[float]


@dataclass(frozen=True, eq=False)
class DesignReport:
    """``design.json``: arm lengths l1, l3 and centre distance (mm), the idler offset and the
    needle angle (degrees), the pitch
    curves, the round trip, the stages of the chain, the gear limits, the checks C1–C13, the
    target points (mm), warnings, timings, the teeth when cut, the module sized by strength and
    the verdict."""

    schema_version: int
    units: Units
    l1_mm: float
    l3_mm: float
    center_distance_mm: float
    idler_offset_deg: float
    needle_angle_deg: float
    carrier: Carrier
    gears: Gears
    roundtrip: RoundTrip
    trajectory: TrajectorySummary
    compatibility: Compatibility
    patent_route: Route
    refinement: Optional[Route]
    fit: Optional[Fit]
    chosen: str
    fourier: Fourier
    module: Optional[ModuleSummary]
    limits: Limits
    checks: Tuple[Check, ...]
    target_points: Points
    warnings: Tuple[str, ...]
    timings_ms: Timings
    teeth: Optional[TeethReport]
    alternatives: Tuple[Alternative, ...]
    sizing: Optional[ModuleSizing]
    verdict: Verdict


@dataclass(frozen=True)
class Sector:
    """An open sector pair: driver interval (deg), kept teeth, hub radii (mm)."""

    drive_deg: Tuple[float, float]
    driven_advance_deg: float
    active_teeth: float
    kept_teeth: Tuple[int, int]
    hub_radius_mm: Tuple[float, float]
    assembly_at_deg: float


@dataclass(frozen=True)
class PairOptions:
    """The options a pair was designed with: driver teeth (``None``: from the centrode), cycle
    advance (rad), module, rack, backlash and chord tolerances (mm), verified steps, the shaper
    cutter, samples per turn and the open sector's driver interval (rad)."""

    teeth: Optional[int]
    centrode_advance_rad: float
    module_mm: float
    rack: Rack
    backlash_mm: float
    chord_tol_mm: float
    verify_chord_tol_mm: float
    verify_steps: int
    cutter_teeth: Optional[int]
    refuse_undercut: bool
    samples: int
    open_sector_rad: Optional[Tuple[float, float]]


@dataclass(frozen=True)
class PairUndercut:
    """Undercut of one gear of a pair: flank counts, radii and depths (mm)."""

    undercut_flanks: int
    concave_flanks: int
    min_rho_mm: float
    required_rho_mm: float
    max_module_mm: float
    max_undercut_mm: float
    max_contact_ratio_loss: float
    min_root_thickness_mm: Optional[float]


@dataclass(frozen=True)
class PairReport:
    """A toothed pair: the tool, its options, tooth counts, module, sizes (mm), ratio range, each
    gear's undercut and process, the mesh, the sector of an open pair and the verdict
    (``pair.json`` without its files and timings)."""

    schema_version: int
    tool: str
    options: PairOptions
    z: int
    z_driven: int
    cycle_advance_deg: float
    module_mm: float
    center_distance_mm: float
    perimeter_mm: float
    ratio_range: Tuple[float, float]
    driver_undercut: PairUndercut
    driven_undercut: PairUndercut
    driver_process: Process
    driven_process: Process
    mesh: Optional[Mesh]
    sector: Optional[Sector]
    verdict: Verdict


@dataclass(frozen=True)
class Features:
    """Agronomic features of one carrier turn (``ncgear simulate``); ``bbox_mm`` is
    (xmin, xmax, ymin, ymax)."""

    height_mm: float
    bbox_mm: Tuple[float, float, float, float]
    rho_range_mm: Tuple[float, float]
    take_carrier_deg: float
    needle_angle_take_deg: float
    plant_carrier_deg: float
    needle_angle_plant_deg: float
    take_angle_deg: float
    push_angle_deg: float
    static_width_at_depth_mm: float
    hole_width_mm: float
    max_tip_speed_mm_s: float
    tip_speed_at_plant_mm_s: float
    max_dynamic_tip_speed_mm_s: float
    min_arm_clearance_mm: float
    plant_spacing_mm: float


@dataclass(frozen=True)
class GreedyStep:
    """One step of the greedy phase compensation."""

    term: str
    index: int
    beta_rad: float
    peak_um: float
    ties: Tuple[int, ...]


@dataclass(frozen=True)
class Joint:
    """The joint optimum of every assembly angle."""

    betas_rad: Tuple[float, ...]
    peak_um: float
    starts: int


@dataclass(frozen=True)
class Phasor:
    """The error terms of one frequency, summed."""

    omega_rad_s: float
    amplitude_um: float
    phase_rad: float


@dataclass(frozen=True, eq=False)
class McStats:
    """Monte Carlo statistics; ``histogram`` rows (low, high, count)."""

    n: int
    min: float
    max: float
    mean: float
    std: float
    mean_std_error: float
    p50: float
    p95: float
    p9973: float
    histogram: Numbers


@dataclass(frozen=True, eq=False)
class ToleranceReport:
    """``tolerance.json``: error harmonics, phase compensation and the Monte Carlo."""

    base_radius_mm: float
    period_s: float
    commensurate: bool
    nominal_peak_um: float
    amplitude_sum_um: float
    floor_um: float
    greedy: Tuple[GreedyStep, ...]
    greedy_peak_um: float
    greedy_peak_arcsec: float
    joint: Joint
    greedy_gap_um: float
    groups: Tuple[Phasor, ...]
    monte_carlo_um: Optional[McStats]
    monte_carlo_arcsec: Optional[McStats]
    p_random_beats_greedy: Optional[float]


@dataclass(frozen=True)
class LoadsUnits:
    """Units of ``loads.json``."""

    length: str
    angle: str
    force: str
    torque: str
    stress: str


@dataclass(frozen=True)
class Operation:
    """How the carrier turns: speed (r/min, rad/s), trains on the carrier, sense (+1 CCW, −1 CW),
    gravity (m/s², trajectory frame; (0, 0) off) and samples over the turn."""

    carrier_rpm: float
    omega_rad_s: float
    arms: int
    direction: int
    gravity_m_s2: Tuple[float, float]
    samples: int


@dataclass(frozen=True, eq=False)
class Bearings:
    """Bearing forces ``[x, y]`` N per sample: the frame on the carrier at O (all arms), the
    carrier on the first arm's intermediate gear at D and on its planet gear (and arm) at A."""

    O_N: Vectors
    D_N: Vectors
    A_N: Vectors


@dataclass(frozen=True, eq=False)
class MeshLoads:
    """One mesh over the turn (per sample): the force along the line of action (N, ≥ 0), the
    loaded ``flank`` (+1 the tangential force turns the driven gear in the sense of travel, −1
    against, 0 unloaded), where it reverses (deg), the pitch point (mm, world frame), the
    effective pressure angle (deg), the pitch curves' signed radii of curvature ``[driver,
    driven]`` (mm, negative concave); with a rating the flank radii ``[driver, driven]`` (mm),
    the contact ratio, the contact stress (MPa) and each gear's root stress ``{gear: MPa}``."""

    normal_force_N: Numbers
    flank: Numbers
    reversals_deg: Numbers
    pitch_point_mm: Points
    effective_pressure_angle_deg: Numbers
    pitch_radius_of_curvature_mm: Vectors
    flank_radius_mm: Optional[Vectors]
    contact_ratio: Optional[Numbers]
    contact_stress_MPa: Optional[Numbers]
    root_stress_MPa: Optional[Dict[str, Numbers]]


@dataclass(frozen=True, eq=False)
class LoadMeshes:
    """The two meshes of the first arm."""

    sun_intermediate: MeshLoads
    intermediate_planet: MeshLoads


@dataclass(frozen=True)
class GearMass:
    """Mass properties: mass (kg), centre of mass in the body frame (mm), moment of inertia
    about the gear's own axis (the arm: about its centre of mass), kg·mm²."""

    mass_kg: float
    com_mm: Tuple[float, float]
    inertia_kg_mm2: float


@dataclass(frozen=True)
class GearMasses:
    """The mass properties used: the gear bodies (face width, density kg/m³, bore; absent:
    massless gears) and the arm as the scene gives it."""

    face_width_mm: Optional[float]
    density_kg_m3: Optional[float]
    bore_mm: Optional[float]
    sun: GearMass
    intermediate: GearMass
    planet: GearMass
    arm: Optional[GearMass]


@dataclass(frozen=True)
class SnLine:
    """An S–N line: life factor ``static_factor`` at ``static_cycles``, 1 at ``knee_cycles``."""

    static_cycles: float
    static_factor: float
    knee_cycles: float


@dataclass(frozen=True)
class Material:
    """The gears' material (MPa): a preset's name or ``custom``."""

    name: str
    E_MPa: float
    poisson: float
    sigma_Hlim_MPa: float
    sigma_Flim_MPa: float
    contact_sn: SnLine
    bending_sn: SnLine
    surface_hardened: bool


@dataclass(frozen=True)
class Factors:
    """The rating factors: ``mode`` ``"iso"`` or ``"nominal"``; the factors the scene sets
    instead of their formulas, or ``None``."""

    mode: str
    K_A: float
    accuracy_grade: int
    K_v: Optional[float]
    K_Hbeta: float
    K_Fbeta: Optional[float]
    K_Halpha: Optional[float]
    K_Falpha: Optional[float]
    Y_ST: float
    Y_M: float


@dataclass(frozen=True)
class RatingOptions:
    """What the teeth were rated with: material, factors, safety targets, and whether on the
    rotor dynamics' mesh forces (``K_v = "dynamic"``, then ``factors.K_v`` = 1)."""

    material: Material
    factors: Factors
    S_H_min: float
    S_F_min: float
    on_dynamic_forces: bool


@dataclass(frozen=True)
class Extreme:
    """A smallest safety factor and where: travel (deg), mesh, gear, tooth."""

    value: float
    travel_deg: float
    mesh: str
    gear: str
    tooth: int


@dataclass(frozen=True)
class GearRating:
    """One gear's rating over the turn: its smallest bending safety factor, largest root stress,
    teeth loaded on both flanks, lives (h, Miner) and the range of Y_F·Y_S."""

    min_S_F: Extreme
    max_root_stress_MPa: float
    alternating_teeth: int
    bending_life_h: float
    pitting_life_h: float
    Y_F_Y_S_range: Tuple[float, float]


@dataclass(frozen=True)
class Rating:
    """The tooth rating (ISO 6336 structure): options, face width and module (mm), the smallest
    safety factors, the shortest life (h) and what limits it, each gear, and notes."""

    options: RatingOptions
    face_width_mm: float
    module_mm: float
    min_S_H: Extreme
    min_S_F: Extreme
    life_h: float
    life_limited_by: str
    gears: Dict[str, GearRating]
    notes: Tuple[str, ...]


@dataclass(frozen=True, eq=False)
class LoadsSummary:
    """Peak, RMS and mean carrier torque (N·m), mean power (W), peak planet mesh torque and frame
    force, the travel angles where the planet mesh torque reverses (deg) and, with a rating, the
    smallest safety factors and the shortest life (h; ``math.inf``: unlimited)."""

    carrier_torque_peak_Nm: float
    carrier_torque_rms_Nm: float
    carrier_torque_mean_Nm: float
    mean_power_W: float
    planet_mesh_torque_peak_Nm: float
    frame_force_peak_N: float
    reversals_deg: Numbers
    min_S_H: Optional[Extreme]
    min_S_F: Optional[Extreme]
    life_h: Optional[float] = field(metadata={"null_is_inf": True})


@dataclass(frozen=True, eq=False)
class LoadsReport:
    """``loads.json``: the planting rotor's loads over one carrier turn at constant speed, per
    sample of ``travel_deg`` (docs/loads.md). Torques (N·m) are positive in the carrier's sense of
    travel; rotor quantities (carrier and sun torque, frame force, bearing O) are sums over the
    arms, the rest the first arm's. ``design``: the design file the scene names (``None`` for a
    design passed in memory). With teeth and a ``[material]``: ``rating`` and the stresses.
    ``needle_table_N``: the needle load's table as the loads use it, rows ``[travel_deg, Fx, Fy]``
    (shape (N, 3), linear between rows; ``None`` without a needle)."""

    schema_version: int
    units: LoadsUnits
    design: Optional[str]
    operation: Operation
    travel_deg: Numbers
    carrier_torque_Nm: Numbers
    sun_torque_Nm: Numbers
    planet_mesh_torque_Nm: Numbers
    frame_force_N: Vectors
    needle_force_N: Vectors
    needle_table_N: Optional[Vectors]
    bearings: Bearings
    meshes: LoadMeshes
    gears: GearMasses
    rating: Optional[Rating]
    summary: LoadsSummary
    verdict: Verdict


@dataclass(frozen=True)
class Dyad:
    """A carrier arm of a synthesis: axis O (mm), arm lengths l1, l3 (mm) and its largest residual
    on the poses (mm)."""

    center_mm: Tuple[float, float]
    l1_mm: float
    l3_mm: float
    max_residual_mm: float


@dataclass(frozen=True)
class Candidate:
    """One candidate arm of a synthesis and how its design passes the poses: the largest pose
    distance (mm) and needle-direction error (degrees), ``None`` when refused (``refused`` says
    why), and the target bands missed."""

    dyad: Dyad
    max_pose_error_mm: Optional[float]
    max_pose_error_deg: Optional[float]
    targets_missed: int
    refused: Optional[str]


@dataclass(frozen=True)
class PoseResult:
    """One pose on the chosen design: its tip (mm) and needle direction (degrees), the carrier
    angle (degrees) where the design's tip is closest, the distance (mm) and needle error
    (degrees) there."""

    tip_mm: Tuple[float, float]
    needle_deg: float
    carrier_deg: float
    error_mm: float
    error_deg: float


@dataclass(frozen=True)
class TargetResult:
    """One agronomic target band ``[min, max]``: the design's value and its margin inside the
    band (negative: outside by that much)."""

    index: str
    band: Tuple[float, float]
    value: float
    margin: float


@dataclass(frozen=True)
class SynthesisReport:
    """``synthesis.json``: the arms found (``dyad_kind`` ``"finite"`` or ``"family"``, or
    ``"targets"``), every candidate tried, the chosen one (index), the carrier sense, each pose
    and target band on the chosen design, and what binds."""

    dyad_kind: str
    dyads: Tuple[Dyad, ...]
    candidates: Tuple[Candidate, ...]
    chosen: int
    carrier: str
    poses: Tuple[PoseResult, ...]
    targets: Tuple[TargetResult, ...]
    binding: Tuple[str, ...]


@dataclass(frozen=True)
class RowNumbers:
    """The numbers of one design of a trade-off: round-trip max deviation and Hausdorff distance
    (mm), largest pressure angle (degrees), tightest concave radius (mm; ``None``: all convex),
    the limits it sits on, the teeth (module rows) and the idler offset (degrees)."""

    max_deviation_mm: float
    hausdorff_mm: float
    pressure_angle_deg: float
    tightest_concave_radius_mm: Optional[float]
    binding: Tuple[str, ...]
    teeth: Optional[int]
    idler_offset_deg: float


@dataclass(frozen=True)
class TradeOffRow:
    """One rung of the trade-off ladder: what was varied (``label``), its pressure-angle limit
    (degrees; ``None``: no limits), concave-radius limit and module (mm), whether it is the
    default design or the off-line layout, and either the design's numbers (``designed``) or the
    message that refused it (``refused``)."""

    label: str
    max_pressure_angle_deg: Optional[float]
    min_concave_radius_mm: Optional[float]
    module_mm: Optional[float]
    is_default: bool
    off_line: bool
    closer_tighter_design: Optional[str]
    designed: Optional[RowNumbers]
    refused: Optional[str]


@dataclass(frozen=True)
class ExactNeeds:
    """What the exact design of an exactly traceable target needs beyond the default limits:
    its deviation (mm), pressure angle (degrees), concave radius (mm), the default design's
    deviation (mm) and a sentence."""

    max_deviation_mm: float
    pressure_angle_deg: float
    concave_radius_mm: Optional[float]
    default_max_deviation_mm: Optional[float]
    message: str


@dataclass(frozen=True)
class TradeOffReport:
    """``tradeoff.json``: what accuracy costs — the target's point count, the carrier axis (mm),
    one row per pressure-angle limit, no limits, the off-line layout and each module, and what
    an exact design needs; ``sizing``: the module sized by strength, as in a design."""

    points: int
    center_mm: Tuple[float, float]
    rows: Tuple[TradeOffRow, ...]
    exact_needs: Optional[ExactNeeds]
    sizing: Optional[ModuleSizing]


@dataclass(frozen=True, eq=False)
class RotorMeshSeries:
    """One mesh of the rotor over the settled turn, per sample of travel: the dynamic normal
    force along the contact flank's line of action (N), the rigid force of ``ncgear loads`` (N),
    the flank in contact (``"drive"``, ``"coast"``, ``"none"`` inside the backlash) and the
    approach of the drive flank (µm; negative: towards the coast flank)."""

    dynamic_force_n: Numbers
    rigid_force_n: Numbers
    contact: Tuple[str, ...]
    deflection_um: Numbers


@dataclass(frozen=True, eq=False)
class RotorMeshesSeries:
    """The two meshes of train 1: sun–intermediate and intermediate–planet."""

    sun_intermediate: RotorMeshSeries
    intermediate_planet: RotorMeshSeries


@dataclass(frozen=True)
class Impact:
    """One impact, a re-contact after a contact loss: travel angle (degrees), the flank struck
    (``"drive"`` or ``"coast"``), the approach speed along the line of action (m/s) and the
    largest mesh force of the impact window (N)."""

    travel_deg: float
    flank: str
    speed_m_s: float
    peak_force_n: float


@dataclass(frozen=True, eq=False)
class RotorMeshSummary:
    """One mesh's summary over the settled turn: the largest dynamic and rigid forces (N), the
    dynamic factor (their ratio), the largest ``|F_dyn − F_rigid|`` relative to the largest rigid
    force, ISO 6336-1 method C's K_v at the largest rigid force (``None`` without teeth), the
    contact-loss intervals (N, 2) ``[from, to]`` in travel degrees (``to < from``: across 0), the
    impacts and their count."""

    peak_dynamic_n: float
    peak_rigid_n: float
    dynamic_factor: float
    largest_deviation_of_peak: float
    iso_K_v: Optional[float]
    contact_loss_deg: Vectors
    impacts: Tuple[Impact, ...]
    impacts_per_turn: int


@dataclass(frozen=True, eq=False)
class RotorMeshesSummary:
    """The summaries of the two meshes: sun–intermediate and intermediate–planet."""

    sun_intermediate: RotorMeshSummary
    intermediate_planet: RotorMeshSummary


@dataclass(frozen=True)
class RotorSteady:
    """The periodic steady state reached: turns integrated, the last turn's relative periodic
    residual, the scene's tolerance and whether the residual fell below it."""

    turns: int
    residual: float
    poincare_tol: float
    settled: bool


@dataclass(frozen=True)
class OdeStats:
    """Integrator counters over all turns: right-hand-side evaluations, accepted and rejected
    steps, located state events."""

    rhs_evals: int
    accepted: int
    rejected: int
    events: int


@dataclass(frozen=True, eq=False)
class RotorSummary:
    """The settled turn's summary: each mesh, the largest distance of the dynamic tip from the
    static path (mm) and its travel angle (degrees), the linearised train's natural frequencies
    at the mean stiffness (Hz), the largest impact speed of either mesh (m/s; 0: none) and the
    impacts per turn of both meshes of one train."""

    meshes: RotorMeshesSummary
    max_tip_deviation_mm: float
    max_tip_deviation_at_deg: float
    natural_frequencies_hz: Tuple[float, float]
    max_impact_speed_m_s: float
    impacts_per_turn: int


@dataclass(frozen=True, eq=False)
class RotorDrive:
    """The compliant drive over the settled turn (``[effects] drive``), per sample of travel:
    the shaft's torque (N·m), the carrier's speed (r/min), the shaft's twist (degrees, the motor
    ahead of the carrier); the shaft's torsional frequency (Hz), the largest shaft torque (N·m)
    and the carrier's speed fluctuation (max − min)/Ω."""

    shaft_torque_nm: Numbers
    carrier_speed_rpm: Numbers
    twist_deg: Numbers
    shaft_frequency_hz: float
    peak_shaft_torque_nm: float
    speed_fluctuation: float


@dataclass(frozen=True, eq=False)
class DynamicsRotorReport:
    """``dynamics.json`` of a rotor scene (docs/dynamics.md, "The rotor"): the settled turn of
    the planting rotor in motion per sample of ``travel_deg`` (degrees) — both meshes' forces,
    the intermediate's and the planet's rotations away from the kinematic law (µrad), the needle
    tip's dynamic path (mm, world frame) and its distance from the static path (mm), the carrier
    torque of every arm, dynamic and rigid (N·m, positive in the sense of travel) — and its
    summary. ``design``: the design file as the scene names it (only echoed for a train passed
    in memory, empty when the scene names none); ``effects``: one line per effect built."""

    schema_version: int
    scene: str
    model: str
    design: str
    carrier_rpm: float
    arms: int
    dofs: Tuple[str, ...]
    effects: Tuple[str, ...]
    steady: RotorSteady
    stats: OdeStats
    travel_deg: Numbers
    meshes: RotorMeshesSeries
    intermediate_deviation_urad: Numbers
    planet_deviation_urad: Numbers
    tip_mm: Points
    tip_deviation_mm: Numbers
    carrier_torque_nm: Numbers
    rigid_carrier_torque_nm: Numbers
    summary: RotorSummary
    drive: Optional[RotorDrive]
