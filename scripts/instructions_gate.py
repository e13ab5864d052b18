"""The instruction gate's comparison (run by scripts/check_instructions.sh; docs/performance.md,
"The instruction gate").

Reads gungraun's JSON lines (`cargo bench --bench instructions -- --output-format=json`) and
benches/instructions/baseline.toml, a table per benchmark (`["function.id"]`) with
`instructions` (callgrind Ir) and `reason` (one line: why the count is what it is).

check: fails when a benchmark executes more than 5 % more instructions than its entry, when a
benchmark has no entry, or when an entry's count differs from the parent commit's with the
same reason (a re-bless names its reason). A count 5 % below its entry passes, with a note
that blessing it would tighten the gate.

bless REASON: writes the measured counts; entries within 2 % keep their count and reason (run
to run, a count of the same tree moved by up to 0.8 %), the others and new benchmarks take REASON.
"""
import json
import subprocess
import sys
import tomllib

LIMIT = 1.05
KEEP = 0.02


def measured(path):
    """{name: Ir} of gungraun's JSON lines."""
    out = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line.startswith("{"):
                continue
            d = json.loads(line)
            name = f"{d['function_name']}.{d['id']}"
            out[name] = int(d["profiles"][0]["data"]["total"]["metrics"]["Ir"]["values"]["new"])
    if not out:
        sys.exit(f"{path}: no benchmark results (did `cargo bench --bench instructions` run?)")
    return out


def read_baseline(text, where):
    try:
        table = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        sys.exit(f"{where}: not TOML: {e}")
    for name, e in table.items():
        if not isinstance(e, dict) or not isinstance(e.get("instructions"), int) or e["instructions"] <= 0:
            sys.exit(f"{where}: [\"{name}\"] needs `instructions`, a positive integer")
        r = e.get("reason")
        if not isinstance(r, str) or not r.strip() or "\n" in r:
            sys.exit(f"{where}: [\"{name}\"] needs `reason`, one line saying why")
    return table


def parent_baseline(path):
    """The baseline of the parent commit, or None (no git, no parent, no file there)."""
    try:
        text = subprocess.run(["git", "show", f"HEAD~1:{path}"], check=True, capture_output=True,
                              text=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return read_baseline(text, f"HEAD~1:{path}")


def write_baseline(path, table):
    lines = [
        "# Instruction counts (callgrind Ir) of benches/instructions.rs: the gate of",
        "# scripts/check_instructions.sh fails when a count grows by more than 5 % over its entry.",
        "# A larger count lands only re-blessed in the same commit, with a one-line reason:",
        "# `scripts/check_instructions.sh --bless \"why\"` (docs/performance.md, \"The instruction gate\").",
    ]
    for name in sorted(table):
        e = table[name]
        lines += ["", f"[{json.dumps(name)}]", f"instructions = {e['instructions']}",
                  f"reason = {json.dumps(e['reason'], ensure_ascii=False)}"]
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


def check(results, path):
    with open(path, encoding="utf-8") as f:
        base = read_baseline(f.read(), path)
    parent = parent_baseline(path) or {}
    failed = []
    print(f"{'benchmark':<28} {'instructions':>15} {'baseline':>15} {'ratio':>7}")
    for name in sorted(results):
        n = results[name]
        e = base.get(name)
        if e is None:
            print(f"{name:<28} {n:>15,} {'—':>15}")
            failed.append(f"{name}: no baseline entry (bless it with its reason)")
            continue
        ratio = n / e["instructions"]
        print(f"{name:<28} {n:>15,} {e['instructions']:>15,} {ratio:>6.3f}×")
        if ratio > LIMIT:
            failed.append(f"{name}: {n:,} instructions, {100 * (ratio - 1):.1f} % over the baseline "
                          f"{e['instructions']:,} (limit 5 %)")
        elif ratio < 1 / LIMIT:
            print(f"  note: {name} is {100 * (1 - ratio):.1f} % below its baseline; blessing it "
                  "tightens the gate")
        p = parent.get(name)
        if p and p["instructions"] != e["instructions"] and p["reason"] == e["reason"]:
            failed.append(f"{name}: re-blessed ({p['instructions']:,} → {e['instructions']:,}) "
                          "without a new reason")
    for name in sorted(set(base) - set(results)):
        print(f"  note: baseline entry {name} has no benchmark")
    if failed:
        print("\nThe instruction gate failed:\n  " + "\n  ".join(failed))
        print("If the work is meant, re-bless in this commit: scripts/check_instructions.sh "
              "--bless \"one-line reason\"")
        sys.exit(1)
    print(f"\nThe instruction gate passed: {len(results)} benchmarks within 5 % of "
          f"{path}.")


def bless(results, path, reason):
    if not reason.strip() or "\n" in reason:
        sys.exit("--bless needs a one-line reason")
    try:
        with open(path, encoding="utf-8") as f:
            base = read_baseline(f.read(), path)
    except FileNotFoundError:
        base = {}
    for name, n in results.items():
        e = base.get(name)
        if e and abs(n / e["instructions"] - 1) <= KEEP:
            continue
        old = f"{e['instructions']:,}" if e else "new"
        print(f"{name:<28} {old:>15} → {n:,}")
        base[name] = {"instructions": n, "reason": reason.strip()}
    write_baseline(path, base)
    print(f"Blessed into {path}; commit it with the change.")


def main():
    args = sys.argv[1:]
    if len(args) == 3 and args[0] == "check":
        check(measured(args[1]), args[2])
    elif len(args) == 4 and args[0] == "bless":
        bless(measured(args[1]), args[2], args[3])
    else:
        sys.exit("usage: instructions_gate.py check RESULTS.json BASELINE.toml | "
                 "bless RESULTS.json BASELINE.toml REASON")


if __name__ == "__main__":
    main()
