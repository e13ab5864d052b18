"""A Pareto front on Dask: NSGA-II (pymoo) trades the gears' path deviation against their largest
pressure angle over two design knobs — the pressure-angle limit the design is held to (degrees)
and the smallest concave radius of curvature it may have (mm) — with the intermediate axis free
to leave the carrier line. Each generation is one ncgear.study.run on a local Dask cluster, its
points cached (a re-run of the same generations evaluates nothing).

    python examples/python/pareto.py [OUT_DIR] [--pop 12] [--gen 6] [--workers N] [--seed 1]

Writes OUT_DIR/front.parquet (the non-dominated designs that pass their checks: knobs and
figures, mm and degrees) and OUT_DIR/front.png (every design evaluated, the front drawn over
them). Needs the study extra: pip install "ncgear[study]".
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from pymoo.algorithms.moo.nsga2 import NSGA2  # noqa: E402
from pymoo.optimize import minimize  # noqa: E402

from ncgear import study  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
OBJECTIVES = ["deviation_max_mm", "pressure_angle_max_deg"]


def main() -> None:
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("out", nargs="?", default="out/pareto", help="output directory")
    a.add_argument("--pop", type=int, default=12, help="population size (default 12)")
    a.add_argument("--gen", type=int, default=6, help="generations (default 6)")
    a.add_argument("--workers", type=int, default=None, help="local Dask workers (default: CPUs)")
    a.add_argument("--seed", type=int, default=1, help="NSGA-II seed (default 1)")
    a.add_argument("--trajectory", default=str(ROOT / "assets" / "trajectories" / "designer_kidney.csv"),
                   help="target trajectory file, mm (default the bundled kidney)")
    args = a.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    from dask.distributed import Client

    with study.local_cluster(args.workers) as cluster, Client(cluster) as client:
        problem = study.Problem(
            "design",
            {"max_pressure_angle": (35.0, 55.0), "min_concave_radius": (4.0, 20.0)},
            OBJECTIVES,
            base={"points": args.trajectory, "idler_offset": "free", "alternatives": False},
            client=client, cache=out / "cache",
        )
        res = minimize(problem, NSGA2(pop_size=args.pop), ("n_gen", args.gen), seed=args.seed,
                       verbose=False)

    every = pd.concat(problem.history, ignore_index=True)
    every = every[every["error"].isna() & every["passed"].astype(bool)]
    X = np.atleast_2d(res.X) if res.X is not None else np.empty((0, 2))
    knobs = problem.names
    front = every.drop_duplicates(subset=knobs).merge(
        pd.DataFrame(X, columns=knobs), on=knobs, how="inner"
    ).sort_values(OBJECTIVES[0], ignore_index=True)
    front.to_parquet(out / "front.parquet")

    fig, ax = plt.subplots(figsize=(6, 4.5), dpi=120)
    ax.scatter(every[OBJECTIVES[0]], every[OBJECTIVES[1]], s=12, c="0.7", label="designs evaluated")
    ax.plot(front[OBJECTIVES[0]], front[OBJECTIVES[1]], "o-", c="C3", label="Pareto front")
    ax.set_xlabel("largest path deviation, mm")
    ax.set_ylabel("largest pressure angle, degrees")
    ax.set_title(f"NSGA-II, {args.pop} × {args.gen} designs, {pathlib.Path(args.trajectory).name}")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "front.png")
    print(f"pareto: {len(front)} designs on the front; wrote {out / 'front.parquet'}, {out / 'front.png'}")


if __name__ == "__main__":
    main()
