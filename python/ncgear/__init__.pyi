"""Type stub of the ncgear package (lengths mm, angles degrees where the CLI takes degrees).
Checked against the module by ``python -m mypy.stubtest ncgear`` (scripts/check_python.sh)."""
import os
from dataclasses import dataclass
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt
from typing_extensions import TypedDict, Unpack

from . import reports
from .reports import (
    CompareReport, DesignReport, Features, LoadsReport, PairReport, Points, RotorReport, SynthesisReport,
    ToleranceReport, TrainTeethReport, Verdict,
)

__version__: str
__all__ = [
    "NcgearError", "Design", "Train", "Pair", "Placement", "Loads", "design", "teeth", "pair",
    "simulate", "tolerance", "loads", "loads_file", "write_step", "write_dxf", "write_svg",
    "set_max_memory_gb", "Synthesis", "TradeOff", "synthesize", "tradeoff", "redesign",
    "read_trajectory", "Dynamics", "SweepRow", "dynamics", "dynamics_file", "Comparison", "compare",
]

PathLike = Union[str, os.PathLike[str]]

class NcgearError(ValueError): ...

class _Json:
    _report: Any
    def to_dict(self) -> Dict[str, Any]: ...
    def json(self) -> str: ...

class _Raw(_Json):
    @property
    def passed(self) -> bool: ...

@dataclass(frozen=True)
class Placement:
    part: str
    center_mm: Tuple[float, float]
    angle_rad: float

@dataclass(frozen=True, eq=False)
class Design(_Raw, DesignReport):
    deviations: npt.NDArray[np.float64]
    _handle: Any
    _report: Any

@dataclass(frozen=True, eq=False)
class Train(_Raw, TrainTeethReport):
    outlines: Dict[str, Points]
    placements: Dict[str, Placement]
    verdict: Verdict
    design: Design
    _handle: Any
    _report: Any

@dataclass(frozen=True, eq=False)
class Pair(_Raw, PairReport):
    outlines: Dict[str, Points]
    placements: Dict[str, Placement]
    _handle: Any
    _report: Any

@dataclass(frozen=True, eq=False)
class Loads(_Raw, LoadsReport):
    _report: Any

@dataclass(frozen=True, eq=False)
class Dynamics(_Json, RotorReport):
    _report: Any

@dataclass(frozen=True, eq=False)
class Comparison(_Json, CompareReport):
    frame_carrier_rad: npt.NDArray[np.float64]
    frame_tip_mm: Points
    frame_residual_mm: Points
    frame_outlier: npt.NDArray[np.bool_]
    _report: Any

@dataclass(frozen=True)
class SweepRow:
    carrier_rpm: float
    dynamic_factor: Tuple[float, float]
    impacts_per_turn: int
    max_impact_speed_m_s: float
    max_tip_deviation_mm: float
    turns: int
    settled: bool

def read_trajectory(
    path: PathLike,
    *,
    layer: Optional[str] = ...,
    id: Optional[str] = ...,
    units: Optional[Literal["mm", "cm", "m", "in", "px"]] = ...,
) -> npt.NDArray[np.float64]: ...
def design(
    points: Union[PathLike, npt.ArrayLike],
    *,
    center: Tuple[float, float] = ...,
    order: Optional[int] = ...,
    sense: Literal["auto", "ccw", "cw"] = ...,
    tol_mm: float = ...,
    refine: Literal["auto", "on", "off"] = ...,
    refine_order: int = ...,
    harmonics: Sequence[Tuple[float, float]] = ...,
    route: Literal["ac", "bd"] = ...,
    w1: float = ...,
    k_max: int = ...,
    grid: int = ...,
    dense: int = ...,
    samples: int = ...,
    ratio_bounds: Tuple[float, float] = ...,
    fit: bool = ...,
    limits: bool = ...,
    max_pressure_angle: float = ...,
    min_concave_radius: Optional[float] = ...,
    min_convex_radius: Optional[float] = ...,
    convexity: bool = ...,
    smooth: Optional[int] = ...,
    module: Union[float, Literal["auto"], None] = ...,
    idler_offset: Literal["auto", "collinear", "free"] = ...,
    alternatives: bool = ...,
    loads: Union[PathLike, Mapping[str, Any], None] = ...,
) -> Design: ...
def teeth(
    design: Design,
    module: float,
    *,
    tooth_policy: Optional[
        Literal["design", "scale-up", "nearest", "scale-down", "ratio-amplitude", "adjust-module"]
    ] = ...,
    teeth: Optional[int] = ...,
    wire_edm: bool = ...,
    verify_steps: int = ...,
    pressure_angle: float = ...,
    addendum: float = ...,
    clearance: float = ...,
    fillet: float = ...,
    backlash: Optional[float] = ...,
    chord_tol: Optional[float] = ...,
    cutter_teeth: Optional[int] = ...,
    refuse_undercut: bool = ...,
) -> Train: ...
def pair(
    law: str,
    *,
    kind: Literal["motion", "centrode", "csv"] = ...,
    teeth: Optional[int] = ...,
    module: float = ...,
    cycle_advance: float = ...,
    drive: Optional[Tuple[float, float]] = ...,
    verify_steps: int = ...,
    pressure_angle: float = ...,
    addendum: float = ...,
    clearance: float = ...,
    fillet: float = ...,
    backlash: Optional[float] = ...,
    chord_tol: Optional[float] = ...,
    cutter_teeth: Optional[int] = ...,
    refuse_undercut: bool = ...,
) -> Pair: ...
def simulate(
    design: Union[Design, Train],
    *,
    rpm: float = ...,
    spacing: Optional[float] = ...,
    speed: Optional[float] = ...,
    depth: float = ...,
    take_level: Optional[float] = ...,
    plant_level: Optional[float] = ...,
) -> Features: ...
def tolerance(errors: PathLike, *, samples: int = ..., seed: int = ..., starts: int = ...) -> ToleranceReport: ...
def loads(design: Union[Design, Train], scene: Union[PathLike, Mapping[str, Any]]) -> Loads: ...
def loads_file(scene: PathLike) -> Loads: ...
def compare(
    track: PathLike,
    design: Union[Design, Train, PathLike],
    *,
    dynamics: Optional[PathLike] = ...,
    **options: Any,
) -> Comparison: ...
@overload
def dynamics(
    design: Union[Design, Train], scene: Union[PathLike, Mapping[str, Any]], *, sweep_rpm: None = ...
) -> Dynamics: ...
@overload
def dynamics(
    design: Union[Design, Train], scene: Union[PathLike, Mapping[str, Any]], *, sweep_rpm: Sequence[float]
) -> List[SweepRow]: ...
@overload
def dynamics_file(scene: PathLike, *, sweep_rpm: None = ...) -> Dynamics: ...
@overload
def dynamics_file(scene: PathLike, *, sweep_rpm: Sequence[float]) -> List[SweepRow]: ...
@dataclass(frozen=True, eq=False)
class Synthesis(_Json, SynthesisReport):
    design: Design
    _report: Any
    @property
    def passed(self) -> bool: ...

@dataclass(frozen=True, eq=False)
class TradeOff(_Json, reports.TradeOff):
    _report: Any

class _DesignOptions(TypedDict, total=False):
    """:func:`design`'s keyword arguments, taken by :func:`redesign` and :func:`synthesize`."""
    center: Tuple[float, float]
    order: Optional[int]
    sense: Literal["auto", "ccw", "cw"]
    tol_mm: float
    refine: Literal["auto", "on", "off"]
    refine_order: int
    harmonics: Sequence[Tuple[float, float]]
    route: Literal["ac", "bd"]
    w1: float
    k_max: int
    grid: int
    dense: int
    samples: int
    ratio_bounds: Tuple[float, float]
    fit: bool
    limits: bool
    max_pressure_angle: float
    min_concave_radius: Optional[float]
    min_convex_radius: Optional[float]
    convexity: bool
    smooth: Optional[int]
    module: Optional[float]
    idler_offset: Literal["auto", "collinear", "free"]
    alternatives: bool

def synthesize(
    spec: Union[PathLike, Mapping[str, Any]],
    *,
    l1_mm: Optional[Tuple[float, float]] = ...,
    l3_mm: Optional[Tuple[float, float]] = ...,
    **options: Unpack[_DesignOptions],
) -> Synthesis: ...
def tradeoff(
    points: Union[PathLike, npt.ArrayLike], *, center: Tuple[float, float] = ...
) -> TradeOff: ...
def redesign(
    points: Union[PathLike, npt.ArrayLike],
    start: Union[Design, PathLike],
    **options: Unpack[_DesignOptions],
) -> Design: ...
def write_step(
    obj: Union[Train, Pair], directory: PathLike, *, face_width: Optional[float] = ..., bore: float = ...
) -> List[str]: ...
def write_dxf(
    obj: Union[Train, Pair], directory: PathLike, *, version: Literal["r2010", "r12"] = ...
) -> List[str]: ...
def write_svg(obj: Union[Train, Pair], directory: PathLike) -> List[str]: ...
def set_max_memory_gb(gb: float) -> None: ...
