"""ncgear against the yardsticks a user would pick instead, back to back in one run.

Run by `bash benches/compare.sh` (it builds the release binary and the venv). Each row times the
ncgear command (whole process, wall clock) and its yardstick alternately, `--repeat` times, and
reports the medians and the ratio yardstick / ncgear. The yardsticks are not part of the project:
`--yardsticks DIR` points at them (default `../shared/bench`); rows whose yardstick is missing
are printed with "—". Prints a Markdown table (the README's performance table) with the date.
"""
import argparse
import datetime
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The project's numpy Monte Carlo, the yardstick when DIR has no mc_numpy_best.py.
MC_NUMPY = os.path.join(ROOT, "benches", "python", "mc_numpy.py")
BIN = os.path.join(ROOT, "target", "release", "ncgear")
G1 = os.path.join(ROOT, "assets", "trajectories", "g1_ellipse.csv")
PAPER = os.path.join(ROOT, "assets", "tolerance", "paper_3k.toml")
LAW = "phi - 0.08*sin(2*phi)"


def wall(cmd, **kw):
    """Wall time (s) of a whole command; its stdout."""
    t = time.perf_counter()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, **kw).stdout
    return time.perf_counter() - t, out


def ncgear(args):
    out = tempfile.mkdtemp(prefix="ncgear_cmp_")
    try:
        return wall([BIN] + [a.replace("{OUT}", out) for a in args])[0]
    finally:
        shutil.rmtree(out, ignore_errors=True)


def numpy_env():
    """The numpy yardstick's environment: OpenBLAS picks its own kernel (OPENBLAS_CORETYPE and
    OPENBLAS_L2_SIZE unset for that command alone)."""
    return {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")}


def blas_kernel():
    """numpy's BLAS as threadpoolctl reports it in the yardstick's environment."""
    code = ("import numpy, threadpoolctl\n"
            "for i in threadpoolctl.threadpool_info():\n"
            "    print(f\"numpy {numpy.__version__}: {i['internal_api']} {i.get('version')}, kernel "
            "{i.get('architecture')}, {i['num_threads']} threads\")")
    return subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True,
                          env=numpy_env()).stdout.strip()


def numpy_mc(script, n):
    # The script prints its own in-process time (the loop, no interpreter start-up): the
    # yardstick at its best. mc_numpy_best.py prints the time first, mc_numpy.py "… in T s; …".
    _, out = wall([sys.executable, script, str(n)], env=numpy_env())
    m = re.search(r" in ([0-9.]+) s", out)
    return float(m.group(1)) if m else float(out.split()[0])


CHAIN = """
import sys, time, numpy as np
sys.path.insert(0, {dir!r})
from pipeline import design_from_trajectory
P = np.loadtxt({g1!r}, delimiter=',', skiprows=1)[:, :2]
t = time.perf_counter(); design_from_trajectory(P, K=16, refine={refine}); print(time.perf_counter() - t)
"""


def numpy_chain(ys, refine):
    code = CHAIN.format(dir=os.path.join(ys, "numpy_chain"), g1=G1, refine=refine)
    _, out = wall([sys.executable, "-c", code])
    return float(out.split()[-1])


def ncgears_pair(exe):
    out = tempfile.mkdtemp(prefix="ncgears_cmp_")
    try:
        return wall([exe, LAW, "--teeth", "24", "--module", "1.5", "--output", out])[0]
    finally:
        shutil.rmtree(out, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--yardsticks", default=os.path.join(ROOT, "..", "shared", "bench"))
    ap.add_argument("--ncgears", default=shutil.which("ncgears"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--samples", type=int, default=50000)
    ap.add_argument("--only", default="", help="run only the rows whose work contains this text")
    a = ap.parse_args()
    ys = a.yardsticks if os.path.isdir(a.yardsticks) else None
    best = os.path.join(ys, "mc_numpy_best.py") if ys else ""
    mc = best if os.path.isfile(best) else MC_NUMPY
    rows = [
        (f"Monte Carlo, {a.samples} assemblies of `paper_3k.toml`",
         ["tolerance", PAPER, "--samples", str(a.samples), "--out", "{OUT}"],
         f"`{os.path.basename(mc)}` (in-process)", lambda: numpy_mc(mc, a.samples), 20.0),
        ("`pair \"phi - 0.08*sin(2*phi)\" --teeth 24 --module 1.5` (90-step verification)",
         ["pair", LAW, "--teeth", "24", "--module", "1.5", "--out", "{OUT}"],
         "ncgears 0.3.1 (PyPI), whole command", (lambda: ncgears_pair(a.ncgears)) if a.ncgears else None, 50.0),
        ("`design g1_ellipse.csv`",
         ["design", G1, "--out", "{OUT}"],
         "numpy chain K = 16 (in-process)", (lambda: numpy_chain(ys, False)) if ys else None, 20.0),
        ("`design g1_ellipse.csv --refine on`",
         ["design", G1, "--refine", "on", "--out", "{OUT}"],
         "numpy chain with refinement (in-process)", (lambda: numpy_chain(ys, True)) if ys else None, 20.0),
        ("`design g1_ellipse.csv --module 2` (teeth + 2 × 72-step verification)",
         ["design", G1, "--module", "2", "--out", "{OUT}"], "—", None, None),
    ]
    rows = [r for r in rows if a.only in r[0]]
    print(blas_kernel() + "\n")
    print(f"Measured {datetime.date.today().isoformat()}, {os.cpu_count()} cores, medians of {a.repeat} "
          "back-to-back runs (whole ncgear process, wall clock).\n")
    print("| work | ncgear (s) | yardstick | yardstick (s) | ratio | goal |")
    print("|---|---|---|---|---|---|")
    for name, args, yname, yard, goal in rows:
        mine, theirs = [], []
        for _ in range(a.repeat):
            mine.append(ncgear(args))
            if yard:
                theirs.append(yard())
        m = statistics.median(mine)
        if yard:
            y = statistics.median(theirs)
            ratio = y / m
            ok = "met" if ratio >= goal else "**not met**"
            print(f"| {name} | {m:.3f} | {yname} | {y:.3f} | {ratio:.1f}× | ≥ {goal:.0f}× ({ok}) |")
        else:
            ok = "met" if m <= 0.2 else "**not met**"
            print(f"| {name} | {m:.3f} | — | — | — | ≤ 0.2 s ({ok}) |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
