"""Type stub of the ncgear package (lengths mm, angles rad)."""
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
PathLike = Union[str, os.PathLike[str]]

class NcgearError(ValueError): ...

class Design:
    l1: float
    l3: float
    pitch_curves: Dict[str, npt.NDArray[np.float64]]
    report: Dict[str, Any]
    deviations: npt.NDArray[np.float64]
    @property
    def verdict(self) -> Dict[str, Any]: ...
    @property
    def passed(self) -> bool: ...

class Train:
    outlines: Dict[str, npt.NDArray[np.float64]]
    placements: Dict[str, Dict[str, Any]]
    report: Dict[str, Any]
    design: Design
    verdict: Dict[str, Any]
    @property
    def passed(self) -> bool: ...

class Pair:
    outlines: Dict[str, npt.NDArray[np.float64]]
    placements: Dict[str, Dict[str, Any]]
    report: Dict[str, Any]
    @property
    def verdict(self) -> Dict[str, Any]: ...
    @property
    def passed(self) -> bool: ...

def design(
    points: Union[PathLike, Sequence[Sequence[float]], npt.ArrayLike],
    center: Tuple[float, float] = ...,
    **options: Any,
) -> Design: ...
def teeth(
    design: Design,
    module: float,
    policy: Optional[str] = ...,
    teeth: Optional[int] = ...,
    backlash: Optional[float] = ...,
    chord_tol: Optional[float] = ...,
    verify_steps: int = ...,
) -> Train: ...
def pair(
    law: str,
    teeth: Optional[int] = ...,
    module: float = ...,
    kind: str = ...,
    verify_steps: int = ...,
    cycle_advance: float = ...,
    drive: Optional[Tuple[float, float]] = ...,
) -> Pair: ...
def simulate(
    design: Union[Design, Train],
    rpm: float = ...,
    spacing: Optional[float] = ...,
    forward_speed: Optional[float] = ...,
    depth: float = ...,
) -> Dict[str, Any]: ...
def tolerance(errors: PathLike, samples: int = ...) -> Dict[str, Any]: ...
def write_step(
    obj: Union[Train, Pair], directory: PathLike, face_width: Optional[float] = ..., bore: float = ...
) -> List[str]: ...
def write_dxf(obj: Union[Train, Pair], directory: PathLike) -> List[str]: ...
def write_svg(obj: Union[Train, Pair], directory: PathLike) -> List[str]: ...
