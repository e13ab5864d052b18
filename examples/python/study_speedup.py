"""Measures ncgear.study (docs/studies.md): a 40-point study on a local Dask cluster equal to the
serial loop point for point, then 2 worker processes against 1 on designs of the bundled kidney
(each several seconds), every worker single-threaded (RAYON_NUM_THREADS=1).

    python examples/python/study_speedup.py [N_SLOW_POINTS]
    python examples/python/study_speedup.py --scaling [N_POINTS]

``--scaling``: N kidney designs (default 4) on 1 and 2 workers × 1 and 2 threads per design
(``study.run(..., workers=, threads=)``), each table equal to the first, the wall times printed.

Prints the numbers docs/studies.md records. Times are wall-clock seconds of study.run (the
cluster started before and closed after, outside the timing).
"""
import os
import pathlib
import sys
import time

os.environ.setdefault("RAYON_NUM_THREADS", "1")  # the serial loop single-threaded as the workers

import pandas as pd  # noqa: E402
from dask.distributed import Client  # noqa: E402

from ncgear import study  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
G1 = str(ROOT / "assets" / "trajectories" / "g1_ellipse.csv")
KIDNEY = str(ROOT / "assets" / "trajectories" / "designer_kidney.csv")


def timed(points, workers, threads=1):
    with study.local_cluster(workers, threads) as cluster, Client(cluster) as c:
        df = study.run("design", points, client=c, progress=False)
    return df, df.attrs["wall_s"]


def scaling(n: int) -> None:
    pts = study.grid(points=[KIDNEY], max_pressure_angle=[40.0 + k for k in range(n)])
    first = None
    for workers in (1, 2):
        for threads in (1, 2):
            df, wall = timed(pts, workers, threads)
            if first is None:
                first = df
            pd.testing.assert_frame_equal(df.drop(columns="time_s"), first.drop(columns="time_s"),
                                          check_exact=True)
            per = df["time_s"]
            print(f"{workers} worker(s) x {threads} thread(s): {wall:.2f} s wall, per point "
                  f"{per.min():.2f}-{per.max():.2f} s, load {os.getloadavg()[0]:.2f}")


def main() -> None:
    if sys.argv[1:2] == ["--scaling"]:
        scaling(int(sys.argv[2]) if len(sys.argv) > 2 else 4)
        return
    n_slow = int(sys.argv[1]) if len(sys.argv) > 1 else 8
    # 1. 40 points, Dask (2 workers) against the serial loop, every figure equal.
    pts = study.sample(40, seed=3, points=G1, max_pressure_angle=(36.0, 50.0),
                       min_concave_radius=(6.0, 14.0), idler_offset=["auto", "free"])
    df, wall = timed(pts, 2)
    t = time.perf_counter()
    ref = study.table(pts, study.serial("design", pts), "design")
    serial_s = time.perf_counter() - t
    pd.testing.assert_frame_equal(df.drop(columns="time_s"), ref.drop(columns="time_s"),
                                  check_exact=True)
    print(f"40 points: equal to the serial loop in every figure; errors {df['error'].notna().sum()}; "
          f"dask 2 workers {wall:.2f} s, serial {serial_s:.2f} s")
    # 2. Slow points: 1 worker against 2.
    slow = study.grid(points=[KIDNEY], max_pressure_angle=[40.0 + k for k in range(n_slow)])
    one, t1 = timed(slow, 1)
    two, t2 = timed(slow, 2)
    pd.testing.assert_frame_equal(one.drop(columns="time_s"), two.drop(columns="time_s"),
                                  check_exact=True)
    for name, df, wall in (("1 worker", one, t1), ("2 workers", two, t2)):
        per = df["time_s"]
        print(f"{n_slow} kidney designs on {name}: {wall:.2f} s wall; per point {per.min():.2f}-"
              f"{per.max():.2f} s (mean {per.mean():.2f}); busy {per.sum() / wall:.2f} workers")
    print(f"speed-up {t1 / t2:.2f}x; cpus {os.cpu_count()}, load average (1 min) "
          f"{os.getloadavg()[0]:.2f} at the end")

if __name__ == "__main__":
    main()
