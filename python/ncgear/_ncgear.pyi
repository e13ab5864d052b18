"""Type stub of the compiled half of ncgear (python/src/lib.rs); checked by mypy.stubtest."""
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt
from typing_extensions import final

__all__ = [
    "DEFAULT_L1_MM", "DEFAULT_L3_MM", "DesignHandle", "NcgearError", "PairHandle", "Report",
    "TrainHandle", "__version__", "compare", "design", "design_sized", "dynamics", "dynamics_file", "forward_for_spacing", "loads", "loads_file", "pair",
    "read_trajectory", "redesign",
    "set_max_memory_gb", "simulate", "spec_box", "synthesize", "teeth", "tolerance", "tradeoff",
]
__version__: str
DEFAULT_L1_MM: Tuple[float, float]
DEFAULT_L3_MM: Tuple[float, float]

class NcgearError(ValueError): ...

@final
class Report:
    def tree(self) -> Any: ...
    def json(self) -> str: ...

@final
class DesignHandle:
    def report(self) -> Report: ...
    def deviations(self) -> npt.NDArray[np.float64]: ...

@final
class TrainHandle:
    def report(self) -> Report: ...
    def verdict(self) -> Report: ...
    def outlines(self) -> Dict[str, npt.NDArray[np.float64]]: ...
    def placements(self) -> List[Tuple[str, str, Tuple[float, float], float]]: ...
    def write_step(self, dir: str, face_width: Optional[float], bore: float) -> List[str]: ...
    def write_sheets(self, dir: str, kind: str, version: str) -> List[str]: ...

@final
class PairHandle:
    def report(self) -> Report: ...
    def outlines(self) -> Dict[str, npt.NDArray[np.float64]]: ...
    def placements(self) -> List[Tuple[str, str, Tuple[float, float], float]]: ...
    def write_step(self, dir: str, face_width: Optional[float], bore: float) -> List[str]: ...
    def write_sheets(self, dir: str, kind: str, version: str) -> List[str]: ...

def read_trajectory(
    path: str, layer: Optional[str], id: Optional[str], units: Optional[str]
) -> npt.NDArray[np.float64]: ...
def design(
    points: Optional[npt.NDArray[np.float64]], path: Optional[str], options: Dict[str, Any]
) -> DesignHandle: ...
def design_sized(
    points: Optional[npt.NDArray[np.float64]],
    path: Optional[str],
    options: Dict[str, Any],
    scene: str,
    text: Optional[str],
) -> DesignHandle: ...
def teeth(
    design: DesignHandle,
    module: float,
    tooth_policy: str,
    teeth: Optional[int],
    wire_edm: bool,
    tooth: Dict[str, Any],
) -> TrainHandle: ...
def pair(
    law: str,
    kind: str,
    teeth: Optional[int],
    module: float,
    cycle_advance_deg: float,
    drive_deg: Optional[Tuple[float, float]],
    tooth: Dict[str, Any],
) -> PairHandle: ...
def simulate(
    design: DesignHandle,
    train: Optional[TrainHandle],
    rpm: float,
    forward_mm_s: float,
    depth_mm: float,
    levels_mm: Tuple[Optional[float], Optional[float]],
) -> Report: ...
def forward_for_spacing(spacing_mm: float, rpm: float) -> float: ...
def tolerance(path: str, samples: int, seed: int, starts: int) -> Report: ...
def loads(
    design: DesignHandle, train: Optional[TrainHandle], scene: str, text: Optional[str]
) -> Report: ...
def loads_file(path: str) -> Report: ...
def dynamics(
    design: DesignHandle,
    train: Optional[TrainHandle],
    scene: str,
    text: Optional[str],
    sweep_rpm: Optional[List[float]],
) -> Report: ...
def compare(
    track: str,
    design: Optional[DesignHandle],
    design_path: Optional[str],
    args: str,
    dynamics: Optional[str],
) -> Tuple[Report, npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64], List[bool]]: ...
def dynamics_file(path: str, sweep_rpm: Optional[List[float]]) -> Report: ...
def set_max_memory_gb(gb: float) -> None: ...
def synthesize(
    spec: str,
    text: Optional[str],
    options: Dict[str, Any],
    l1_mm: Optional[Tuple[float, float]],
    l3_mm: Optional[Tuple[float, float]],
) -> Tuple[Report, DesignHandle]: ...
def spec_box(
    spec: str, text: Optional[str]
) -> Tuple[Tuple[float, float], Tuple[float, float]]: ...
def tradeoff(
    points: Optional[npt.NDArray[np.float64]], path: Optional[str], center: Tuple[float, float]
) -> Report: ...
def redesign(
    points: Optional[npt.NDArray[np.float64]],
    path: Optional[str],
    start: Optional[DesignHandle],
    start_json: Optional[str],
    options: Dict[str, Any],
) -> DesignHandle: ...
