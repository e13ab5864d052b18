"""ncgear: non-circular gears for the planting arm of rice transplanters, from Python.

The same library as the ``ncgear`` command line, called in-process::

    import ncgear
    d = ncgear.design("assets/trajectories/g1_ellipse.csv")   # or an (N, 2) array, mm
    t = ncgear.teeth(d, module=2.0)
    ncgear.write_step(t, "out/step", face_width=20.0, bore=10.0)  # sun/intermediate/planet/train.step

Lengths in mm, angles in radians unless a name ends in ``_deg``. Every failure raises
:class:`NcgearError` (a ``ValueError``) with the message the CLI prints. A result that is made
but fails its own verification (a check C1–C12, interference or a bad backlash in a mesh) is
returned, not raised: its ``verdict`` says ``{"passed": False, "failures": [...]}`` — where the
CLI exits with code 3 — and its ``passed`` property is False.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _ncgear
from ._ncgear import NcgearError

__version__ = _ncgear.__version__
__all__ = [
    "NcgearError", "Design", "Train", "Pair", "design", "teeth", "pair", "simulate",
    "tolerance", "write_step", "write_dxf", "write_svg",
]

PathLike = Union[str, "os.PathLike[str]"]


def _arrays(pairs) -> Dict[str, np.ndarray]:
    return {name: np.asarray(pts, dtype=float).reshape(-1, 2) for name, pts in pairs}


def _placements(rows) -> Dict[str, Dict[str, Any]]:
    return {
        occ: {"part": part, "centre_mm": np.asarray(c, dtype=float), "angle_rad": float(a)}
        for occ, part, c, a in rows
    }


class _Verified:
    """A result with a ``verdict`` (``{"passed": bool, "failures": [str]}``)."""

    verdict: Dict[str, Any]

    @property
    def passed(self) -> bool:
        """Whether the result passed its verification (``verdict["passed"]``)."""
        return bool(self.verdict["passed"])


class _Reported(_Verified):
    """A result whose ``report`` carries its ``verdict``."""

    report: Dict[str, Any]

    @property
    def verdict(self) -> Dict[str, Any]:  # type: ignore[override]
        """``{"passed": bool, "failures": [str]}`` of the report."""
        return self.report["verdict"]


@dataclass(frozen=True)
class Design(_Reported):
    """A designed train: arm lengths, pitch curves (body frames, mm) and the report.

    ``report`` holds the keys and numbers of the CLI's ``design.json``; ``deviations`` is the
    distance (mm) of each target point to the path the designed gears trace.
    """

    l1: float
    l3: float
    pitch_curves: Dict[str, np.ndarray]
    report: Dict[str, Any]
    deviations: np.ndarray
    _h: Any = field(repr=False, compare=False)


@dataclass(frozen=True)
class Train(_Verified):
    """Teeth on a design: outlines (body frames, mm, as exported), placements at carrier angle 0
    (``arm1_*``, ``arm2_*``; centres mm, angles rad) and the ``teeth`` report block."""

    outlines: Dict[str, np.ndarray]
    placements: Dict[str, Dict[str, Any]]
    report: Dict[str, Any]
    design: Design = field(repr=False, compare=False)
    _h: Any = field(repr=False, compare=False)
    verdict: Dict[str, Any] = field(default_factory=dict)
    """``{"passed": bool, "failures": [str]}`` of both meshes (no interference, finite
    non-negative backlash)."""


@dataclass(frozen=True)
class Pair(_Reported):
    """A single toothed pair: driver and driven outlines (body frames, mm), their placements at
    the start (driver at the origin, driven at ``(a, 0)``) and the report."""

    outlines: Dict[str, np.ndarray]
    placements: Dict[str, Dict[str, Any]]
    report: Dict[str, Any]
    _h: Any = field(repr=False, compare=False)


def design(
    points: Union[PathLike, Sequence[Sequence[float]], np.ndarray],
    center: Tuple[float, float] = (0.0, 0.0),
    **options: Any,
) -> Design:
    """Designs the sun and intermediate gears whose train traces ``points``.

    ``points``: an (N, 2) array of needle-tip points in mm in travel order, or the path of a
    trajectory file (CSV/JSON/TXT as the CLI reads). ``center``: the carrier axis O, mm.
    ``options``: ``order``, ``tol_mm``, ``smoothing``, ``fit`` (bool), ``samples``,
    ``refine`` (``"auto"``, ``"on"``, ``"off"``), ``limits`` (bool, default True: design within
    the gear limits), ``max_pressure_angle`` (deg, default 45), ``min_concave_radius`` (mm),
    ``min_convex_radius`` (mm: the undercut limit, default 7·module),
    ``module`` (mm: design for the module, the tooth count a constraint of the fit) — the CLI's
    flags of the same names.
    """
    if isinstance(points, (str, os.PathLike)):
        pts, path = None, os.fspath(points)
    else:
        arr = np.asarray(points, dtype=float)
        if arr.ndim != 2 or arr.shape[1] != 2:
            raise NcgearError(f"points: expected an (N, 2) array, got shape {arr.shape}")
        pts, path = arr.tolist(), None
    cx, cy = (float(v) for v in center)
    h = _ncgear.design(pts, path, (cx, cy), json.dumps(options))
    report = json.loads(h.report_json())
    return Design(
        l1=report["l1"],
        l3=report["l3"],
        pitch_curves=_arrays(h.pitch_curves()),
        report=report,
        deviations=np.asarray(h.deviations(), dtype=float),
        _h=h,
    )


def teeth(
    design: Design,
    module: float,
    policy: Optional[str] = None,
    teeth: Optional[int] = None,
    backlash: Optional[float] = None,
    chord_tol: Optional[float] = None,
    verify_steps: int = 72,
) -> Train:
    """Puts rack-generated teeth on the three gears of ``design`` (``ncgear design --module``).

    ``policy``: ``design`` (the design's own tooth count: default for a design made with
    ``module=`` this module; its perimeters are exactly zπm, nothing is scaled), ``scale-up``
    (default otherwise), ``nearest``, ``scale-down``, ``ratio-amplitude``, ``adjust-module``;
    ``teeth`` forces z. ``backlash`` and ``chord_tol`` in mm (defaults 0.04·m
    and 1e-3·m); ``verify_steps`` carrier positions of the mesh check (0 skips it).
    """
    if policy is None:
        made_for = (design.report.get("module") or {}).get("module_mm")
        policy = "design" if made_for == float(module) and teeth is None else "scale-up"
    h = _ncgear.teeth(design._h, float(module), policy, teeth, backlash, chord_tol, int(verify_steps))
    return Train(
        outlines=_arrays(h.outlines()),
        placements=_placements(h.placements()),
        report=json.loads(h.report_json()),
        design=design,
        _h=h,
        verdict=json.loads(h.verdict_json()),
    )


def pair(
    law: str,
    teeth: Optional[int] = None,
    module: float = 1.0,
    kind: str = "motion",
    verify_steps: int = 90,
    cycle_advance: float = 360.0,
    drive: Optional[Tuple[float, float]] = None,
) -> Pair:
    """A toothed non-circular pair (``ncgear pair``) from a motion law ψ(φ) (``kind="motion"``,
    e.g. ``"phi - 0.08*sin(2*phi)"``), a centrode r(φ) (``"centrode"``) or a CSV law file
    (``"csv"``, ``law`` is its path). ``teeth`` is required for a motion or CSV law: the driver's
    count; the driven gear gets ``teeth·360°/Δ`` with Δ the law's advance per driver turn (a
    centrode is solved for ``cycle_advance``, degrees). ``drive=(start, end)`` (degrees) makes an
    open sector pair of a motion law with ``teeth`` on that driver interval."""
    d = None if drive is None else (float(drive[0]), float(drive[1]))
    h = _ncgear.pair(law, kind, teeth, float(module), int(verify_steps), float(cycle_advance), d)
    return Pair(
        outlines=_arrays(h.outlines()),
        placements=_placements(h.placements()),
        report=json.loads(h.report_json()),
        _h=h,
    )


def simulate(
    design: Union[Design, Train],
    rpm: float = 300.0,
    spacing: Optional[float] = None,
    forward_speed: Optional[float] = None,
    depth: float = 30.0,
) -> Dict[str, Any]:
    """Agronomic features of one carrier turn (``ncgear simulate``): trajectory height, hole
    size, spacing, needle angles… ``spacing`` (mm) or ``forward_speed`` (m/s) sets the machine's
    travel (default 1 m/s); ``depth`` the planting depth, mm. A :class:`Train` simulates the
    final, toothed gears."""
    train = design if isinstance(design, Train) else None
    d = train.design if train is not None else design
    if forward_speed is not None:
        fwd = 1000.0 * float(forward_speed)
    elif spacing is not None:
        if not spacing > 0:
            raise NcgearError(f"--spacing {spacing}: must be a positive plant spacing in mm")
        fwd = _ncgear.forward_for_spacing(float(spacing), float(rpm))
    else:
        fwd = 1000.0
    h = train._h if train is not None else None
    return json.loads(_ncgear.simulate(d._h, h, float(rpm), fwd, float(depth)))


def tolerance(errors: PathLike, samples: int = 0) -> Dict[str, Any]:
    """``ncgear tolerance`` on an error file: the keys of ``tolerance.json``; ``samples`` > 0 adds
    a Monte Carlo run."""
    return json.loads(_ncgear.tolerance(os.fspath(errors), int(samples)))


def write_step(
    obj: Union[Train, Pair], directory: PathLike, face_width: Optional[float] = None, bore: float = 0.0
) -> List[str]:
    """STEP AP214 solids (mm) into ``directory``: for a :class:`Train` ``sun.step``,
    ``intermediate.step``, ``planet.step`` (each about its rotation centre) and ``train.step``
    (both arms at carrier angle 0, an assembly); for a :class:`Pair` ``pair.step``.
    ``face_width`` defaults to 10·m; ``bore`` is a diameter (0: none). Returns the paths."""
    return obj._h.write_step(os.fspath(directory), face_width, float(bore))


def write_dxf(obj: Union[Train, Pair], directory: PathLike) -> List[str]:
    """DXF R2010 (mm) into ``directory``: each gear and the train, or ``pair.dxf``."""
    return obj._h.write_sheets(os.fspath(directory), "dxf")


def write_svg(obj: Union[Train, Pair], directory: PathLike) -> List[str]:
    """SVG (mm) into ``directory``: each gear and the train, or ``pair.svg``."""
    return obj._h.write_sheets(os.fspath(directory), "svg")
