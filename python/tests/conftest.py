"""Shared fixtures: the repository, the CLI binary, the G1 design and train (computed once)."""
import os
import pathlib
import subprocess

import pytest

import ncgear

ROOT = pathlib.Path(__file__).resolve().parents[2]
G1 = ROOT / "assets" / "trajectories" / "g1_ellipse.csv"


def cli(*args, check=True):
    """Runs the CLI (``NCGEAR_BIN`` or target/release/ncgear)."""
    exe = os.environ.get("NCGEAR_BIN", str(ROOT / "target" / "release" / "ncgear"))
    p = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
    if check:
        assert p.returncode == 0, p.stderr
    return p


@pytest.fixture(scope="session")
def g1():
    return ncgear.design(G1)


@pytest.fixture(scope="session")
def g1_train(g1):
    return ncgear.teeth(g1, module=2.0)


@pytest.fixture(scope="session")
def out(tmp_path_factory):
    return tmp_path_factory.mktemp("ncgear")
