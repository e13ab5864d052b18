"""Design studies: one job of the package over many points, on a Dask cluster, as a table.

::

    from ncgear import study
    pts = study.grid(points=["assets/trajectories/g1_ellipse.csv"], max_pressure_angle=[35, 40, 45])
    df = study.run("design", pts, cache="target/study-cache", out="study.parquet")

``run`` evaluates each point (a dict of the job's keyword arguments) on a
``dask.distributed.Client`` — the one given, or a local cluster of worker processes made for the
call and closed after it — and returns one row per point, in input order: the parameters, the
figures (:data:`ncgear.study.jobs.FIGURES`), ``time_s`` and ``error``. A point that fails is a row
whose ``error`` is its message. With ``cache`` each row is kept in a file named by a hash of the
job, the parameters and the ncgear version, so a re-run evaluates only what is missing.
:class:`Problem` (pymoo) evaluates a population through :func:`run`. Needs the ``study`` extra
(``pip install ncgear[study]``).
"""
from __future__ import annotations

import itertools
import os
import sys
import time
from typing import TYPE_CHECKING, Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

import ncgear

from .cache import Cache, canonical, point_key
from .jobs import FIGURES, check_job, evaluate, serial

__all__ = [
    "run", "grid", "sample", "evaluate", "serial", "Problem", "FIGURES", "table", "local_cluster",
]

if TYPE_CHECKING:
    from .moo import Problem as Problem

PathLike = Union[str, "os.PathLike[str]"]


def __getattr__(name: str) -> Any:
    if name == "Problem":  # pymoo is imported only when the adapter is used
        from .moo import Problem

        return Problem
    raise AttributeError(f"module 'ncgear.study' has no attribute {name!r}")


def grid(**axes: Sequence[Any]) -> List[Dict[str, Any]]:
    """The cartesian product of ``axes`` (each a non-empty list of values of one keyword
    argument), the last axis varying fastest: ``grid(a=[1, 2], b=[3, 4])`` is
    ``[{a: 1, b: 3}, {a: 1, b: 4}, {a: 2, b: 3}, {a: 2, b: 4}]``."""
    for name, values in axes.items():
        if isinstance(values, (str, bytes, os.PathLike)) or not hasattr(values, "__len__"):
            raise ncgear.NcgearError(f"{name}={values!r}: expected a list of values (one axis)")
        if len(values) == 0:
            raise ncgear.NcgearError(f"{name}: empty axis (give at least one value)")
    names = list(axes)
    return [dict(zip(names, combo)) for combo in itertools.product(*axes.values())]


def sample(n: int, *, seed: int, **ranges: Any) -> List[Dict[str, Any]]:
    """``n`` random points (numpy ``Generator`` seeded with ``seed``): a range ``(low, high)`` of
    floats draws uniformly in [low, high), of two ints an integer in [low, high]; a list draws
    one of its values; any other value is the same in every point. Axes are drawn in the order
    given, so the same call gives the same points."""
    if not (isinstance(n, (int, np.integer)) and n >= 0):
        raise ncgear.NcgearError(f"n={n!r}: expected a count of points (an int ≥ 0)")
    rng = np.random.default_rng(seed)
    columns: Dict[str, List[Any]] = {}
    for name, r in ranges.items():
        if isinstance(r, tuple) and len(r) == 2 and all(isinstance(v, (int, float)) for v in r):
            low, high = r
            if not low <= high:
                raise ncgear.NcgearError(f"{name}={r!r}: expected (low, high) with low ≤ high")
            if all(isinstance(v, int) and not isinstance(v, bool) for v in r):
                columns[name] = [int(v) for v in rng.integers(low, high, n, endpoint=True)]
            else:
                columns[name] = [float(v) for v in rng.uniform(low, high, n)]
        elif isinstance(r, list):
            if not r:
                raise ncgear.NcgearError(f"{name}: empty list of choices")
            columns[name] = [r[int(i)] for i in rng.integers(0, len(r), n)]
        else:
            columns[name] = [r] * n
    return [{name: columns[name][k] for name in ranges} for k in range(n)]


def _cell(v: Any) -> Any:
    """A parameter as a table cell: a scalar as itself, a path as text, else its JSON."""
    if v is None or isinstance(v, (bool, int, float, str, np.integer, np.floating)):
        return v.item() if isinstance(v, np.generic) else v
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    import json

    return json.dumps(canonical(v))


def table(points: Sequence[Mapping[str, Any]], rows: Sequence[Mapping[str, Any]], job: str) -> Any:
    """The study's ``pandas.DataFrame``: per point its parameters (union of the keys, in order of
    appearance; non-scalars as JSON text), then the job's figures, ``time_s`` and ``error``."""
    import pandas as pd  # type: ignore[import-untyped]

    names: List[str] = []
    for p in points:
        names.extend(k for k in p if k not in names)
    columns = names + [f for f in FIGURES[job] if f not in names] + ["time_s", "error"]
    records = [
        {**{k: _cell(p.get(k)) for k in names}, **{f: r.get(f) for f in columns[len(names):]}}
        for p, r in zip(points, rows)
    ]
    return pd.DataFrame.from_records(records, columns=columns)


def local_cluster(workers: Optional[int] = None, threads: Optional[int] = None) -> Any:
    """A ``LocalCluster`` of ``workers`` processes (default: one per CPU), each evaluating one
    point at a time, on loopback, without dashboard. ``threads``: the library's own thread pool
    (rayon) per process, the threads one design uses (``RAYON_NUM_THREADS``); default the CPUs
    shared out, ``max(1, cpus // workers)``, so that the processes share the CPUs instead of each
    taking all of them. A row does not depend on it (a design is the same number on any number
    of threads); only the time does (docs/studies.md, "Scaling")."""
    from dask.distributed import LocalCluster

    cpus = os.cpu_count() or 1
    n = workers if workers is not None else cpus
    if not (isinstance(n, int) and n >= 1):
        raise ncgear.NcgearError(f"workers={workers!r}: expected a number of processes ≥ 1")
    t = threads if threads is not None else max(1, cpus // n)
    if not (isinstance(t, int) and t >= 1):
        raise ncgear.NcgearError(f"threads={threads!r}: expected a number of threads ≥ 1")
    return LocalCluster(
        n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
        host="127.0.0.1", env={"RAYON_NUM_THREADS": str(t)},
    )


def _local_client(workers: Optional[int], threads: Optional[int]) -> Any:
    from dask.distributed import Client

    cluster = local_cluster(workers, threads)
    return Client(cluster)


def _on_cluster(client: Any, job: str, todo: Dict[str, Mapping[str, Any]], store: Optional[Cache],
                progress: bool) -> Dict[str, Dict[str, Any]]:
    """Evaluates ``todo`` (key → point) on ``client``; each row stored as soon as it arrives."""
    from dask.distributed import as_completed
    from dask.distributed import progress as bar

    futures = {
        client.submit(evaluate, job, dict(p), key=f"ncgear-{job}-{k}", pure=False): k
        for k, p in todo.items()
    }
    if progress and futures and sys.stdout.isatty():
        bar(list(futures))
    done: Dict[str, Dict[str, Any]] = {}
    for fut in as_completed(list(futures)):
        k = futures[fut]
        try:
            row = fut.result()
        except Exception as e:  # the task failed (e.g. its workers died too often): not cached
            done[k] = {"error": f"{type(e).__name__}: {e}", "time_s": None}
            continue
        done[k] = row  # a point's own error is a result, cached like any other
        if store is not None:
            store.put(k, job, todo[k], row)
    return done


def run(
    job: str,
    points: Sequence[Mapping[str, Any]],
    *,
    client: Any = None,
    cache: Optional[PathLike] = None,
    progress: bool = True,
    out: Optional[PathLike] = None,
    workers: Optional[int] = None,
    threads: Optional[int] = None,
) -> Any:
    """``job`` (``"design"``, ``"synthesize"``, ``"tradeoff"`` or ``"loads"``) on each of
    ``points`` (dicts of its keyword arguments; a job ``loads`` point takes ``scene`` and an
    optional ``tooth_module`` (mm) beside :func:`ncgear.design`'s), as a ``pandas.DataFrame`` of one
    row per point in input order (:func:`table`).

    ``client``: a ``dask.distributed.Client`` (``Client("tcp://host:8786")`` for a cluster);
    ``None`` starts :func:`local_cluster` of ``workers`` processes (default: one per CPU) of
    ``threads`` threads per design (default: CPUs ÷ workers) and closes it after. ``cache``: a directory of one small JSON file per evaluated point; points already
    there are not evaluated again. ``progress``: Dask's progress bar when stdout is a terminal.
    ``out``: also write the table as Parquet there. ``df.attrs["evaluated"]`` is how many
    points were evaluated (the rest came from the cache), ``df.attrs["wall_s"]`` the seconds.
    """
    check_job(job)
    points = [dict(p) for p in points]
    for i, p in enumerate(points):
        if not all(isinstance(k, str) for k in p):
            raise ncgear.NcgearError(f"points[{i}]: keys must be argument names (str)")
    start = time.perf_counter()
    version = str(ncgear.__version__)
    keys = [point_key(job, p, version) for p in points]
    store = Cache(cache, version) if cache is not None else None
    rows: Dict[str, Dict[str, Any]] = {}
    if store is not None:
        for k in set(keys):
            row = store.get(k)
            if row is not None:
                rows[k] = row
    todo = {k: p for k, p in zip(keys, points) if k not in rows}
    if todo:
        own = client is None
        c = _local_client(workers, threads) if own else client
        try:
            rows.update(_on_cluster(c, job, todo, store, progress))
        finally:
            if own:
                cluster = c.cluster
                c.close()
                cluster.close()
    df = table(points, [rows[k] for k in keys], job)
    df.attrs["evaluated"] = len(todo)
    df.attrs["wall_s"] = time.perf_counter() - start
    if out is not None:
        os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
        df.to_parquet(out)
    return df
