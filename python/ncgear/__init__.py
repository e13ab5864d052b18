"""ncgear: non-circular gears for the planting arm of rice transplanters, from Python.

The same library as the ``ncgear`` command line, called in-process::

    import ncgear
    d = ncgear.design("assets/trajectories/g1_ellipse.csv", tol_mm=0.05)  # or an (N, 2) array, mm
    d.l1_mm, d.limits.pressure_angle_deg, d.gears.sun.pitch      # typed report, numpy points (mm)
    t = ncgear.teeth(d, module=2.0, tooth_policy="scale-up")
    ncgear.write_step(t, "out/step", face_width=20.0, bore=10.0)  # sun/intermediate/planet/train.step
    r = ncgear.loads(t, "assets/loads/rotor.toml")        # loads over a turn, tooth stresses, life

Results are frozen dataclasses (:mod:`ncgear.reports`) with the keys of the CLI's JSON files as
typed fields; ``to_dict()`` and ``json()`` give the JSON itself. Options are keyword arguments
named as the CLI's flags (``--tol-mm`` is ``tol_mm``); lengths in mm, angles in degrees where the
CLI takes degrees. Every failure raises :class:`NcgearError` (a ``ValueError``) naming the
argument at fault. A result that is made but fails its own verification (a check C1–C13,
interference or a bad backlash in a mesh) is returned, not raised: its ``verdict.passed`` is
False — where the CLI exits with code 3.
"""
from __future__ import annotations

import inspect
import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _ncgear
from ._ncgear import NcgearError
from . import reports
from .reports import (
    CompareReport, DesignReport, Features, LoadsReport, PairReport, Points, RotorReport, SynthesisReport,
    ToleranceReport,
    TrainTeethReport, Verdict, build,
)

__version__: str = _ncgear.__version__
__all__ = [
    "NcgearError", "Design", "Train", "Pair", "Placement", "Loads", "design", "teeth", "pair",
    "simulate", "tolerance", "loads", "loads_file", "write_step", "write_dxf", "write_svg",
    "set_max_memory_gb", "Synthesis", "TradeOff", "synthesize", "tradeoff", "redesign",
    "read_trajectory", "Dynamics", "SweepRow", "dynamics", "dynamics_file", "Comparison", "compare",
]

PathLike = Union[str, "os.PathLike[str]"]


class _Json:
    """A result that keeps the report the library wrote."""

    _report: Any

    def to_dict(self) -> Dict[str, Any]:
        """The report as the CLI writes it (parsed JSON)."""
        return json.loads(self._report.json())

    def json(self) -> str:
        """The report as JSON text."""
        return str(self._report.json())


class _Raw(_Json):
    """A result that keeps the report the library wrote and its verdict."""

    @property
    def passed(self) -> bool:
        """Whether the result passed its verification (``verdict.passed``)."""
        verdict: Verdict = getattr(self, "verdict")
        return verdict.passed


@dataclass(frozen=True)
class Placement:
    """Where a part of a STEP assembly sits: its part, centre (mm) and angle (rad)."""

    part: str
    center_mm: Tuple[float, float]
    angle_rad: float


def _placements(rows: List[Tuple[str, str, Tuple[float, float], float]]) -> Dict[str, Placement]:
    return {occ: Placement(part, (float(c[0]), float(c[1])), float(a)) for occ, part, c, a in rows}


def _readonly(arrays: Dict[str, np.ndarray]) -> Dict[str, np.ndarray]:
    for a in arrays.values():
        a.flags.writeable = False
    return arrays


@dataclass(frozen=True, eq=False)
class Design(_Raw, DesignReport):
    """A designed train: the fields of ``design.json`` (:class:`ncgear.reports.DesignReport`)
    and ``deviations``, the distance (mm) of each target point to the path the designed gears
    trace."""

    deviations: npt.NDArray[np.float64]
    _handle: Any = field(repr=False)
    _report: Any = field(repr=False)


@dataclass(frozen=True, eq=False)
class Train(_Raw, TrainTeethReport):
    """Teeth on a design: the ``teeth`` block of ``design.json``
    (:class:`ncgear.reports.TrainTeethReport`), the outlines (body frames, (N, 2) mm, as exported),
    the placements at carrier angle 0 (``sun``, ``arm1_*``, ``arm2_*``) and the verdict of both
    meshes (no interference, finite non-negative backlash) and of the tooth policy (a scaling
    policy that moves the tip by more than the design's C12 limit fails, as in the CLI)."""

    outlines: Dict[str, Points]
    placements: Dict[str, Placement]
    verdict: Verdict
    design: Design = field(repr=False)
    _handle: Any = field(repr=False)
    _report: Any = field(repr=False)


@dataclass(frozen=True, eq=False)
class Pair(_Raw, PairReport):
    """A single toothed pair (:class:`ncgear.reports.PairReport`): driver and driven outlines
    (body frames, (N, 2) mm) and their placements at the start (driver at the origin, driven at
    ``(center_distance_mm, 0)``)."""

    outlines: Dict[str, Points]
    placements: Dict[str, Placement]
    _handle: Any = field(repr=False)
    _report: Any = field(repr=False)


@dataclass(frozen=True, eq=False)
class Loads(_Raw, LoadsReport):
    """The loads of a rotor over one carrier turn: the fields of ``loads.json``
    (:class:`ncgear.reports.LoadsReport`); ``to_dict()``/``json()`` give ``loads.json`` itself and
    ``passed`` whether the safety factors meet their targets (True without a rating)."""

    _report: Any = field(repr=False)


@dataclass(frozen=True, eq=False)
class Dynamics(_Json, RotorReport):
    """The planting rotor in motion, settled to its periodic steady state: the fields of a rotor
    scene's ``dynamics.json`` (:class:`ncgear.reports.RotorReport`);
    ``to_dict()``/``json()`` give ``dynamics.json`` itself."""

    _report: Any = field(repr=False)


@dataclass(frozen=True, eq=False)
class Comparison(_Json, CompareReport):
    """A filmed track against its design (``ncgear compare``, docs/compare.md): the fields of
    ``compare.json`` (:class:`ncgear.reports.CompareReport`) and the frames as arrays, one row
    per frame read: ``frame_carrier_rad`` (N,), the registered tip ``frame_tip_mm`` (N, 2, mm,
    design frame), its residual from the reference path ``frame_residual_mm`` (N, 2, mm) and
    ``frame_outlier`` (N,) bool; ``to_dict()``/``json()`` give ``compare.json`` itself."""

    frame_carrier_rad: np.ndarray = field(repr=False)
    frame_tip_mm: Points = field(repr=False)
    frame_residual_mm: Points = field(repr=False)
    frame_outlier: np.ndarray = field(repr=False)
    _report: Any = field(repr=False)


@dataclass(frozen=True)
class SweepRow:
    """One carrier speed of a rotor sweep (``ncgear dynamics --sweep-rpm``): the speed (r/min),
    the dynamic factors of ``(sun–intermediate, intermediate–planet)``, the impacts per turn of
    one train (both meshes), the largest impact speed (m/s), the largest tip deviation from the
    static path (mm), the turns to the steady state and whether it settled."""

    carrier_rpm: float
    dynamic_factor: Tuple[float, float]
    impacts_per_turn: int
    max_impact_speed_m_s: float
    max_tip_deviation_mm: float
    turns: int
    settled: bool


def _options(given: Dict[str, Any], *positional: str) -> Dict[str, Any]:
    """The keyword arguments of a call (its ``locals()`` first thing) without the positional."""
    return {k: v for k, v in given.items() if k not in positional}


def _design_options(given: Mapping[str, Any], call: str) -> Dict[str, Any]:
    """:func:`design`'s keyword arguments: its defaults, then ``given`` (a name it does not take
    is a ``TypeError``, as for any function)."""
    for name in given:
        if name not in _DESIGN_DEFAULTS:
            raise TypeError(f"{call}() got an unexpected keyword argument {name!r} "
                            f"(it takes design()'s: {', '.join(_DESIGN_DEFAULTS)})")
    return {**_DESIGN_DEFAULTS, **given}


def read_trajectory(
    path: PathLike,
    *,
    layer: Optional[str] = None,
    id: Optional[str] = None,
    units: Optional[Literal["mm", "cm", "m", "in", "px"]] = None,
) -> npt.NDArray[np.float64]:
    """The needle-tip points (N, 2), mm, in travel order, that :func:`design` sees in a file.

    A DXF or SVG drawing (by its extension) is read as ``ncgear design`` reads it: ``layer``
    picks the DXF layer and ``id`` the SVG element whose closed loop is the target (needed when
    the drawing holds several loops); ``units`` gives the size of a drawing unit when the file
    does not say (DXF ``$INSUNITS`` unitless, an SVG without an absolute width) or overrides it.
    Curves are flattened to 1 µm and resampled at 720 points by arc length; a loop of straight
    segments keeps its vertices. CSV, TXT and JSON point files are read as they are (the
    drawing options do not apply). ``design(read_trajectory(path, ...))`` designs the same gears
    as ``ncgear design path --layer ... --units ...``. A path that crosses itself is taken in the
    order drawn. Errors (open loops, more than two ends at a point, a stretch drawn twice,
    several loops, unknown units) are :class:`NcgearError` naming what to fix.
    """
    return _ncgear.read_trajectory(os.fspath(path), layer, id, units)


def design(
    points: Union[PathLike, npt.ArrayLike],
    *,
    center: Tuple[float, float] = (0.0, 0.0),
    order: Optional[int] = None,
    sense: Literal["auto", "ccw", "cw"] = "auto",
    tol_mm: float = 0.05,
    refine: Literal["auto", "on", "off"] = "auto",
    refine_order: int = 12,
    harmonics: Sequence[Tuple[float, float]] = (),
    route: Literal["ac", "bd"] = "ac",
    w1: float = 0.5,
    k_max: int = 20,
    grid: int = 1024,
    dense: int = 20000,
    samples: int = 3600,
    ratio_bounds: Tuple[float, float] = (0.3, 3.3),
    fit: bool = True,
    limits: bool = True,
    max_pressure_angle: float = 45.0,
    min_concave_radius: Optional[float] = None,
    min_convex_radius: Optional[float] = None,
    convexity: bool = False,
    smooth: Optional[int] = None,
    module: Union[float, Literal["auto"], None] = None,
    idler_offset: Literal["auto", "collinear", "free"] = "auto",
    alternatives: bool = False,
    loads: Union[PathLike, Mapping[str, Any], None] = None,
) -> Design:
    """Designs the sun and intermediate gears whose train traces ``points`` (``ncgear design``).

    ``points``: an (N, 2) array of needle-tip points in mm in travel order, or the path of a
    trajectory file (CSV/JSON as the CLI reads). The options are the CLI's flags:

    - ``center``: carrier axis O, mm. ``sense``: carrier sense (``"auto"``: the better one).
    - ``order``: fixed Fourier order K (``None``: adaptive 4…40 until ``tol_mm`` is met).
    - ``tol_mm``: target max tip deviation, mm. ``samples``: points per output pitch curve.
    - ``refine``, ``refine_order``: the tip-motion refinement and its order.
    - ``harmonics``: hypothesis harmonics ``(A, phi_deg)`` of F′₀ = 1 + Σ A_n sin(2n·u + φ_n).
    - ``route`` (``"ac"`` front exact, ``"bd"`` back exact), ``w1`` (mirror weight), ``k_max``
      (iteration cap): the patent route. ``grid``: carrier-angle FFT size; ``dense``: dense
      samples of the trajectory interpolant.
    - ``ratio_bounds``: admissible sun ratio range. ``fit``: the final fit to the points
      (``--no-fit`` is ``fit=False``). ``limits``: design within the gear limits
      (``--limits off`` is ``limits=False``).
    - ``max_pressure_angle``: largest effective pressure angle, degrees.
      ``min_concave_radius`` / ``min_convex_radius``: radius-of-curvature limits, mm (defaults
      12.5·module or 10 mm, and 7·module or none). ``convexity``: convex pitch curves only.
    - ``smooth``: smooth noisy points to this many Fourier harmonics first.
    - ``module``: design for this module, mm: the tooth count a constraint of the fit (then
      :func:`teeth` with the same module cuts the design's own teeth, unscaled). ``"auto"``
      (with ``loads``): the module sized by strength, as ``ncgear design --module auto --loads
      SCENE``: the target designed, toothed (default rack) and rated at each standard module,
      smallest first, and the design of the smallest that meets the scene's S_H and S_F targets
      kept (the best one, failing its verdict, when none does); the table is ``Design.sizing``
      (:class:`ncgear.reports.ModuleSizing`; ``sizing.chosen_module_mm``, and per module
      ``rows[i].teeth``, ``s_h``, ``s_f``), and ``teeth(d, d.sizing.chosen_module_mm)`` cuts the
      teeth that were rated.
    - ``loads``: the loads scene the module is sized for (``module="auto"`` only): a scene file
      (TOML or JSON, with ``[material]``) or a dict of its tables, as :func:`loads` takes; its
      ``design`` key is not read.
    - ``idler_offset``: where the intermediate axis may sit: ``"auto"`` on the carrier line
      unless a whole number of teeth would move the arm (designing for a ``module``, turned off
      it by the offset that keeps the arm, ``l1 = 2a·cos ε``); ``"collinear"`` never; ``"free"``
      in every fit. The design's offset is ``Design.idler_offset_deg``.
    - ``alternatives``: when the design fails its verification, design its nearest alternative
      too (the other idler layout, else a looser pressure-angle limit, else a smaller module) and
      name it in ``Design.alternatives`` and the warnings, as the CLI's ``--alternatives`` does:
      one more design, about as long as this one. Without it a failed design names the
      alternatives that apply in its warnings, not designed.
    """
    options = _options(locals(), "points", "loads")
    if module == "auto":
        if loads is None:
            raise NcgearError('module="auto" sizes the module by strength: give the loads the '
                              'gears must carry, loads=SCENE (a scene file or dict, docs/loads.md)')
        options["module"] = None
        if isinstance(loads, Mapping):
            scene, text = "loads", _scene_json(loads, "loads")
        else:
            scene, text = os.fspath(loads), None
        return _design_of(_ncgear.design_sized(*_target(points), options, scene, text))
    if loads is not None:
        raise NcgearError('loads= sizes the module (module="auto"); the loads of a design at '
                          'module M are ncgear.loads(ncgear.teeth(d, M), scene)')
    return _design_of(_ncgear.design(*_target(points), options))


def _target(
    points: Union[PathLike, npt.ArrayLike],
) -> Tuple[Optional[npt.NDArray[np.float64]], Optional[str]]:
    """A target as the binding takes it: ``(array, None)`` or ``(None, path)``."""
    if isinstance(points, (str, os.PathLike)):
        return None, os.fspath(points)
    return np.ascontiguousarray(points, dtype=np.float64), None


def _design_of(h: Any) -> Design:
    """The :class:`Design` of a design handle."""
    report = h.report()
    return build(Design, report.tree(), deviations=h.deviations(), _handle=h, _report=report)


def _default_policy(design: Design, module: float, teeth: Optional[int]) -> str:
    """``"design"`` for a design made for ``module`` (no ``teeth`` given), else ``"scale-up"``."""
    made_for = design.module.module_mm if design.module is not None else None
    return "design" if made_for == float(module) and teeth is None else "scale-up"


#: :func:`design`'s keyword arguments and their defaults (shared by :func:`redesign` and
#: :func:`synthesize`; ``loads``, the sizing's scene, is :func:`design`'s own).
_DESIGN_DEFAULTS: Dict[str, Any] = {
    name: p.default for name, p in inspect.signature(design).parameters.items()
    if p.kind is inspect.Parameter.KEYWORD_ONLY and name != "loads"
}


def teeth(
    design: Design,
    module: float,
    *,
    tooth_policy: Optional[
        Literal["design", "scale-up", "nearest", "scale-down", "ratio-amplitude", "adjust-module"]
    ] = None,
    teeth: Optional[int] = None,
    wire_edm: bool = False,
    verify_steps: int = 72,
    pressure_angle: float = 20.0,
    addendum: float = 1.0,
    clearance: float = 0.25,
    fillet: float = 0.38,
    backlash: Optional[float] = None,
    chord_tol: Optional[float] = None,
    cutter_teeth: Optional[int] = None,
    refuse_undercut: bool = False,
) -> Train:
    """Puts rack-generated teeth of ``module`` (mm) on the three gears of ``design``
    (``ncgear design --module``).

    ``tooth_policy``: how the tooth count is made an integer — ``"design"`` (the design's own
    count; default for a design made with ``module=`` this module), ``"scale-up"`` (default
    otherwise), ``"nearest"``, ``"scale-down"``, ``"ratio-amplitude"``, ``"adjust-module"``;
    ``teeth`` forces z. ``wire_edm``: sweep a gear no shaper cutter fits. ``verify_steps``:
    carrier positions of each mesh check (0 skips it). The rack: ``pressure_angle`` (degrees),
    ``addendum``, ``clearance``, ``fillet`` (factors of the module). ``backlash`` and
    ``chord_tol`` in mm (defaults 0.04·m and 1e-3·m). ``cutter_teeth``: the shaper cutter for
    concave gears (default: the largest that fits). ``refuse_undercut`` (``--no-undercut``):
    refuse a gear the rack undercuts.
    """
    tooth = _options(locals(), "design", "module", "tooth_policy", "teeth", "wire_edm")
    policy = tooth_policy if tooth_policy is not None else _default_policy(design, module, teeth)
    h = _ncgear.teeth(design._handle, module, policy, teeth, wire_edm, tooth)
    report = h.report()
    return build(
        Train, report.tree(), outlines=_readonly(h.outlines()),
        placements=_placements(h.placements()), verdict=build(Verdict, h.verdict().tree()),
        design=design, _handle=h, _report=report,
    )


def pair(
    law: str,
    *,
    kind: Literal["motion", "centrode", "csv"] = "motion",
    teeth: Optional[int] = None,
    module: float = 1.0,
    cycle_advance: float = 360.0,
    drive: Optional[Tuple[float, float]] = None,
    verify_steps: int = 90,
    pressure_angle: float = 20.0,
    addendum: float = 1.0,
    clearance: float = 0.25,
    fillet: float = 0.38,
    backlash: Optional[float] = None,
    chord_tol: Optional[float] = None,
    cutter_teeth: Optional[int] = None,
    refuse_undercut: bool = False,
) -> Pair:
    """A toothed non-circular pair (``ncgear pair``) of ``module`` (mm) from a motion law ψ(φ)
    (``kind="motion"``, e.g. ``"phi - 0.08*sin(2*phi)"``), a centrode r(φ) (``"centrode"``) or a
    CSV law file (``"csv"``, ``law`` is its path).

    ``teeth``: the driver's count (required for a motion or CSV law); the driven gear gets
    ``teeth·360°/Δ`` with Δ the law's advance per driver turn (a centrode is solved for
    ``cycle_advance``, degrees). ``drive=(start, end)`` (degrees; ``--open --drive-start
    --drive-end``) makes an open sector pair on that driver interval. The rack and verification
    options are those of :func:`teeth`.
    """
    tooth = _options(locals(), "law", "kind", "teeth", "module", "cycle_advance", "drive")
    h = _ncgear.pair(law, kind, teeth, module, cycle_advance, drive, tooth)
    report = h.report()
    return build(
        Pair, report.tree(), outlines=_readonly(h.outlines()),
        placements=_placements(h.placements()), _handle=h, _report=report,
    )


def _forward_mm_s(rpm: float, spacing: Optional[float], speed: Optional[float]) -> float:
    """The machine's forward speed, mm/s: from ``speed`` (m/s) or plant ``spacing`` (mm)."""
    if spacing is not None and speed is not None:
        raise NcgearError(f"spacing={spacing!r}: not with speed={speed!r} (give one of them)")
    if speed is not None:
        return 1000.0 * float(speed)
    if spacing is None:
        return 1000.0
    if not spacing > 0:
        raise NcgearError(f"spacing={spacing!r}: must be a positive plant spacing in mm")
    return float(_ncgear.forward_for_spacing(float(spacing), float(rpm)))


def simulate(
    design: Union[Design, Train],
    *,
    rpm: float = 300.0,
    spacing: Optional[float] = None,
    speed: Optional[float] = None,
    depth: float = 30.0,
    take_level: Optional[float] = None,
    plant_level: Optional[float] = None,
) -> Features:
    """Agronomic features of one carrier turn (``ncgear simulate``): trajectory height, hole
    size, spacing, needle angles… ``rpm``: carrier speed. ``spacing`` (mm) or ``speed`` (m/s)
    sets the machine's travel (default 1 m/s); ``depth``: planting depth, mm; ``take_level`` /
    ``plant_level``: seedling-taking and planting levels y, mm (default the highest / lowest
    point). A :class:`Train` simulates the final, toothed gears."""
    train = design if isinstance(design, Train) else None
    d = train.design if train is not None else design
    fwd = _forward_mm_s(rpm, spacing, speed)
    h = train._handle if train is not None else None
    r = _ncgear.simulate(d._handle, h, rpm, fwd, depth, (take_level, plant_level))
    return build(Features, r.tree())


def tolerance(errors: PathLike, *, samples: int = 0, seed: int = 1, starts: int = 24) -> ToleranceReport:
    """``ncgear tolerance`` on an error file: the fields of ``tolerance.json``. ``samples`` > 0
    adds a Monte Carlo of that many random assemblies (seed ``seed``); ``starts``: starts of the
    joint phase optimizer."""
    r = _ncgear.tolerance(os.fspath(errors), samples, seed, starts)
    return build(ToleranceReport, r.tree())


def _scene_json(scene: Mapping[str, Any], arg: str = "scene") -> str:
    """A dict scene (argument ``arg``) as JSON text (numpy arrays and numbers as lists and
    numbers)."""

    def plain(o: Any) -> Any:
        if isinstance(o, np.ndarray):
            return o.tolist()
        if isinstance(o, np.generic):
            return o.item()
        if isinstance(o, os.PathLike):
            return os.fspath(o)
        raise TypeError(f"a {type(o).__name__} is not a scene value")

    try:
        return json.dumps(dict(scene), allow_nan=False, default=plain)
    except (TypeError, ValueError) as e:
        raise NcgearError(f"{arg}: {e}") from None


def _design_and_train(design: Any) -> Tuple[Design, Any]:
    """The design of a :class:`Design` or :class:`Train`, and the train's handle (None for a
    design); a TypeError for anything else."""
    train = design if isinstance(design, Train) else None
    d = train.design if train is not None else design
    if not isinstance(d, Design):
        got = type(design).__name__
        raise TypeError(f"design: expected an ncgear.Design or ncgear.Train, got {got}")
    return d, (train._handle if train is not None else None)


def loads(design: Union[Design, Train], scene: Union[PathLike, Mapping[str, Any]]) -> Loads:
    """The planting rotor's loads over one carrier turn at constant speed (``ncgear loads``,
    docs/loads.md): carrier, sun and planet-mesh torques, the frame, bearing and mesh forces and,
    for a :class:`Train` under a scene with ``[material]``, the tooth stresses (ISO 6336
    structure), their safety factors and the life.

    ``design``: a :class:`Design` (its pitch curves: loads only; a scene with ``[material]`` is
    an error) or a :class:`Train` (its teeth, scaled assembly and rack). ``scene``: the path of a
    scene file (TOML or JSON), or a dict of its tables with the same keys
    (``{"operation": {"carrier_rpm": 300.0, "arms": 2}, "arm": {...}, "gears": {...},
    "needle": {...}, "material": {...}, "rating": {...}}``). The scene's ``design`` key, if any,
    is ignored: the design passed is the one loaded (:func:`loads_file` runs a scene on the design
    file it names). A bad or unknown key raises :class:`NcgearError` naming the key and its
    range; the scene's name in messages is its path, or ``scene`` for a dict. A rating that misses
    its safety targets is returned with ``passed`` False.
    """
    d, h = _design_and_train(design)
    if isinstance(scene, Mapping):
        r = _ncgear.loads(d._handle, h, "scene", _scene_json(scene))
    else:
        r = _ncgear.loads(d._handle, h, os.fspath(scene), None)
    return build(Loads, r.tree(), _report=r)


def loads_file(scene: PathLike) -> Loads:
    """``ncgear loads SCENE`` in-process: the scene file and the design file it names
    (``design = "…/design.json"``, relative to the scene file; its teeth made again when the
    scene rates them). ``to_dict()`` is the CLI's ``loads.json``, number for number."""
    r = _ncgear.loads_file(os.fspath(scene))
    return build(Loads, r.tree(), _report=r)


def _rotor_result(r: Any, sweep_rpm: Optional[Sequence[float]]) -> Union[Dynamics, List[SweepRow]]:
    """The rotor report ``r`` as a :class:`Dynamics`, or a sweep's rows."""
    if sweep_rpm is not None:
        return [build(SweepRow, row) for row in r.tree()]
    return build(Dynamics, r.tree(), _report=r)


def _speeds(sweep_rpm: Optional[Sequence[float]]) -> Optional[List[float]]:
    """The sweep's carrier speeds (r/min) as floats."""
    if sweep_rpm is None:
        return None
    try:
        return [float(v) for v in np.asarray(sweep_rpm, dtype=np.float64).reshape(-1)]
    except (TypeError, ValueError) as e:
        raise NcgearError(f"sweep_rpm: {e}") from None


def dynamics(
    design: Union[Design, Train],
    scene: Union[PathLike, Mapping[str, Any]],
    *,
    sweep_rpm: Optional[Sequence[float]] = None,
) -> Union[Dynamics, List[SweepRow]]:
    """The planting rotor in motion (``ncgear dynamics`` on a rotor scene, docs/dynamics.md,
    "The rotor"): the train's elastic teeth, tooth-pair alternation, damping and backlash with
    contact loss and impacts, integrated turn after turn to the periodic steady state, as a
    :class:`Dynamics`; with ``sweep_rpm`` (carrier speeds, r/min, each in (0, 3000], at most
    200) the steady state at each speed instead, as a list of :class:`SweepRow`.

    ``design``: a :class:`Train` (its teeth, scaled assembly and rack: what the ISO stiffness and
    ``backlash = "teeth"`` read) or a :class:`Design` (its pitch curves: only the effects given
    by value). ``scene``: the path of a rotor scene file (TOML or JSON, ``[scene] model =
    "rotor"``), or a dict of its tables with the same keys; its ``scene.design`` key may be left
    out and is not read (the design passed is the one run; the key is only echoed in ``design``,
    empty without it). A bad or unknown key, or
    an effect the design cannot give, raises :class:`NcgearError` naming the key
    (``effects.mesh_damping.zeta``); the scene's name in messages is its path, or ``scene`` for a
    dict. A run that does not settle is returned with ``steady.settled`` False.
    """
    d, h = _design_and_train(design)
    rpm = _speeds(sweep_rpm)
    if isinstance(scene, Mapping):
        r = _ncgear.dynamics(d._handle, h, "scene", _scene_json(scene), rpm)
    else:
        r = _ncgear.dynamics(d._handle, h, os.fspath(scene), None, rpm)
    return _rotor_result(r, sweep_rpm)


def dynamics_file(
    scene: PathLike, *, sweep_rpm: Optional[Sequence[float]] = None
) -> Union[Dynamics, List[SweepRow]]:
    """``ncgear dynamics SCENE`` in-process on a rotor scene: the scene file and the design file
    it names (``design = "…/design.json"``, relative to the scene file). ``to_dict()`` is the
    CLI's ``dynamics.json``, number for number; with ``sweep_rpm`` (r/min) the sweep's rows, as
    ``--sweep-rpm`` gives them."""
    return _rotor_result(_ncgear.dynamics_file(os.fspath(scene), _speeds(sweep_rpm)), sweep_rpm)


def compare(
    track: PathLike,
    design: Union[Design, Train, PathLike],
    *,
    dynamics: Optional[PathLike] = None,
    **options: Any,
) -> Comparison:
    """``ncgear compare TRACK --design …`` in-process: the track file ``track`` (plain CSV,
    Tracker's or Kinovea's export) registered to the static path of ``design`` (a
    :class:`Design`, a :class:`Train`'s design, or a ``design.json`` path) and compared with it;
    with ``dynamics`` (a rotor scene file of the same design) against its dynamic path at the
    recorded speed too (``dynamics`` in the result). ``options`` are the CLI's flags of the same
    names with underscores, read by the library itself (its keys, defaults and checks; an
    unknown key raises :class:`NcgearError` naming it): ``rpm``, ``fps``, ``columns`` (list of
    names or 1-based positions), ``encoder``, ``units``, ``px_per_mm``, ``calibration`` (x1, y1,
    x2, y2, dist_mm), ``fit_scale``, ``carrier_axis`` (x, y), ``rotation`` (deg), ``mirror``,
    ``y_down``, ``y_up``, ``drift_order`` (3), ``smooth_order`` (chosen when absent), ``depth``
    (30 mm), ``spacing`` (mm)."""
    args = json.dumps({k: _plain(v) for k, v in options.items()})
    scene = os.fspath(dynamics) if dynamics is not None else None
    if isinstance(design, (Design, Train)):
        d, _ = _design_and_train(design)
        out = _ncgear.compare(os.fspath(track), d._handle, None, args, scene)
    else:
        out = _ncgear.compare(os.fspath(track), None, os.fspath(design), args, scene)
    r, phi, tip, residual, outlier = out
    return build(
        Comparison,
        r.tree(),
        frame_carrier_rad=phi,
        frame_tip_mm=tip,
        frame_residual_mm=residual,
        frame_outlier=np.asarray(outlier, dtype=bool),
        _report=r,
    )


def _plain(v: Any) -> Any:
    """``v`` as JSON takes it: numpy arrays and tuples as lists, numpy scalars as numbers."""
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (tuple, list)):
        return [_plain(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    return v


@dataclass(frozen=True, eq=False)
class Synthesis(_Json, SynthesisReport):
    """A synthesis (``ncgear synthesize``): the fields of ``synthesis.json``
    (:class:`ncgear.reports.SynthesisReport`) and the chosen :class:`Design` (``design``);
    ``passed`` is the design's verdict."""

    design: Design = field(repr=False)
    _report: Any = field(repr=False)

    @property
    def passed(self) -> bool:
        """Whether the chosen design passed its verification."""
        return self.design.passed


@dataclass(frozen=True, eq=False)
class TradeOff(_Json, reports.TradeOff):
    """What accuracy costs (``ncgear tradeoff``): the fields of ``tradeoff.json``
    (:class:`ncgear.reports.TradeOff`), one row per gear limit, layout and module."""

    _report: Any = field(repr=False)


def synthesize(
    spec: Union[PathLike, Mapping[str, Any]],
    *,
    l1_mm: Optional[Tuple[float, float]] = None,
    l3_mm: Optional[Tuple[float, float]] = None,
    **options: Any,
) -> Synthesis:
    """Key poses or agronomic target bands → carrier arm and gears (``ncgear synthesize``).

    ``spec``: a spec file (TOML or JSON: ``[machine]``, ``[[pose]]`` with ``x_mm``, ``y_mm``,
    ``needle_deg``, ``[targets]``), or a dict of the same keys (``{"pose": [...]}``).
    ``l1_mm``, ``l3_mm``: the arm's search box ``(min, max)``, mm, in place of the spec's
    ``machine.l1_mm`` / ``machine.l3_mm`` (targets-only specs; a study varies them this way).
    ``options``: :func:`design`'s keyword arguments for each candidate's gears (``module=2.0``
    designs them for that module, ``idler_offset="free"`` lets the intermediate axis leave the
    carrier line, ``max_pressure_angle=40.0`` …), except ``center``: the carrier axis is the
    spec's ``machine.center_mm`` or the one solved for. Raises :class:`NcgearError` on a bad spec
    or when no candidate arm gives a design; a design that fails its checks or misses a band is
    returned (see ``passed``, ``targets[i].margin``).
    """
    if "center" in options:
        raise NcgearError("center: the synthesis solves for the carrier axis; give it as the "
                          "spec's machine.center_mm")
    opts = _design_options(options, "synthesize")
    box = tuple(None if b is None else (float(b[0]), float(b[1])) for b in (l1_mm, l3_mm))
    if isinstance(spec, Mapping):
        r, h = _ncgear.synthesize("spec", _scene_json(spec, "spec"), opts, *box)
    else:
        r, h = _ncgear.synthesize(os.fspath(spec), None, opts, *box)
    return build(Synthesis, r.tree(), design=_design_of(h), _report=r)


def tradeoff(
    points: Union[PathLike, npt.ArrayLike], *, center: Tuple[float, float] = (0.0, 0.0)
) -> TradeOff:
    """What accuracy costs (``ncgear tradeoff``): the target ``points`` (an (N, 2) array, mm, or a
    trajectory file) designed once per pressure-angle limit (35°…50° and none), with the
    intermediate axis off the carrier line, and per module (1…3 mm); ``center``: carrier axis O,
    mm. A refused design is a row whose ``refused`` is its message. The designs run in parallel
    on the library's threads, without the GIL."""
    r = _ncgear.tradeoff(*_target(points), (float(center[0]), float(center[1])))
    return build(TradeOff, r.tree(), _report=r)


def redesign(
    points: Union[PathLike, npt.ArrayLike], start: Union[Design, PathLike], **options: Any
) -> Design:
    """The design of ``points`` warm-started from ``start``, an earlier design of a nearby target
    (a :class:`Design`, or the path of its ``design.json``): the edit loop of an interactive
    designer. One local fit from the start's train replaces the full search of :func:`design`
    (much faster; a local optimum near the start, so its deviation may exceed a full design's).
    A start that does not fit the target (another carrier sense) gives :func:`design`'s result.
    ``options``: :func:`design`'s keyword arguments."""
    options = _design_options(options, "redesign")
    if isinstance(start, Design):
        h = _ncgear.redesign(*_target(points), start._handle, None, options)
    elif isinstance(start, (str, os.PathLike)):
        try:
            with open(start, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise NcgearError(f"start={os.fspath(start)!r}: cannot read it ({e.strerror})") from None
        h = _ncgear.redesign(*_target(points), None, text, options)
    else:
        got = type(start).__name__
        raise NcgearError(f"start: expected an ncgear.Design or a design.json path, got {got}")
    return _design_of(h)


def write_step(
    obj: Union[Train, Pair], directory: PathLike, *, face_width: Optional[float] = None, bore: float = 0.0
) -> List[str]:
    """STEP AP214 solids (mm) into ``directory``: for a :class:`Train` ``sun.step``,
    ``intermediate.step``, ``planet.step`` (each about its rotation centre) and ``train.step``
    (both arms at carrier angle 0, an assembly); for a :class:`Pair` ``pair.step``.
    ``face_width`` defaults to 10·m; ``bore`` is a diameter (0: none). Returns the paths."""
    return list(obj._handle.write_step(os.fspath(directory), face_width, bore))


def write_dxf(
    obj: Union[Train, Pair], directory: PathLike, *, version: Literal["r2010", "r12"] = "r2010"
) -> List[str]:
    """DXF (mm) into ``directory``: each gear and the train, or ``pair.dxf``; ``version``
    ``"r2010"`` (closed LWPOLYLINE) or ``"r12"`` (POLYLINE/VERTEX, for old programs)."""
    return list(obj._handle.write_sheets(os.fspath(directory), "dxf", version))


def write_svg(obj: Union[Train, Pair], directory: PathLike) -> List[str]:
    """SVG (mm) into ``directory``: each gear and the train, or ``pair.svg``."""
    return list(obj._handle.write_sheets(os.fspath(directory), "svg", "r2010"))


def set_max_memory_gb(gb: float) -> None:
    """Memory a single computation may estimate for itself before it is refused, GB (the CLI's
    ``--max-memory-gb``; default 4). Applies to the whole process."""
    _ncgear.set_max_memory_gb(gb)
