#!/usr/bin/env python3
"""The comparison suite against the peer ncgears: every law below is made by both
tools, whole commands, and the results are compared; prints a markdown table and exits 1 when a
check fails.

Checks per law (where both tools report the quantity):
- centre distance equal to 1e-9 relative (both scale the pitch curves to z·π·m, or solve a
  centrode's closure, from the same law);
- tooth counts equal (an open sector: the pitches on the active driver interval);
- outline areas within 1 % (closed gears; ncgear thins each coast flank by half its 0.04·m
  backlash, ncgears cuts none by default, which costs ≈ 0.2 % — open sectors close their bodies
  differently, a hub circle here, a notched sector there, so their areas are not compared);
- ncgear's mesh verification: 0 interference steps and overlap ≤ 1e-9 mm²;
- ncgear's max transmission error ≤ ncgears' (both the driven gear's angle error, degrees);
- wall time of each whole command and the ratio.

Usage: compare_ncgears.py --ncgear target/release/ncgear --ncgears target/pyvenv/bin/ncgears
       [--jobs 2] [--out DIR]
"""
import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import tempfile
import time

LAWS = [
    dict(name="1:1 motion law (ncgears' example)", law="phi - 0.08*sin(2*phi)", teeth=24, module=1.5),
    dict(name="1:1 centrode, closure solved", law="1 + 0.08*cos(2*phi)", centrode=True, teeth=24, module=1.0),
    dict(name="1:1 three lobes", law="phi - 0.04*sin(3*phi)", teeth=30, module=1.0),
    dict(name="1:2", law="0.5*phi + 0.05*sin(2*phi)", teeth=24, module=1.0),
    dict(name="2:3", law="2/3*phi + 0.04*sin(2*phi)", teeth=24, module=1.0),
    dict(name="1:2 centrode, cycle advance 180°", law="1 + 0.08*cos(2*phi)", centrode=True,
         advance_deg=180.0, teeth=24, module=1.0),
    dict(name="strong variation, undercut", law="phi - 0.12*sin(2*phi)", teeth=24, module=1.0),
    dict(name="open sector 0–180°", law="phi - 0.08*sin(2*phi)", teeth=12, module=1.5, open=(0.0, 180.0)),
    dict(name="open sector 0–150°", law="phi + 0.1*sin(phi)", teeth=10, module=1.0, open=(0.0, 150.0)),
    dict(name="open sector 0–200°, mean ratio 0.6", law="0.6*phi + 0.05*sin(phi)", teeth=12, module=1.0,
         open=(0.0, 200.0)),
    dict(name="open sector 30–200°, mean ratio 0.6", law="0.6*phi + 0.05*sin(phi)", teeth=10, module=1.0,
         open=(30.0, 200.0)),
]


def wall(cmd):
    t = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True)
    return time.perf_counter() - t, run


def shoelace(path):
    p = [tuple(map(float, line.split()[:2])) for line in open(path) if line.strip()]
    return abs(0.5 * sum(p[i][0] * p[(i + 1) % len(p)][1] - p[(i + 1) % len(p)][0] * p[i][1]
                         for i in range(len(p))))


def ours(exe, case, out):
    cmd = [exe, "pair"]
    cmd += ["--centrode", case["law"]] if case.get("centrode") else [case["law"]]
    cmd += ["--teeth", str(case["teeth"]), "--module", str(case["module"]), "--out", out, "--json"]
    if "advance_deg" in case:
        cmd += ["--cycle-advance", str(case["advance_deg"])]
    if "open" in case:
        cmd += ["--open", "--drive-start", str(case["open"][0]), "--drive-end", str(case["open"][1])]
    t, run = wall(cmd)
    if run.returncode != 0:
        return t, None, run.stderr.strip()
    d = json.loads(run.stdout)
    d["areas"] = [shoelace(os.path.join(out, f"{g}_outline.txt")) for g in ("driver", "driven")]
    return t, d, None


def theirs(exe, case, out):
    cmd = [exe, case["law"], "--teeth", str(case["teeth"]), "--module", str(case["module"]), "--output", out]
    if case.get("centrode"):
        cmd.append("--centrode")
    if "advance_deg" in case:
        cmd += ["--cycle-delta", repr(math.radians(case["advance_deg"]))]
    if "open" in case:
        cmd += ["--open", "--drive-start", repr(math.radians(case["open"][0])),
                "--drive-end", repr(math.radians(case["open"][1]))]
    t, run = wall(cmd)
    if run.returncode != 0:
        return t, None, (run.stderr or run.stdout).strip().splitlines()[-1:]
    meta = json.load(open(os.path.join(out, "gear_pair", "metadata.json")))
    return t, meta, None


def compare(case, mine, peer):
    """(row cells, failures) of one law."""
    fails = []
    a, b = mine["center_distance_mm"], peer["center_distance"]
    rel = abs(a - b) / b
    if rel > 1e-9:
        fails.append(f"centre distance {a!r} vs {b!r} (rel {rel:.1e})")
    if "open" in case:
        z_mine = (round(mine["sector"]["active_teeth"], 9), round(mine["sector"]["active_teeth"], 9))
    else:
        z_mine = (mine["z"], mine["z_driven"])
    z_peer = (peer["drive_teeth"], peer["driven_teeth"])
    if tuple(map(float, z_mine)) != tuple(map(float, z_peer)):
        fails.append(f"teeth {z_mine} vs {z_peer}")
    area = "—"
    if "open" not in case:
        dev = [abs(m - p) / p for m, p in zip(mine["areas"], (peer["drive_area"], peer["driven_area"]))]
        area = f"{100 * max(dev):.2f} %"
        if max(dev) > 0.01:
            fails.append(f"areas {mine['areas']} vs {peer['drive_area']}, {peer['driven_area']}")
    mesh = mine["mesh"]
    if mesh["interference_steps"] != 0 or mesh["max_overlap_area_mm2"] > 1e-9:
        fails.append(f"interference {mesh['interference_steps']}, overlap {mesh['max_overlap_area_mm2']}")
    te_mine, te_peer = mesh["max_transmission_error_deg"], math.degrees(peer["maximum_transmission_error"])
    if te_mine > te_peer:
        fails.append(f"TE {te_mine:.2e}° > ncgears' {te_peer:.2e}°")
    teeth = f"{z_peer[0]}:{z_peer[1]}" if "open" not in case else f"{z_peer[0]} active"
    return [teeth, f"{a:.9f}", f"{rel:.0e}", area, f"{mesh['interference_steps']}/{mesh['steps']}",
            f"{te_mine:.1e}° / {te_peer:.1e}°"], fails


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ncgear", required=True)
    ap.add_argument("--ncgears", required=True)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    root = a.out or tempfile.mkdtemp(prefix="ncgears_suite_")

    def one(k):
        case = LAWS[k]
        d = os.path.join(root, f"law{k}")
        t_mine, mine, err_mine = ours(a.ncgear, case, os.path.join(d, "ncgear"))
        t_peer, peer, err_peer = theirs(a.ncgears, case, os.path.join(d, "ncgears"))
        return case, t_mine, mine, err_mine, t_peer, peer, err_peer

    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        results = list(pool.map(one, range(len(LAWS))))
    print(f"| law | teeth | centre distance, mm | rel. diff. | area diff. | interference | max TE ncgear / ncgears | time ncgear / ncgears | ratio |")
    print("|---|---|---|---|---|---|---|---|---|")
    failed = 0
    for case, t_mine, mine, err_mine, t_peer, peer, err_peer in results:
        label = f"{case['name']}: `{case['law']}`"
        if mine is None:
            failed += 1
            print(f"| {label} | ncgear failed: {err_mine!r} (ncgears: {err_peer or 'made it'}) | | | | | | | |")
            continue
        if peer is None:
            # Made by ncgear only: its own checks still hold.
            mesh = mine["mesh"]
            ok = mesh["interference_steps"] == 0 and mesh["max_overlap_area_mm2"] <= 1e-9
            failed += not ok
            why = " ".join(err_peer).replace("|", "/")
            print(f"| {label} | ncgears refuses: “{why}” | {mine['center_distance_mm']:.9f} | — | — | "
                  f"{mesh['interference_steps']}/{mesh['steps']} | "
                  f"{mesh['max_transmission_error_deg']:.1e}° / — | {t_mine:.2f} s / {t_peer:.2f} s | — |")
            continue
        cells, fails = compare(case, mine, peer)
        ratio = t_peer / t_mine
        print(f"| {label} | " + " | ".join(cells) + f" | {t_mine:.2f} s / {t_peer:.2f} s | {ratio:.0f}× |")
        for f in fails:
            print(f"  FAIL {case['name']}: {f}", file=sys.stderr)
        failed += bool(fails)
    print(f"\n{len(LAWS) - failed} of {len(LAWS)} laws pass ({len(LAWS)} compared).", file=sys.stderr)
    if len(LAWS) < 8:
        failed += 1
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
