"""How a report class of :mod:`ncgear.reports` is read from its JSON (hand-written; the classes
themselves are generated from ``docs/schemas/`` by ``scripts/gen_reports.py``).

:func:`build` makes a frozen dataclass from a JSON object, field by field by annotation: a nested
class from its object, ``Tuple[X, ...]`` and fixed tuples from arrays, ``Dict[str, X]`` from a
map, a numpy array (``Points``, ``Vectors``, ``Numbers``) as a read-only float64 array. A key
missing from the object (one the library leaves out when it does not apply) reads as ``None``,
empty or ``math.inf`` by type; a ``float`` JSON writes as ``null`` (it is not finite: an
unbounded check value, an unlimited life) reads as ``math.inf``, and so does an ``Optional``
number marked ``null_is_inf`` (a key left out when absent, so a ``null`` is a number that is not
finite). A field's JSON key is its name, or its ``key`` metadata (``passed`` ↔ ``pass``).
"""
from __future__ import annotations

import dataclasses
import math
import typing
from typing import Any, Dict, Union

import numpy as np
import numpy.typing as npt

__all__ = ["Numbers", "Points", "Vectors", "build", "json_key"]

Points = npt.NDArray[np.float64]
"""Read-only float64 array of shape (N, 2): points (or vectors) ``[x, y]``, mm where the key
says so (N for a force)."""
Numbers = npt.NDArray[np.float64]
"""Read-only 1-D float64 array."""
Vectors = npt.NDArray[np.float64]
"""Read-only 2-D float64 array (N, k): k values per row (``[K, mm]`` rows, an interval
``[from, to]``, a table row ``[travel_deg, Fx, Fy]``)."""

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
        return {k: _value(args[1], x) for k, x in ({} if v is None else v).items()}
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
