"""Whole `ncgear design` commands on every bundled trajectory, timed (wall clock).

`python3 benches/python/design_times.py target/release/ncgear [RUNS]` designs each of the
bundled trajectories (assets/trajectories, assets/cases) without a module and for m = 1.5 and
2, RUNS times each (default 3), and prints a Markdown table: the median and worst wall time per
target and mode, and the median and worst of all runs per mode, with whether each design passed.
"""
import pathlib, statistics, subprocess, sys, tempfile, time

exe = sys.argv[1]
runs = int(sys.argv[2]) if len(sys.argv) > 2 else 3
root = pathlib.Path(__file__).resolve().parents[2]
targets = sorted((root / "assets" / "trajectories").glob("*.csv")) + sorted(
    (root / "assets" / "trajectories").glob("*.json")) + sorted((root / "assets" / "cases").glob("*.csv"))
modes = {"untoothed": [], "m = 1.5": ["--module", "1.5"], "m = 2": ["--module", "2"]}
rows, every = [], {m: [] for m in modes}
with tempfile.TemporaryDirectory() as out:
    for t in targets:
        row = [t.name]
        for mode, flags in modes.items():
            times, codes = [], set()
            for _ in range(runs):
                t0 = time.perf_counter()
                p = subprocess.run([exe, "design", str(t), "--out", out, *flags],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                times.append(time.perf_counter() - t0)
                codes.add(p.returncode)
            every[mode] += times
            verdict = "pass" if codes == {0} else "fail" if codes == {3} else f"exit {sorted(codes)}"
            row.append(f"{statistics.median(times):.2f} / {max(times):.2f} ({verdict})")
        rows.append(row)
print("| trajectory | " + " | ".join(f"{m}: median / worst s" for m in modes) + " |")
print("|---|" + "---:|" * len(modes))
for r in rows:
    print("| " + " | ".join(r) + " |")
print("| **all runs** | " + " | ".join(
    f"**{statistics.median(v):.2f} / {max(v):.2f}**" for v in every.values()) + " |")
