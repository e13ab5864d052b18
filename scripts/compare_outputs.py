#!/usr/bin/env python3
"""Compare two output trees of scripts/bundled_outputs.sh, ignoring wall-time fields.

JSON files (and JSON on stdout) are compared after removing keys that hold timings
(`timings_ms`, `*_ms`, `*elapsed*`, `wall*`). Every other file is compared byte for byte, with
the output directory's path replaced and DXF time stamps and GUIDs blanked. Prints one line per difference; exit 1 when any.
"""
import json, os, re, sys

TIMING = ("timings_ms", "elapsed", "wall", "runtime", "ms")

def is_timing(key):
    k = key.lower()
    return k in TIMING or k.endswith("_ms") or "elapsed" in k or k.startswith("wall") or k.endswith("_time_s") or k == "time_s"

def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if not is_timing(k)}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v

def load_json(path, root):
    try:
        with open(path) as f:
            return json.loads(f.read().replace(root, "OUT"))
    except Exception:
        return None

JULIAN = re.compile(rb"^(24\d{5}\.\d+|[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12})\r?$", re.M)

def load_bytes(path, root):
    """The file's bytes with the output root replaced and DXF time stamps (Julian dates) and GUIDs blanked."""
    data = open(path, "rb").read().replace(root.encode(), b"OUT")
    return JULIAN.sub(b"JD", data) if path.lower().endswith(".dxf") else data

def main(a, b):
    diffs = 0
    for root, _, files in os.walk(a):
        for name in sorted(files):
            pa = os.path.join(root, name)
            rel = os.path.relpath(pa, a)
            pb = os.path.join(b, rel)
            if not os.path.exists(pb):
                print(f"missing in {b}: {rel}"); diffs += 1; continue
            ja, jb = load_json(pa, a), load_json(pb, b)
            if ja is not None and jb is not None:
                same = strip(ja) == strip(jb)
            else:
                same = load_bytes(pa, a) == load_bytes(pb, b)
            if not same:
                print(f"differs: {rel}"); diffs += 1
    for root, _, files in os.walk(b):
        for name in files:
            rel = os.path.relpath(os.path.join(root, name), b)
            if not os.path.exists(os.path.join(a, rel)):
                print(f"new in {b}: {rel}"); diffs += 1
    return 1 if diffs else 0

if __name__ == "__main__":
    sys.exit(main(os.path.realpath(sys.argv[1]), os.path.realpath(sys.argv[2])))
