"""The jobs a study runs, one point at a time: a call of the package (``design``, ``synthesize``,
``tradeoff``, ``loads``) on one dict of keyword arguments, and the figures a gear engineer
compares, as one flat row. Runs on a Dask worker as well as in the calling process; a failing
point is a row whose ``error`` is the message, never an exception."""
from __future__ import annotations

import json
import math
import os
import time
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple

import numpy as np

import ncgear
from ncgear import _ncgear

#: Figures of a design, in row order, each named after the report field it is (docs/studies.md):
#: the distance of the target points to the traced path (max and mean of ``Design.deviations``,
#: mm), the round trip's max tip deviation (``Design.roundtrip.max_deviation_mm``, mm), the largest pressure angle (degrees),
#: the tightest concave and convex radii of curvature (mm; ``inf``: none), the teeth per gear (a
#: design for a module, else ``None``), the idler offset (degrees), the arms l1, l3 (mm) and the
#: verdict.
DESIGN_FIGURES: Tuple[str, ...] = (
    "deviations_max_mm", "deviations_mean_mm", "roundtrip_max_deviation_mm", "pressure_angle_max_deg",
    "concave_radius_min_mm", "convex_radius_min_mm", "teeth", "idler_offset_deg", "l1_mm",
    "l3_mm", "passed",
)
#: The agronomic target bands a synthesis spec may give (``[targets]``, mm and degrees).
BANDS: Tuple[str, ...] = (
    "take_angle_deg", "push_angle_deg", "angle_difference_deg", "height_mm", "hole_width_mm",
    "arm_clearance_mm",
)
#: A trade-off: the default row's figures, the rows designed and the closest row's deviation.
TRADEOFF_FIGURES: Tuple[str, ...] = (
    "designed_max_deviation_mm", "pressure_angle_max_deg", "concave_radius_min_mm",
    "idler_offset_deg", "rows_designed", "best_max_deviation_mm", "best_row",
)
#: Loads: the design's figures, the carrier torque (peak, RMS; N·m), mean power (W), and with a
#: rating the smallest pitting and bending safety factors S_H, S_F and the life (h).
LOADS_FIGURES: Tuple[str, ...] = DESIGN_FIGURES + (
    "carrier_torque_peak_Nm", "carrier_torque_rms_Nm", "mean_power_W", "S_H_min", "S_F_min",
    "life_h", "loads_passed",
)
#: A synthesis: the chosen design's figures, its largest pose distance (mm), the bands it
#: misses and each band's margin ``margin_<band>`` (in the band's unit, < 0 outside it, ``None``
#: when the spec gives no such band); with a ``scene``, the loads' figures of its gears.
SYNTHESIZE_FIGURES: Tuple[str, ...] = (
    DESIGN_FIGURES + ("pose_error_max_mm", "targets_missed")
    + tuple(f"margin_{b}" for b in BANDS) + LOADS_FIGURES[len(DESIGN_FIGURES):]
)
FIGURES: Dict[str, Tuple[str, ...]] = {
    "design": DESIGN_FIGURES, "synthesize": SYNTHESIZE_FIGURES, "tradeoff": TRADEOFF_FIGURES,
    "loads": LOADS_FIGURES,
}


def _radius(r: Optional[float]) -> float:
    return math.inf if r is None else float(r)


def design_figures(d: ncgear.Design) -> Dict[str, Any]:
    """The figures of design ``d`` (:data:`DESIGN_FIGURES`)."""
    dev = np.asarray(d.deviations)
    return {
        "deviations_max_mm": float(dev.max()),
        "deviations_mean_mm": float(dev.mean()),
        "roundtrip_max_deviation_mm": float(d.roundtrip.max_deviation_mm),
        "pressure_angle_max_deg": float(d.limits.pressure_angle_deg),
        "concave_radius_min_mm": _radius(d.limits.tightest_concave_radius_mm),
        "convex_radius_min_mm": _radius(d.limits.tightest_convex_radius_mm),
        "teeth": int(d.module.teeth) if d.module is not None else None,
        "idler_offset_deg": float(d.idler_offset_deg),
        "l1_mm": float(d.l1_mm),
        "l3_mm": float(d.l3_mm),
        "passed": bool(d.verdict.passed),
    }


def _design(p: Dict[str, Any]) -> Dict[str, Any]:
    p = dict(p)
    return design_figures(ncgear.design(p.pop("points"), **p))


def _synthesize(p: Dict[str, Any]) -> Dict[str, Any]:
    """``spec`` (a spec file or dict), ``l1_max_mm`` / ``l3_max_mm`` (the arm box's upper edges,
    mm: the spec's ``machine.l1_mm`` / ``machine.l3_mm`` searched up to there), ``scene`` and
    ``tooth_module`` as for job ``loads`` (the module defaults to the design's own ``module``),
    the rest :func:`ncgear.synthesize`'s options (:func:`ncgear.design`'s)."""
    p = dict(p)
    spec = p.pop("spec", None)
    if spec is None:
        raise ncgear.NcgearError("spec: missing (a synthesis spec file or dict)")
    box = {k: p.pop(k) for k in ("l1_max_mm", "l3_max_mm") if k in p}
    scene = p.pop("scene", None)
    tooth_module = p.pop("tooth_module", p.get("module"))
    if box:
        given = dict(zip(("l1_mm", "l3_mm"), _ncgear.spec_box(*_spec_args(spec))))
        for key, top in box.items():
            field = key.replace("_max_mm", "_mm")
            p[field] = (float(given[field][0]), float(top))
    s = ncgear.synthesize(spec, **p)
    errors = [q.error_mm for q in s.poses]
    margins = {f"margin_{t.index}": float(t.margin) for t in s.targets}
    row = {
        **design_figures(s.design),
        "pose_error_max_mm": max(errors) if errors else None,
        "targets_missed": sum(1 for t in s.targets if t.margin < 0.0),
        **{f"margin_{b}": margins.get(f"margin_{b}") for b in BANDS},
    }
    if scene is not None:
        row.update(_loads_figures(s.design, scene, tooth_module))
    return row


def _spec_args(spec: Any) -> Tuple[str, Optional[str]]:
    """A spec as the binding takes it: ``(path, None)`` or ``("spec", JSON text)``."""
    if isinstance(spec, Mapping):
        return "spec", json.dumps(dict(spec))
    return os.fspath(spec), None


def _tradeoff(p: Dict[str, Any]) -> Dict[str, Any]:
    t = ncgear.tradeoff(**p)
    made = [r for r in t.rows if r.designed is not None]
    default = next((r.designed for r in t.rows if r.is_default), None)
    best = min(made, key=lambda r: r.designed.max_deviation_mm) if made else None  # type: ignore
    return {
        "designed_max_deviation_mm": default.max_deviation_mm if default else None,
        "pressure_angle_max_deg": default.pressure_angle_deg if default else None,
        "concave_radius_min_mm": _radius(default.tightest_concave_radius_mm) if default else None,
        "idler_offset_deg": default.idler_offset_deg if default else None,
        "rows_designed": len(made),
        "best_max_deviation_mm": best.designed.max_deviation_mm if best else None,  # type: ignore
        "best_row": best.label if best else None,
    }


def _loads(p: Dict[str, Any]) -> Dict[str, Any]:
    """``scene`` (a path or dict), ``tooth_module`` (mm; teeth cut on the design, rated when the
    scene has a ``[material]``), the rest :func:`ncgear.design`'s arguments."""
    p = dict(p)
    scene = p.pop("scene")
    tooth_module = p.pop("tooth_module", None)
    d = ncgear.design(p.pop("points"), **p)
    return {**design_figures(d), **_loads_figures(d, scene, tooth_module)}


def _loads_figures(d: ncgear.Design, scene: Any, tooth_module: Optional[float]) -> Dict[str, Any]:
    """The loads' figures (:data:`LOADS_FIGURES` after the design's) of design ``d`` in ``scene``,
    on its teeth of ``tooth_module`` (mm) when given."""
    rotor: Any = d if tooth_module is None else ncgear.teeth(d, float(tooth_module))
    r = ncgear.loads(rotor, scene)
    s = r.summary
    return {
        "carrier_torque_peak_Nm": float(s.carrier_torque_peak_Nm),
        "carrier_torque_rms_Nm": float(s.carrier_torque_rms_Nm),
        "mean_power_W": float(s.mean_power_W),
        "S_H_min": float(s.min_S_H.value) if s.min_S_H is not None else None,
        "S_F_min": float(s.min_S_F.value) if s.min_S_F is not None else None,
        "life_h": float(s.life_h) if s.life_h is not None else None,
        "loads_passed": bool(r.passed),
    }


JOBS: Dict[str, Callable[[Dict[str, Any]], Dict[str, Any]]] = {
    "design": _design, "synthesize": _synthesize, "tradeoff": _tradeoff, "loads": _loads,
}


def check_job(job: str) -> None:
    """Raises :class:`ncgear.NcgearError` unless ``job`` names a job."""
    if job not in JOBS:
        names = ", ".join(repr(j) for j in JOBS)
        raise ncgear.NcgearError(f"job={job!r}: expected one of {names}")


def _message(e: BaseException) -> str:
    if isinstance(e, ncgear.NcgearError):
        return str(e)
    if isinstance(e, TypeError) and "unexpected keyword argument" in str(e):
        return f"TypeError: {e} (a point's keys are the job's keyword arguments)"
    return f"{type(e).__name__}: {e}"


def evaluate(job: str, params: Mapping[str, Any]) -> Dict[str, Any]:
    """One point: ``job`` on the keyword arguments ``params``. The row: the job's figures
    (:data:`FIGURES`), ``time_s`` (wall-clock seconds of the call) and ``error`` (``None``, or the
    message of the point's failure, its figures then ``None``)."""
    check_job(job)
    start = time.perf_counter()
    row: Dict[str, Any] = {name: None for name in FIGURES[job]}
    try:
        if job != "synthesize" and "points" not in params:
            raise ncgear.NcgearError("points: missing (the target: an (N, 2) array, mm, or a file)")
        row.update(JOBS[job](dict(params)))
        row["error"] = None
    except Exception as e:  # a failing point is a row, never the end of the study
        row["error"] = _message(e)
    row["time_s"] = time.perf_counter() - start
    return row


def serial(job: str, points: List[Mapping[str, Any]]) -> List[Dict[str, Any]]:
    """The plain loop: :func:`evaluate` on each point in order, in this process."""
    return [evaluate(job, p) for p in points]
