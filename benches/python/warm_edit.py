"""The designer's warm edit as the page sends it, timed at the client.

`python3 benches/python/warm_edit.py target/release/ncgear PORT [DRAGS]` starts `ncgear serve`
on loopback PORT, designs the bundled G1 example, then sends DRAGS (default 20) successive
edits — each a Gaussian bump of at most 1 mm on the path, cumulative — as `POST /api/design`
with the page's own body (`points`, the form's default options, `view`, `spacing_mm`, and the
previous answer as `start`), and prints the wall time at the client and the server's
`server_ms` (p50, p95), the answer's size and the design's stage times of the last edit.
"""
import json, math, random, statistics, subprocess, sys, time, urllib.request
exe, port = sys.argv[1], int(sys.argv[2])
srv = subprocess.Popen(exe.split() + ["serve", "--port", str(port)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
url = f"http://127.0.0.1:{port}/"
for _ in range(100):
    try:
        urllib.request.urlopen(url, timeout=1).read(); break
    except Exception:
        time.sleep(0.1)
def post(path, body):
    data = json.dumps(body).encode()
    t0 = time.perf_counter()
    r = urllib.request.urlopen(urllib.request.Request(url + path, data, {"Content-Type": "application/json"}), timeout=60)
    raw = r.read()
    return (time.perf_counter() - t0) * 1e3, raw
try:
    pts = json.loads(urllib.request.urlopen(url + "api/examples/g1_ellipse").read())["points"]
    opts = {"center": [0, 0], "tol_mm": 0.05, "limits": "on", "sense": "auto", "max_pressure_angle": 45, "idler_offset": "auto"}
    _, raw = post("api/design", {"points": pts, "options": opts, "view": True, "spacing_mm": 140})
    cur = json.loads(raw)
    rng = random.Random(7)
    base = [p[:] for p in pts]
    walls, servers, sizes = [], [], []
    for _ in range(int(sys.argv[3]) if len(sys.argv) > 3 else 20):
        c, amp, w = rng.randrange(len(pts)), rng.uniform(-1.0, 1.0), 30
        for j in range(len(pts)):
            dj = min(abs(j - c), len(pts) - abs(j - c))
            f = amp * math.exp(-(dj / w) ** 2)
            base[j][0] += 0.6 * f; base[j][1] += 0.4 * f
        start = dict(cur); start.pop("view", None); start.pop("server_ms", None)
        wall, raw = post("api/design", {"points": base, "options": opts, "view": True, "spacing_mm": 140, "start": start})
        d = json.loads(raw)
        walls.append(wall); servers.append(d["server_ms"]); sizes.append(len(raw))
        cur = d
    q = lambda v: (statistics.median(v), sorted(v)[math.ceil(0.95 * len(v)) - 1])
    print("last edit, stage times (ms):", {k: round(v, 1) for k, v in cur["timings_ms"].items() if v})
    print("wall p50 %.1f p95 %.1f ms | server p50 %.1f p95 %.1f ms | answer %.0f kB | dev %.3f mm" % (*q(walls), *q(servers), statistics.mean(sizes) / 1e3, cur["roundtrip"]["max_deviation_mm"]))
finally:
    srv.terminate()
