"""Shared fixtures: the repository, the CLI binary, the G1 design and train (computed once), and
the check that a typed report holds its JSON."""
import dataclasses
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import ncgear
from ncgear import reports

ROOT = pathlib.Path(__file__).resolve().parents[2]
G1 = ROOT / "assets" / "trajectories" / "g1_ellipse.csv"


def cli(*args, check=True):
    """Runs the CLI (``NCGEAR_BIN`` or target/release/ncgear)."""
    exe = os.environ.get("NCGEAR_BIN", str(ROOT / "target" / "release" / "ncgear"))
    p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
    if check:
        assert p.returncode == 0, p.stderr
    return p


def _same(value, raw, path="report"):
    """Asserts the typed ``value`` holds exactly the JSON ``raw``: every key a field (recursively),
    every number equal and of its JSON type, number lists as read-only float64 arrays."""
    if dataclasses.is_dataclass(value):
        keys = {reports.json_key(f): f.name for f in dataclasses.fields(value)}
        assert set(raw) <= set(keys), f"{path}: keys without a field {set(raw) - set(keys)}"
        for key, name in keys.items():
            if key in raw:
                _same(getattr(value, name), raw[key], f"{path}.{key}")
    elif isinstance(value, np.ndarray):
        assert value.dtype == np.float64 and not value.flags.writeable, path
        assert np.array_equal(value, np.asarray(raw, dtype=float).reshape(value.shape)), path
    elif isinstance(value, tuple):
        assert len(value) == len(raw), path
        for i, (v, r) in enumerate(zip(value, raw)):
            _same(v, r, f"{path}[{i}]")
    elif isinstance(value, dict):
        assert set(value) == set(raw), path
        for k in value:
            _same(value[k], raw[k], f"{path}.{k}")
    elif raw is None and isinstance(value, float):
        assert math.isinf(value), path  # JSON writes an unbounded number as null
    else:
        assert value == raw and type(value) is type(raw), path


@pytest.fixture(scope="session")
def g1():
    return ncgear.design(G1)


@pytest.fixture(scope="session")
def g1_train(g1):
    return ncgear.teeth(g1, module=2.0)


@pytest.fixture(scope="session")
def out(tmp_path_factory):
    return tmp_path_factory.mktemp("ncgear")
