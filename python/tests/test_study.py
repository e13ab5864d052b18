"""ncgear.study: a study on Dask equals the plain serial loop point for point — on a local
cluster, on a scheduler and two worker processes on loopback, and when one of those workers is
killed mid-study; the cache makes a re-run evaluate nothing; a failing point is a row with its
message; the pymoo adapter and the bundled Pareto example run at a small size."""
import json
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pandas as pd
import pytest

import ncgear
from ncgear import study

from conftest import G1, ROOT

distributed = pytest.importorskip("dask.distributed")
KIDNEY = str(ROOT / "assets" / "trajectories" / "designer_kidney.csv")
BAD = "tol_mm=-1.0"


def _same_as_serial(df, job, points):
    """Every figure of every row equals the serial loop's (time_s aside), rows in input order."""
    ref = study.table(points, study.serial(job, points), job).drop(columns="time_s")
    got = df.drop(columns="time_s")
    assert len(got) == len(points)
    pd.testing.assert_frame_equal(got.reset_index(drop=True), ref, check_exact=True)


@pytest.fixture(scope="module")
def client():
    """A local cluster of 2 worker processes, each with RAYON_NUM_THREADS=1."""
    with study.local_cluster(2) as cluster:
        with distributed.Client(cluster) as c:
            yield c


def test_grid_is_the_cartesian_product_in_order_and_sample_is_seeded():
    assert study.grid(a=[1, 2], b=["x", "y"]) == [
        {"a": 1, "b": "x"}, {"a": 1, "b": "y"}, {"a": 2, "b": "x"}, {"a": 2, "b": "y"}]
    s = study.sample(5, seed=7, w1=(0.2, 0.8), k=(3, 6), route=["ac", "bd"], points="p.csv")
    assert s == study.sample(5, seed=7, w1=(0.2, 0.8), k=(3, 6), route=["ac", "bd"], points="p.csv")
    assert s != study.sample(5, seed=8, w1=(0.2, 0.8), k=(3, 6), route=["ac", "bd"], points="p.csv")
    assert all(0.2 <= p["w1"] < 0.8 and p["k"] in (3, 4, 5, 6) and p["points"] == "p.csv" for p in s)
    assert s[0]["w1"] == float(np.random.default_rng(7).uniform(0.2, 0.8, 5)[0])
    with pytest.raises(ncgear.NcgearError, match=r"^a=3: expected a list of values \(one axis\)"):
        study.grid(a=3)
    with pytest.raises(ncgear.NcgearError, match=r"^job='desing': expected one of 'design'"):
        study.run("desing", [{}])


def test_local_cluster_equals_serial_and_a_failing_point_is_a_row(client, tmp_path):
    points = study.grid(points=[str(G1)], max_pressure_angle=[40.0, 45.0], tol_mm=[0.05, -1.0])
    df = study.run("design", points, client=client, out=tmp_path / "s.parquet")
    _same_as_serial(df, "design", points)
    assert list(df.columns[:3]) == ["points", "max_pressure_angle", "tol_mm"]
    with pytest.raises(ncgear.NcgearError) as e:
        ncgear.design(G1, tol_mm=-1.0)
    errors = df.loc[df["tol_mm"] < 0, "error"]
    assert len(errors) == 2 and set(errors) == {str(e.value)}
    assert df.loc[df["tol_mm"] > 0, "error"].isna().all()
    assert (df.loc[df["tol_mm"] > 0, "deviations_max_mm"] < 0.05).all()
    back = pd.read_parquet(tmp_path / "s.parquet")
    pd.testing.assert_frame_equal(back, df, check_exact=True)
    assert df.attrs["evaluated"] == 4


def test_the_cache_makes_a_rerun_evaluate_only_what_is_missing(client, tmp_path):
    points = study.grid(points=[str(G1)], max_pressure_angle=[38.0, 42.0, 46.0])
    first = study.run("design", points[:2], client=client, cache=tmp_path)
    assert first.attrs["evaluated"] == 2
    files = sorted(p.name for p in tmp_path.rglob("*.json"))
    assert len(files) == 2 and not list(tmp_path.rglob("*.tmp"))
    again = study.run("design", points, client=client, cache=tmp_path)
    assert again.attrs["evaluated"] == 1
    third = study.run("design", points, client=client, cache=tmp_path)
    assert third.attrs["evaluated"] == 0
    pd.testing.assert_frame_equal(third, again, check_exact=True)
    _same_as_serial(third, "design", points)


def _dask(*args):
    return subprocess.Popen([sys.executable, "-m", "dask", *args], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)


def test_a_worker_killed_mid_study_leaves_every_point_once_and_equal_to_serial(tmp_path):
    sched_file = tmp_path / "scheduler.json"
    procs = [_dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                   "--scheduler-file", str(sched_file))]
    try:
        deadline = time.monotonic() + 60
        while not sched_file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        for _ in range(2):
            procs.append(_dask("worker", "--scheduler-file", str(sched_file), "--nthreads", "1",
                               "--no-nanny", "--no-dashboard", "--host", "127.0.0.1"))
        with distributed.Client(scheduler_file=str(sched_file), timeout=60) as c:
            c.wait_for_workers(2, timeout=60)
            # Kidney designs of a few seconds each: the kill lands while tasks run.
            points = study.grid(points=[KIDNEY], max_pressure_angle=[40.0, 43.0, 46.0, 49.0, 52.0],
                                idler_offset=["free"])
            result = {}
            cache = tmp_path / "cache"
            t = threading.Thread(target=lambda: result.update(
                df=study.run("design", points, client=c, cache=cache, progress=False)))
            t.start()
            while not list(cache.rglob("*.json")) and t.is_alive():
                time.sleep(0.05)
            done_before_kill = len(list(cache.rglob("*.json")))
            procs[1].kill()
            t.join(timeout=300)
            assert not t.is_alive(), "the study did not finish after a worker was killed"
            df = result["df"]
            assert done_before_kill < len(points)
            assert len(c.scheduler_info()["workers"]) == 1
        assert len(df) == len(points) and df["error"].isna().all()
        keys = [json.dumps(p, sort_keys=True) for p in points]
        assert len(set(keys)) == len(points)
        _same_as_serial(df, "design", points)
    finally:
        for p in reversed(procs):
            p.kill()
            p.wait(timeout=30)


def test_the_pymoo_problem_and_the_pareto_example_at_a_small_size(client, tmp_path):
    pytest.importorskip("pymoo")
    p = study.Problem("design", {"max_pressure_angle": (38.0, 50.0)},
                      ["deviations_max_mm", "pressure_angle_max_deg"], base={"points": str(G1)},
                      client=client)
    out = {}
    p._evaluate(np.array([[40.0], [48.0]]), out)
    df = p.history[0]
    assert out["F"].shape == (2, 2) and out["G"].shape == (2, 1)
    assert np.array_equal(out["F"][:, 0], df["deviations_max_mm"].to_numpy())
    assert np.array_equal(out["G"][:, 0], np.where(df["passed"], 0.0, 1.0))
    # The rows it calls feasible are exactly those whose every g ≤ 0 (here: those that pass).
    assert np.array_equal(p.constraints(df), out["G"])
    assert list(p.feasible(df).index) == list(df.index[df["passed"].astype(bool)])
    with pytest.raises(ncgear.NcgearError, match=r"^'S_H_min': not a figure of job 'design'"):
        study.Problem("design", {"tol_mm": (0.01, 0.1)}, ["S_H_min"])
    c = study.Problem("design", {"module": [1.5, 2.0, 2.5], "idler_offset": ["auto", "free"]},
                      ["deviations_max_mm"], base={"points": str(G1)})
    assert list(c.xl) == [0.0, 0.0] and list(c.xu) == [3.0, 2.0]
    assert c.points(np.array([[0.0, 1.99], [2.999, 0.5], [3.0, 2.0]])) == [
        {"points": str(G1), "module": 1.5, "idler_offset": "free"},
        {"points": str(G1), "module": 2.5, "idler_offset": "auto"},
        {"points": str(G1), "module": 2.5, "idler_offset": "free"},
    ]
    # The bundled example: arms for the rice bands over the arm box, module and idler layout.
    script = ROOT / "examples" / "python" / "pareto.py"
    r = subprocess.run([sys.executable, str(script), str(tmp_path / "pareto"), "--pop", "4",
                        "--gen", "2", "--workers", "2", "--modules", "2.5", "3"],
                       capture_output=True, text=True, timeout=400)
    assert r.returncode == 0, r.stderr
    every = pd.read_parquet(tmp_path / "pareto" / "evaluated.parquet")
    front = pd.read_parquet(tmp_path / "pareto" / "front.parquet")
    assert len(every) == 8 and set(every["module"]) <= {2.5, 3.0}
    assert 1 <= len(front) <= 8 and (tmp_path / "pareto" / "front.png").stat().st_size > 1000
    # Every design on the front meets every constraint: its checks, the bands, the arm box, the
    # scene's safety targets.
    assert front["passed"].all() and (front["targets_missed"] == 0).all()
    assert (front["S_H_min"] >= 1.0).all() and (front["S_F_min"] >= 1.4).all()
    assert (front["l1_mm"] <= front["l1_max_mm"] + 1e-9).all()
    assert (front["l3_mm"] <= front["l3_max_mm"] + 1e-9).all()
    # The front is non-dominated: no row is at least as good in every objective and better in one.
    f = front[["pressure_angle_max_deg", "carrier_torque_peak_Nm", "deviations_max_mm"]].to_numpy()
    for a in f:
        assert not any((b <= a).all() and (b < a).any() for b in f)


def test_each_job_row_holds_the_figures_of_the_direct_call():
    d = ncgear.design(G1)
    row = study.evaluate("design", {"points": str(G1)})
    assert row["deviations_max_mm"] == float(d.deviations.max()) and row["passed"] is True
    assert row["pressure_angle_max_deg"] == d.limits.pressure_angle_deg and row["error"] is None
    spec = ROOT / "assets" / "synthesis" / "g1_five_poses.toml"
    s = ncgear.synthesize(spec)
    row = study.evaluate("synthesize", {"spec": str(spec)})
    assert row["pose_error_max_mm"] == max(q.error_mm for q in s.poses)
    assert row["l1_mm"] == s.design.l1_mm
    scene = ROOT / "assets" / "loads" / "rotor.toml"
    # A synthesis in a narrower arm box, for a module, with its loads.
    rice = ROOT / "assets" / "synthesis" / "rice_targets.toml"
    s = ncgear.synthesize(rice, l1_mm=(40.0, 80.0), module=2.5, idler_offset="free")
    r = ncgear.loads(ncgear.teeth(s.design, 2.5), scene)
    row = study.evaluate("synthesize", {"spec": str(rice), "l1_max_mm": 80.0, "module": 2.5,
                                        "idler_offset": "free", "scene": str(scene)})
    assert row["l1_mm"] == s.design.l1_mm <= 80.0 and row["teeth"] == s.design.module.teeth
    assert row["carrier_torque_peak_Nm"] == r.summary.carrier_torque_peak_Nm
    assert row["targets_missed"] == sum(t.margin < 0 for t in s.targets)
    assert row["margin_height_mm"] == next(t.margin for t in s.targets if t.index == "height_mm")
    assert row["margin_arm_clearance_mm"] is None and row["pose_error_max_mm"] is None
    r = ncgear.loads(ncgear.teeth(d, 2.0), scene)
    row = study.evaluate("loads", {"points": str(G1), "scene": str(scene), "tooth_module": 2.0})
    assert row["carrier_torque_peak_Nm"] == r.summary.carrier_torque_peak_Nm
    assert row["S_H_min"] == (r.summary.min_S_H.value if r.summary.min_S_H else None)
    assert row["loads_passed"] is r.passed
    row = study.evaluate("design", {"points": str(G1), "tolmm": 0.1})
    assert row["error"] == ("TypeError: design() got an unexpected keyword argument 'tolmm' "
                            "(a point's keys are the job's keyword arguments)")
    assert row["deviations_max_mm"] is None
    t = ncgear.tradeoff(G1)
    row = study.evaluate("tradeoff", {"points": str(G1)})
    made = [r.designed.max_deviation_mm for r in t.rows if r.designed is not None]
    assert row["rows_designed"] == len(made) and row["best_max_deviation_mm"] == min(made)
    default = next(r.designed for r in t.rows if r.is_default)
    assert row["designed_max_deviation_mm"] == default.max_deviation_mm


def test_each_row_is_the_direct_call_field_for_field_on_any_number_of_threads():
    """A row is ``ncgear.design(**point)``: each column the report field it is named after
    (docs/studies.md), on workers of 1 and of 2 threads per design alike."""
    points = study.grid(points=[str(G1)], max_pressure_angle=[38.0, 45.0],
                        idler_offset=["auto", "free"])
    want = []
    for p in points:
        q = dict(p)
        d = ncgear.design(q.pop("points"), **q)
        want.append({
            "deviations_max_mm": float(d.deviations.max()),
            "deviations_mean_mm": float(d.deviations.mean()),
            "roundtrip_max_deviation_mm": d.roundtrip.max_deviation_mm,
            "pressure_angle_max_deg": d.limits.pressure_angle_deg,
            "idler_offset_deg": d.idler_offset_deg,
            "l1_mm": d.l1_mm, "l3_mm": d.l3_mm, "passed": d.verdict.passed,
        })
    for threads in (1, 2):
        df = study.run("design", points, workers=1, threads=threads, progress=False)
        for i, w in enumerate(want):
            got = {k: df.iloc[i][k] for k in w}
            assert got == w, (threads, i)
    with pytest.raises(ncgear.NcgearError, match=r"^threads=0: expected a number of threads"):
        study.local_cluster(1, threads=0)
