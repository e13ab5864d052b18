"""The study cache: one small JSON file per evaluated point, named by a content hash of the job,
the point's parameters (canonical JSON; a parameter naming an existing file adds that file's
bytes) and the ncgear version, written atomically (a temporary file renamed)."""
from __future__ import annotations

import hashlib
import json
import math
import os
import tempfile
from typing import Any, Dict, Mapping, Optional

import numpy as np


def canonical(v: Any) -> Any:
    """``v`` as plain JSON values: arrays and tuples as lists, numpy scalars as numbers, paths as
    text, dict keys sorted by ``json.dumps``; a non-finite float as its text (``"inf"``)."""
    if isinstance(v, np.ndarray):
        return canonical(v.tolist())
    if isinstance(v, np.generic):
        return canonical(v.item())
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    if isinstance(v, Mapping):
        return {str(k): canonical(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [canonical(x) for x in v]
    if isinstance(v, float) and not math.isfinite(v):
        return repr(v)
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    raise TypeError(f"a {type(v).__name__} is not a study parameter (use numbers, text, lists)")


def _file_digests(v: Any, out: Dict[str, str]) -> None:
    """The sha256 of each existing file a text parameter names, into ``out``."""
    if isinstance(v, str) and len(v) < 4096 and os.path.isfile(v):
        with open(v, "rb") as f:
            out[v] = hashlib.sha256(f.read()).hexdigest()
    elif isinstance(v, dict):
        for x in v.values():
            _file_digests(x, out)
    elif isinstance(v, list):
        for x in v:
            _file_digests(x, out)


def point_key(job: str, params: Mapping[str, Any], version: str) -> str:
    """The content hash (sha256 hex) of one point of ``job``."""
    try:
        plain = canonical(dict(params))
    except TypeError as e:
        import ncgear

        raise ncgear.NcgearError(f"points: {e}") from None
    files: Dict[str, str] = {}
    _file_digests(plain, files)
    text = json.dumps(
        {"job": job, "params": plain, "files": files, "ncgear": version},
        sort_keys=True, separators=(",", ":"), allow_nan=False,
    )
    return hashlib.sha256(text.encode()).hexdigest()


def _plain_row(row: Mapping[str, Any]) -> Dict[str, Any]:
    return {k: canonical(v) for k, v in row.items()}


def _row_of(stored: Dict[str, Any]) -> Dict[str, Any]:
    return {
        k: float(v) if isinstance(v, str) and v in ("inf", "-inf", "nan") else v
        for k, v in stored.items()
    }


class Cache:
    """A directory of rows: ``<dir>/<key[:2]>/<key>.json`` holding the job, parameters, ncgear
    version and row of one point."""

    def __init__(self, directory: "str | os.PathLike[str]", version: str) -> None:
        self.directory = os.fspath(directory)
        self.version = version

    def _path(self, key: str) -> str:
        return os.path.join(self.directory, key[:2], key + ".json")

    def get(self, key: str) -> Optional[Dict[str, Any]]:
        """The stored row of ``key``, or ``None`` (absent or unreadable: evaluated again)."""
        try:
            with open(self._path(key), encoding="utf-8") as f:
                return _row_of(json.load(f)["row"])
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def put(self, key: str, job: str, params: Mapping[str, Any], row: Mapping[str, Any]) -> None:
        """Stores ``row`` atomically (a reader sees the whole file or none)."""
        path = self._path(key)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        text = json.dumps(
            {"job": job, "params": canonical(dict(params)), "ncgear": self.version,
             "row": _plain_row(row)},
            sort_keys=True, allow_nan=False,
        )
        fd, tmp = tempfile.mkstemp(dir=os.path.dirname(path), suffix=".tmp")
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
            os.replace(tmp, path)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise
