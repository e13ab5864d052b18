"""A pymoo ``Problem`` over a study job: each generation's population evaluated as one
:func:`ncgear.study.run` (so on the Dask cluster, through the cache), objectives and constraints
read from the table's columns."""
from __future__ import annotations

from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from pymoo.core.problem import Problem as _PymooProblem  # type: ignore[import-untyped]

import ncgear

from . import run as _run
from .jobs import FIGURES, check_job

#: The objective of a point that failed (and its constraints 1): far worse than any design.
PENALTY = 1.0e6


class Problem(_PymooProblem):  # type: ignore[misc]
    """Minimise ``objectives`` (figure columns of ``job``; ``"-name"`` maximises ``name``) over
    ``variables``: ``{argument: (low, high)}`` (a float; units those of the argument) or
    ``{argument: [choice, ...]}`` (one of the values given: a module, an idler layout; searched as
    an index), the other arguments fixed by ``base``. Constraints, each g ≤ 0: the verdict (``require_pass``: g = 0 when
    the design passes its checks and gear limits, else 1), ``minimum`` ``{column: value}``
    (g = value − column, e.g. ``{"S_H_min": 1.0}`` for a safety factor) and ``maximum``
    (g = column − value). A point that fails gets :data:`PENALTY` objectives and g = 1.
    ``client``, ``cache``, ``workers``: as :func:`ncgear.study.run`. ``self.history`` holds
    every evaluated table."""

    def __init__(
        self,
        job: str,
        variables: Mapping[str, Union[Tuple[float, float], list]],
        objectives: Sequence[str],
        *,
        base: Optional[Mapping[str, Any]] = None,
        require_pass: bool = True,
        minimum: Optional[Mapping[str, float]] = None,
        maximum: Optional[Mapping[str, float]] = None,
        client: Any = None,
        cache: Any = None,
        workers: Optional[int] = None,
    ) -> None:
        check_job(job)
        if not variables:
            raise ncgear.NcgearError("variables: give at least one {argument: (low, high)}")
        self.choices: Dict[str, list] = {}
        box: Dict[str, Tuple[float, float]] = {}
        for name, r in variables.items():
            if isinstance(r, list):
                if not r:
                    raise ncgear.NcgearError(f"variables[{name!r}]: give at least one choice")
                self.choices[name] = list(r)
                box[name] = (0.0, float(len(r)))
            elif len(r) == 2 and float(r[0]) < float(r[1]):
                box[name] = (float(r[0]), float(r[1]))
            else:
                raise ncgear.NcgearError(
                    f"variables[{name!r}]={r!r}: expected (low, high) with low < high, or a list "
                    "of choices"
                )
        columns = set(FIGURES[job])
        bounds = {**(minimum or {}), **(maximum or {})}
        for name in [o.lstrip("-") for o in objectives] + list(bounds):
            if name not in columns:
                raise ncgear.NcgearError(
                    f"{name!r}: not a figure of job {job!r} (one of {', '.join(FIGURES[job])})"
                )
        if not objectives:
            raise ncgear.NcgearError("objectives: give at least one figure to minimise")
        self.job, self.names = job, list(variables)
        self.objectives = list(objectives)
        self.base: Dict[str, Any] = dict(base or {})
        self.require_pass = require_pass
        self.minimum, self.maximum = dict(minimum or {}), dict(maximum or {})
        self.client, self.cache, self.workers = client, cache, workers
        self.history: list = []
        n_constr = int(require_pass) + len(self.minimum) + len(self.maximum)
        super().__init__(
            n_var=len(self.names), n_obj=len(self.objectives), n_ieq_constr=n_constr,
            xl=np.array([box[n][0] for n in self.names]),
            xu=np.array([box[n][1] for n in self.names]),
        )

    def points(self, X: np.ndarray) -> list:
        """The study points of a population ``X`` (one row per individual): a float variable as
        itself, a choice's index in [0, n) as its value."""
        return [{**self.base, **{n: self._value(n, v) for n, v in zip(self.names, x)}}
                for x in np.atleast_2d(X)]

    def _value(self, name: str, v: float) -> Any:
        c = self.choices.get(name)
        if c is None:
            return float(v)
        return c[min(max(int(np.floor(v)), 0), len(c) - 1)]

    def _evaluate(self, X: np.ndarray, out: Dict[str, Any], *args: Any, **kwargs: Any) -> None:
        df = _run(self.job, self.points(X), client=self.client, cache=self.cache,
                  progress=False, workers=self.workers)
        self.history.append(df)
        failed = df["error"].notna().to_numpy()
        F = np.empty((len(df), len(self.objectives)))
        for j, o in enumerate(self.objectives):
            sign = -1.0 if o.startswith("-") else 1.0
            F[:, j] = sign * df[o.lstrip("-")].astype(float).to_numpy()
        F[failed | ~np.isfinite(F).all(axis=1)] = PENALTY
        out["F"] = F
        if self.n_ieq_constr:
            out["G"] = self.constraints(df)

    def constraints(self, df: Any) -> np.ndarray:
        """The constraint values g (≤ 0 when met) of a study table's rows, one column per
        constraint in the order: the verdict, ``minimum``, ``maximum``; a failed row, or one
        with a figure missing, has g = 1 throughout."""
        G = []
        if self.require_pass:
            G.append(np.where(df["passed"].fillna(False).astype(bool), 0.0, 1.0))
        for c, v in self.minimum.items():
            G.append(v - df[c].astype(float).to_numpy())
        for c, v in self.maximum.items():
            G.append(df[c].astype(float).to_numpy() - v)
        g = np.column_stack(G) if G else np.zeros((len(df), 0))
        failed = df["error"].notna().to_numpy()
        g[failed | ~np.isfinite(g).all(axis=1)] = 1.0
        return g

    def feasible(self, df: Any) -> Any:
        """The rows of a study table that meet every constraint (see :meth:`constraints`)."""
        return df[(self.constraints(df) <= 0.0).all(axis=1)]
