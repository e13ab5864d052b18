"""A Pareto front on Dask: NSGA-II (pymoo) chooses planting arms for the bundled rice target bands
(assets/synthesis/rice_targets.toml: taking and pushing angles, trajectory height, hole width)
over the arm box, the module and the idler layout, trading the gears' quality (their largest
pressure angle) against the peak torque the carrier must deliver and the path deviation of the
toothed train. Each design is synthesised from the bands (``ncgear.synthesize``), its gears made
for the module, and its loads computed in the bundled rotor scene (assets/loads/rotor.toml:
300 r/min, two arms, the needle's planting forces, cast-iron gears rated by ISO 6336).

Variables: the arm box's upper edges ``l1_max_mm`` (60…160 mm) and ``l3_max_mm`` (120…320 mm),
the ``module`` (1.5, 2, 2.5 or 3 mm) and the ``idler_offset`` ("auto", "collinear", "free").
Constraints (g ≤ 0): the design passes its checks and gear limits, every target band is met,
S_H ≥ 1.0 and S_F ≥ 1.4 (the scene's targets). Each generation is one ncgear.study.run on a
local Dask cluster, its points cached (a re-run of the same generations evaluates nothing).

    python examples/python/pareto.py [OUT_DIR] [--pop 12] [--gen 6] [--workers N] [--seed 1]
                                     [--modules 1.5 2 2.5 3]

Writes OUT_DIR/front.parquet (the non-dominated feasible designs: variables and figures, mm,
degrees, N·m), OUT_DIR/evaluated.parquet (every design evaluated) and OUT_DIR/front.png (peak
carrier torque against pressure angle, every feasible design evaluated, the front drawn over
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
OBJECTIVES = ["pressure_angle_max_deg", "carrier_torque_peak_Nm", "deviations_max_mm"]
ARM_BOX = {"l1_max_mm": (60.0, 160.0), "l3_max_mm": (120.0, 320.0)}
MODULES = [1.5, 2.0, 2.5, 3.0]
IDLER = ["auto", "collinear", "free"]
#: The scene's safety targets (assets/loads/rotor.toml [rating]).
SAFETY = {"S_H_min": 1.0, "S_F_min": 1.4}


def main() -> None:
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("out", nargs="?", default="out/pareto", help="output directory")
    a.add_argument("--pop", type=int, default=12, help="population size (default 12)")
    a.add_argument("--gen", type=int, default=6, help="generations (default 6)")
    a.add_argument("--workers", type=int, default=None, help="local Dask workers (default: CPUs)")
    a.add_argument("--seed", type=int, default=1, help="NSGA-II seed (default 1)")
    a.add_argument("--modules", type=float, nargs="+", default=MODULES,
                   help="the modules to choose from, mm (default 1.5 2 2.5 3)")
    a.add_argument("--spec", default=str(ROOT / "assets" / "synthesis" / "rice_targets.toml"),
                   help="synthesis spec of target bands (default the bundled rice bands)")
    a.add_argument("--scene", default=str(ROOT / "assets" / "loads" / "rotor.toml"),
                   help="loads scene (default the bundled rotor)")
    args = a.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    from dask.distributed import Client

    with study.local_cluster(args.workers) as cluster, Client(cluster) as client:
        problem = study.Problem(
            "synthesize", {**ARM_BOX, "module": list(args.modules), "idler_offset": IDLER},
            OBJECTIVES,
            base={"spec": args.spec, "scene": args.scene, "alternatives": False},
            maximum={"targets_missed": 0}, minimum=SAFETY,
            client=client, cache=out / "cache",
        )
        res = minimize(problem, NSGA2(pop_size=args.pop), ("n_gen", args.gen), seed=args.seed,
                       verbose=False)

    every = pd.concat(problem.history, ignore_index=True)
    every.to_parquet(out / "evaluated.parquet")
    good = problem.feasible(every).drop_duplicates(subset=problem.names)
    X = np.atleast_2d(res.X) if res.X is not None else np.empty((0, len(problem.names)))
    chosen = pd.DataFrame(problem.points(X))[problem.names] if len(X) else None
    front = (good.merge(chosen.drop_duplicates(), on=problem.names, how="inner")
             if chosen is not None else good.iloc[:0]).sort_values(OBJECTIVES[0], ignore_index=True)
    front.to_parquet(out / "front.parquet")

    fig, ax = plt.subplots(figsize=(6.4, 4.6), dpi=120)
    ax.scatter(good[OBJECTIVES[0]], good[OBJECTIVES[1]], s=14, c="0.7",
               label="feasible designs evaluated")
    for m, part in front.groupby("module"):
        ax.scatter(part[OBJECTIVES[0]], part[OBJECTIVES[1]], s=36, label=f"front, m = {m:g} mm")
    ax.set_xlabel("largest pressure angle, degrees")
    ax.set_ylabel("peak carrier torque, N·m")
    ax.set_title(f"NSGA-II, {args.pop} × {args.gen} arms for the rice bands")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "front.png")
    print(f"pareto: {len(every)} designs evaluated, {len(good)} feasible, {len(front)} on the "
          f"front; wrote {out / 'front.parquet'}, {out / 'evaluated.parquet'}, {out / 'front.png'}")


if __name__ == "__main__":
    main()
