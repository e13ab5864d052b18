"""Accuracy against time for the rotor model (docs/dynamics.md, "Accuracy costs time").

Runs the bundled G1 rotor (assets/dynamics/rotor_g1.toml) through the CLI with each solver
setting for exactly two turns (the bundled run settles in two), and compares the second turn
with a converged reference (DOPRI5 rtol 1e-11): the largest force error of both meshes relative
to each mesh's dynamic peak, the largest tip-path error (mm), and the impacts per turn. Time:
the fastest of three whole commands (wall clock, s).

Usage: python3 benches/python/rotor_accuracy.py target/release/ncgear
"""
import json
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = ROOT / "assets/dynamics/rotor_g1.toml"

CASES = [
    ("DOPRI5 rtol 1e-11 (reference)", "rtol = 1e-11\natol = 1e-15"),
    ("DOPRI5 rtol 1e-10", "rtol = 1e-10\natol = 1e-14"),
    ("DOPRI5 rtol 1e-9", "rtol = 1e-9\natol = 1e-13"),
    ("DOPRI5 rtol 1e-8 (bundled)", "rtol = 1e-8\natol = 1e-12"),
    ("DOPRI5 rtol 1e-7", "rtol = 1e-7\natol = 1e-11"),
    ("DOPRI5 rtol 1e-6", "rtol = 1e-6\natol = 1e-10"),
    ("DOPRI5 rtol 1e-8, no breakpoints", "rtol = 1e-8\natol = 1e-12\nbreakpoints = false"),
    ("DOPRI5 rtol 1e-8, no events", "rtol = 1e-8\natol = 1e-12\nevents = false"),
    ("RK4 200 000 steps/turn", "method = \"rk4\"\nrk4_steps_per_turn = 200000"),
    ("RK4 500 000 steps/turn", "method = \"rk4\"\nrk4_steps_per_turn = 500000"),
]


def scene_text(solver):
    text = SCENE.read_text()
    head, rest = text.split("[solver]", 1)
    steady = rest[rest.index("[steady]"):]
    design = (SCENE.parent / "../loads/g1_m2_design.json").resolve()
    head = head.replace('"../loads/g1_m2_design.json"', json.dumps(str(design)))
    steady = "[steady]\npoincare_tol = 1e-300\nmax_turns = 2\n"
    return head + "[solver]\n" + solver + "\n" + steady


def run(binary, solver, out):
    scene = out / "scene.toml"
    scene.write_text(scene_text(solver))
    best = None
    for _ in range(3):
        t = time.perf_counter()
        p = subprocess.run([binary, "dynamics", str(scene), "--out", str(out)],
                           capture_output=True, text=True)
        dt = time.perf_counter() - t
        if p.returncode not in (0, 3):
            raise SystemExit(p.stderr)
        best = dt if best is None else min(best, dt)
    return json.loads((out / "dynamics.json").read_text()), best


def main():
    binary = sys.argv[1]
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for i, (name, solver) in enumerate(CASES):
            out = pathlib.Path(d) / str(i)
            out.mkdir()
            rows.append((name, *run(binary, solver, out)))
    ref = rows[0][1]
    print(f"rotor accuracy against time, {time.strftime('%Y-%m-%d')}, two turns of the bundled G1 rotor")
    print("| setting | force error (of peak) | tip error (mm) | impacts/turn | RHS evaluations | time (s) |")
    print("|---|---|---|---|---|---|")
    for name, r, t in rows:
        err = 0.0
        for m in ("sun_intermediate", "intermediate_planet"):
            a = ref["meshes"][m]["dynamic_force_n"]
            b = r["meshes"][m]["dynamic_force_n"]
            peak = max(abs(x) for x in a)
            err = max(err, max(abs(x - y) for x, y in zip(a, b)) / peak)
        tip = max(abs(x - y) for x, y in zip(ref["tip_deviation_mm"], r["tip_deviation_mm"]))
        print(f"| {name} | {err:.1e} | {tip:.1e} | {r['summary']['impacts_per_turn']} | "
              f"{r['stats']['rhs_evals']} | {t:.2f} |")


if __name__ == "__main__":
    main()
