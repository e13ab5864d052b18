"""`ncgear serve` under load: concurrent clients dragging, and clients that disconnect mid-request.

Starts `BIN serve --port 0` (--bin) (the URL is its first stdout line) and drives it as the page
does (src/serve/page/app.js): each client opens the bundled G1 example, designs it cold (the
page's `redesign(false)`), then drags: the page's twelve handles, each moving the path by the
periodic Catmull–Rom blend of `points()`; every request moves one handle by up to 1 mm
(cumulative, each handle held within ±MAX_DISP_MM of where it started; a drag is five moves of one
handle), waits the page's 60 ms debounce, and sends the page's exact body — `{"points", "options"
(the form's defaults), "view": true, "spacing_mm": 140, "start": the previous answer without its
"view" and "server_ms"}` — to `POST /api/design` on a keep-alive connection, then waits for the
answer (a drag never has two requests of one page in flight).

Phases, one server process:
1. single: one client alone, SINGLE_S seconds (the reference p50/p95);
2. disconnects alone: abandoned requests (a full warm request then the socket closed before the
   answer, half a body then closed, headers only then closed, a full request then reset), one
   every DISCONNECT_EVERY_S, for DISCONNECTS_S seconds: the server CPU they cost, and a probe;
3. load: CLIENTS clients at once for DURATION_S seconds, the disconnecting client alongside.

Measured: each request's server time (`server_ms` of the answer: its computation, after its
wait for a permit at the server's gate) and wall time (send to last byte read: the wait included), per client and overall p50/p95; the server's resident memory (VmRSS), threads and
CPU time from /proc every second; every status code; connection errors; anything the server
wrote on stderr (a caught panic prints there); that it is alive at the end.

Usage: python3 scripts/serve_load.py [--bin target/release/ncgear] [--clients 4] [--duration 120]
  [--single 30] [--out FILE.json] [--check] [--max-ratio R] [--max-growth-mb M] ...

The server's counters (`GET /api/stats`) before and after each phase tell what became of the
abandoned requests: left the queue uncomputed, or designed but not drawn nor answered.

With --check the run fails (exit 1) on a 5xx, a connection error of a dragging client, a dead
server or any stderr output, an abandoned request drawn and answered, an abandoned request sent
whole costing the idle server more CPU than --max-abandoned-cost warm requests, RSS growth after
the warm-up above --max-growth-mb, p95 ratio (load / single, wall time) above --max-ratio, or the
whole run taking longer than --timeout. Standard library only; loopback only.
"""

import argparse
import http.client
import json
import math
import os
import random
import socket
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HANDLES = 12  # app.js HANDLES
DEBOUNCE_S = 0.060  # app.js DEBOUNCE_MS
MAX_STEP_MM = 1.0  # one pointer move per request: up to 1 mm
MAX_DISP_MM = 5.0  # each handle held within ±5 mm of its start (a drag, not a random walk away)
MOVES_PER_DRAG = 5
# The form's defaults as app.js `options()` sends them (index.html values; empty fields dropped).
OPTIONS = {"center": [0, 0], "tol_mm": 0.05, "limits": "on", "sense": "auto", "max_pressure_angle": 45}
SPACING_MM = 140
TICK = os.sysconf("SC_CLK_TCK")


def log(msg):
    print(f"serve_load: {msg}", flush=True)


def pct(values, q):
    """Nearest-rank percentile (as check_serve.py: the ceil(q·n)-th smallest)."""
    if not values:
        return None
    s = sorted(values)
    return s[max(0, math.ceil(q * len(s)) - 1)]


def summary(values):
    return {"n": len(values), "p50": pct(values, 0.50), "p95": pct(values, 0.95),
            "max": max(values) if values else None,
            "mean": statistics.fmean(values) if values else None}


class Page:
    """The page's edited path (app.js loadPoints, blend, points)."""

    def __init__(self, pts):
        self.orig = pts
        n = len(pts)
        s = [0.0]
        for j in range(1, n + 1):
            a, b = pts[j - 1], pts[j % n]
            s.append(s[j - 1] + math.hypot(b[0] - a[0], b[1] - a[1]))
        total = s[n] or 1
        self.u = [HANDLES * s[j] / total for j in range(n)]
        self.nodes = []
        for k in range(HANDLES):
            best = 0
            for j in range(n):
                if abs(self.u[j] - k) < abs(self.u[best] - k):
                    best = j
            self.nodes.append(best)
        for k, j in enumerate(self.nodes):
            self.u[j] = k
        self.disp = [[0.0, 0.0] for _ in range(HANDLES)]

    @staticmethod
    def blend(u):
        i = math.floor(u)
        t = u - i
        t2, t3 = t * t, t * t * t
        w = [(-t3 + 2 * t2 - t) / 2, (3 * t3 - 5 * t2 + 2) / 2, (-3 * t3 + 4 * t2 + t) / 2, (t3 - t2) / 2]
        return [(((i + o) % HANDLES + HANDLES) % HANDLES, w[q]) for q, o in enumerate((-1, 0, 1, 2))]

    def points(self):
        out = []
        for j, p in enumerate(self.orig):
            x, y = p[0], p[1]
            for k, w in self.blend(self.u[j]):
                x += w * self.disp[k][0]
                y += w * self.disp[k][1]
            out.append([x, y])
        return out


def body(points, start):
    """The page's request body, in its key order, compact as JSON.stringify writes it; `start` is
    the previous answer without `view` and `server_ms` (bytes, see `split_answer`)."""
    b = {"points": points, "options": OPTIONS, "view": True, "spacing_mm": SPACING_MM}
    head = json.dumps(b, separators=(",", ":")).encode()
    return head if start is None else head[:-1] + b',"start":' + start + b"}"


def start_of(d):
    """app.js startOf: the answer without `view` and `server_ms`."""
    s = dict(d)
    s.pop("view", None)
    s.pop("server_ms", None)
    return s


def split_answer(raw):
    """(server_ms, the start of the next request) of an answer, by cutting its bytes: the answer
    is ~0.6 MB of JSON, and parsing it and writing the start again in Python would cost the client
    ~40 ms of CPU a request — taken from the two cores the server is measured on. The server
    writes an object's keys sorted (serde_json's map), so the top level ends `…,"server_ms":N,
    "target_points":…,"verdict":…,"view":{…},"warnings":[…]}`: `warnings` is the last key (no
    string holds an unescaped quote, so its last occurrence is the top-level one), `view` the one
    before. `check_split` verifies this against a parse on each client's first answer."""
    w = raw.rindex(b',"warnings":')
    v = raw.rindex(b',"view":{', 0, w)
    s = raw.index(b',"server_ms":')
    e = raw.index(b",", s + 1)
    return float(raw[s + len(b',"server_ms":'):e]), raw[:s] + raw[e:v] + raw[w:]


def check_split(raw):
    ms, start = split_answer(raw)
    d = json.loads(raw)
    if ms != d["server_ms"] or json.loads(start) != start_of(d):
        sys.exit("serve_load: the answer's layout is not the one split_answer expects")


class Sampler(threading.Thread):
    """The server's VmRSS, threads and CPU time (utime + stime) every second."""

    def __init__(self, pid, t0):
        super().__init__(daemon=True)
        self.pid, self.t0, self.samples, self.stop = pid, t0, [], threading.Event()

    def read(self):
        try:
            status = Path(f"/proc/{self.pid}/status").read_text()
            stat = Path(f"/proc/{self.pid}/stat").read_text()
        except OSError:
            return None
        f = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
        fields = stat[stat.rindex(")") + 2:].split()
        cpu_s = (int(fields[11]) + int(fields[12])) / TICK
        return {"t": round(time.monotonic() - self.t0, 3), "rss_kb": int(f["VmRSS"].split()[0]),
                "threads": int(f["Threads"]), "cpu_s": cpu_s}

    def run(self):
        while not self.stop.is_set():
            s = self.read()
            if s:
                self.samples.append(s)
            self.stop.wait(1.0)


class Client(threading.Thread):
    """One page dragging handles until `deadline`."""

    def __init__(self, name, host, port, pts, seed, deadline, think_s, max_requests):
        super().__init__(daemon=True)
        self.max_requests = max_requests
        self.name, self.host, self.port = name, host, port
        self.page = Page(pts)
        self.rng = random.Random(seed)
        self.deadline, self.think_s = deadline, think_s
        self.server_ms, self.wall_ms, self.statuses, self.errors = [], [], {}, []
        self.cold_ms = None
        self.next_start = None  # the previous answer without view and server_ms, bytes

    def post(self, conn, data):
        t = time.monotonic()
        conn.request("POST", "/api/design", body=data, headers={"Content-Type": "application/json"})
        r = conn.getresponse()
        raw = r.read()
        return r.status, raw, 1e3 * (time.monotonic() - t)

    def move(self, step):
        """One pointer move of the handle being dragged (a new handle every MOVES_PER_DRAG)."""
        if step % MOVES_PER_DRAG == 0:
            self.k = self.rng.randrange(HANDLES)
            a = self.rng.uniform(0, 2 * math.pi)
            self.dir = [math.cos(a), math.sin(a)]
        r = self.rng.uniform(0.2, MAX_STEP_MM)
        d = self.page.disp[self.k]
        for c in range(2):
            v = d[c] + r * self.dir[c]
            if abs(v) > MAX_DISP_MM:  # turn back at the edge of the box
                self.dir[c] = -self.dir[c]
                v = d[c] + r * self.dir[c]
            d[c] = v

    def run(self):
        conn = http.client.HTTPConnection(self.host, self.port, timeout=120)
        step = 0
        sent = 0
        while time.monotonic() < self.deadline and sent < self.max_requests:
            sent += 1
            warm = self.next_start is not None
            if warm:
                self.move(step)
                step += 1
                time.sleep(self.think_s)
            data = body(self.page.points(), self.next_start)
            try:
                status, raw, wall = self.post(conn, data)
            except (OSError, http.client.HTTPException) as e:
                self.errors.append(f"{type(e).__name__}: {e}")
                conn.close()
                conn = http.client.HTTPConnection(self.host, self.port, timeout=120)
                continue
            self.statuses[status] = self.statuses.get(status, 0) + 1
            if status != 200:
                continue  # the page keeps the design on screen
            if warm:
                ms, self.next_start = split_answer(raw)
                self.server_ms.append(ms)
                self.wall_ms.append(wall)
            else:
                check_split(raw)
                self.cold_ms = wall
                _, self.next_start = split_answer(raw)
        conn.close()


class Disconnecter(threading.Thread):
    """Abandons a request every `every_s` until `deadline`, cycling through four ways."""

    KINDS = ("full request, closed before the answer", "half the body, then closed",
             "headers only, then closed", "full request, then reset (RST)")

    def __init__(self, host, port, data, deadline, every_s):
        super().__init__(daemon=True)
        self.host, self.port, self.data = host, port, data
        self.deadline, self.every_s = deadline, every_s
        self.done = {k: 0 for k in self.KINDS}
        self.errors = []

    def abandon(self, kind):
        head = (f"POST /api/design HTTP/1.1\r\nHost: {self.host}:{self.port}\r\n"
                f"Content-Type: application/json\r\nContent-Length: {len(self.data)}\r\n\r\n").encode()
        s = socket.create_connection((self.host, self.port), timeout=10)
        try:
            if kind == 0:
                s.sendall(head + self.data)
                time.sleep(0.005)
            elif kind == 1:
                s.sendall(head + self.data[: len(self.data) // 2])
                time.sleep(0.005)
            elif kind == 2:
                s.sendall(head)
            else:
                s.sendall(head + self.data)
                time.sleep(0.005)
                s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
        finally:
            s.close()

    def run(self):
        n = 0
        while time.monotonic() < self.deadline:
            kind = n % len(self.KINDS)
            try:
                self.abandon(kind)
                self.done[self.KINDS[kind]] += 1
            except OSError as e:
                self.errors.append(f"{self.KINDS[kind]}: {e}")
            n += 1
            time.sleep(self.every_s)


def stats(host, port):
    """The server's counters (`GET /api/stats`: computed, gone before computing, gone after the
    design, refused busy; the queue now)."""
    conn = http.client.HTTPConnection(host, port, timeout=30)
    conn.request("GET", "/api/stats")
    s = json.loads(conn.getresponse().read())
    conn.close()
    return s


def delta(a, b):
    return {k: b[k] - a[k] for k in ("computed", "gone_before_computing", "gone_after_design", "refused_busy")}


def probe(host, port, pts, start):
    """One warm design on a fresh connection: status, wall ms."""
    conn = http.client.HTTPConnection(host, port, timeout=60)
    t = time.monotonic()
    conn.request("POST", "/api/design", body=body(pts, start), headers={"Content-Type": "application/json"})
    r = conn.getresponse()
    r.read()
    conn.close()
    return r.status, 1e3 * (time.monotonic() - t)


def rss_at(samples, t):
    """The sample nearest to time t."""
    return min(samples, key=lambda s: abs(s["t"] - t))


def run_clients(n, host, port, pts, seconds, think_s, seed0, max_requests):
    deadline = time.monotonic() + seconds
    clients = [Client(f"client{i + 1}", host, port, pts, seed0 + i, deadline, think_s, max_requests)
               for i in range(n)]
    for c in clients:
        c.start()
    return clients


def report_clients(clients):
    statuses = {}
    for c in clients:
        for k, v in c.statuses.items():
            statuses[k] = statuses.get(k, 0) + v
    server = [x for c in clients for x in c.server_ms]
    wall = [x for c in clients for x in c.wall_ms]
    return {
        "per_client": {c.name: {"server_ms": summary(c.server_ms), "wall_ms": summary(c.wall_ms),
                                "cold_wall_ms": c.cold_ms, "statuses": c.statuses,
                                "connection_errors": c.errors} for c in clients},
        "server_ms": summary(server), "wall_ms": summary(wall),
        "statuses": statuses, "connection_errors": sum(len(c.errors) for c in clients),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=str(ROOT / "target/release/ncgear"))
    ap.add_argument("--clients", type=int, default=4)
    ap.add_argument("--duration", type=float, default=120.0, help="seconds of the load phase")
    ap.add_argument("--single", type=float, default=30.0, help="seconds of the single-client phase")
    ap.add_argument("--disconnects", type=float, default=10.0, help="seconds of the disconnects-alone phase")
    ap.add_argument("--disconnect-every", type=float, default=0.5, help="seconds between abandoned requests")
    ap.add_argument("--think-ms", type=float, default=1e3 * DEBOUNCE_S, help="pause before each drag request")
    ap.add_argument("--warmup", type=float, default=60.0, help="seconds of the load phase before memory must be flat")
    ap.add_argument("--workers", type=int, help="the server's --workers (default: its own, the cores)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", help="JSON report path")
    ap.add_argument("--check", action="store_true", help="fail on the bounds below")
    ap.add_argument("--max-ratio", type=float, default=2.0, help="p95 wall, load / single")
    ap.add_argument("--max-growth-mb", type=float, default=8.0, help="RSS growth after the warm-up")
    ap.add_argument("--max-abandoned-cost", type=float, default=1.5,
                    help="server CPU of an abandoned request sent whole, in warm requests (alone, the "
                         "server computes it at once: at most its design; the drawing and answer are saved)")
    ap.add_argument("--max-requests", type=int, default=10**9, help="requests per client per phase (a bound)")
    ap.add_argument("--timeout", type=float, default=None,
                    help="seconds for the whole run: past it the server is killed and the run fails")
    args = ap.parse_args()

    workers = ["--workers", str(args.workers)] if args.workers else []
    proc = subprocess.Popen([args.bin, "serve", "--port", "0", *workers], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    if args.timeout:
        def overdue():
            log(f"FAILED: the run took longer than {args.timeout:.0f} s (--timeout): server killed")
            proc.kill()
            os._exit(1)
        watchdog = threading.Timer(args.timeout, overdue)
        watchdog.daemon = True
        watchdog.start()
    line = proc.stdout.readline()
    url = next((w for w in line.split() if w.startswith("http://")), None)
    if not url:
        proc.kill()
        sys.exit(f"serve_load: no URL from ncgear serve: {line!r}")
    hostport = url[len("http://"):].rstrip("/")
    host, port = hostport.rsplit(":", 1)
    port = int(port)
    if host not in ("127.0.0.1", "localhost", "[::1]"):
        proc.kill()
        sys.exit(f"serve_load: not loopback: {url}")
    stderr_lines = []
    threading.Thread(target=lambda: stderr_lines.extend(proc.stderr), daemon=True).start()
    t0 = time.monotonic()
    sampler = Sampler(proc.pid, t0)
    out = {"date": time.strftime("%Y-%m-%d"), "cores": os.cpu_count(), "loadavg_before": os.getloadavg(),
           "binary": args.bin, "url": url,
           "model": {"think_ms": args.think_ms, "max_step_mm": MAX_STEP_MM, "max_disp_mm": MAX_DISP_MM,
                     "moves_per_drag": MOVES_PER_DRAG, "options": OPTIONS, "spacing_mm": SPACING_MM},
           "params": vars(args)}
    failures = []
    try:
        out["rss_kb_at_start"] = sampler.read()["rss_kb"]
        sampler.start()
        conn = http.client.HTTPConnection(host, port, timeout=60)
        conn.request("GET", "/api/examples/g1_ellipse")
        pts = json.loads(conn.getresponse().read())["points"]
        conn.close()

        # 1. One client alone.
        log(f"{url}: one client for {args.single:.0f} s")
        own0 = time.process_time()
        st0 = stats(host, port)
        cpu_single0 = sampler.read()["cpu_s"]
        single = run_clients(1, host, port, pts, args.single, args.think_ms / 1e3, args.seed, args.max_requests)
        for c in single:
            c.join()
        cpu_single1 = sampler.read()["cpu_s"]
        out["single"] = report_clients(single)
        st1 = stats(host, port)
        n_single = delta(st0, st1)["computed"]
        out["single"]["server_cpu_ms_per_request"] = 1e3 * (cpu_single1 - cpu_single0) / max(1, n_single)
        out["single"]["load_generator_cpu_s"] = time.process_time() - own0
        out["single"]["cold_wall_ms"] = single[0].cold_ms
        s = out["single"]
        log(f"single: {s['server_ms']['n']} warm designs, server p50 {s['server_ms']['p50']:.1f} / "
            f"p95 {s['server_ms']['p95']:.1f} ms, wall p50 {s['wall_ms']['p50']:.1f} / "
            f"p95 {s['wall_ms']['p95']:.1f} ms; statuses {s['statuses']}; server CPU "
            f"{s['server_cpu_ms_per_request']:.0f} ms a request")
        warm_start = single[0].next_start
        moved = single[0].page.points()

        # 2. Abandoned requests alone: what they cost the server.
        time.sleep(1.0)
        cpu0 = sampler.read()["cpu_s"]
        threads0 = sampler.read()["threads"]
        st0 = stats(host, port)
        disc = Disconnecter(host, port, body(moved, warm_start), time.monotonic() + args.disconnects,
                            args.disconnect_every)
        disc.start()
        disc.join()
        time.sleep(1.5)  # anything still computing for them finishes
        cpu1 = sampler.read()["cpu_s"]
        st1 = stats(host, port)
        n_abandoned = sum(disc.done.values())
        n_full = disc.done[Disconnecter.KINDS[0]] + disc.done[Disconnecter.KINDS[3]]
        status, wall = probe(host, port, moved, warm_start)
        out["disconnects_alone"] = {
            "abandoned": disc.done, "errors": disc.errors,
            "server_cpu_ms": 1e3 * (cpu1 - cpu0),
            "server_cpu_ms_per_abandoned": 1e3 * (cpu1 - cpu0) / max(1, n_abandoned),
            "server_cpu_ms_per_full_abandoned": 1e3 * (cpu1 - cpu0) / max(1, n_full),
            "threads_before": threads0, "threads_after": sampler.read()["threads"],
            "server_counts": delta(st0, st1),
            "probe": {"status": status, "wall_ms": wall},
        }
        d = out["disconnects_alone"]
        log(f"disconnects alone: {n_abandoned} abandoned requests ({n_full} sent whole) cost the server "
            f"{d['server_cpu_ms']:.0f} ms CPU ({d['server_cpu_ms_per_abandoned']:.1f} ms each); "
            f"probe after: {status} in {wall:.0f} ms; threads {threads0} → {d['threads_after']}; "
            f"server counts {d['server_counts']}")

        # 3. The load: N clients and the disconnecting client.
        log(f"{args.clients} clients for {args.duration:.0f} s, an abandoned request every "
            f"{args.disconnect_every} s alongside")
        t_load = time.monotonic() - t0
        own0 = time.process_time()
        st0 = stats(host, port)
        clients = run_clients(args.clients, host, port, pts, args.duration, args.think_ms / 1e3, args.seed + 100,
                              args.max_requests)
        disc = Disconnecter(host, port, body(moved, warm_start), time.monotonic() + args.duration,
                            args.disconnect_every)
        disc.start()
        for c in clients:
            c.join()
        disc.join()
        t_end = time.monotonic() - t0
        own1 = time.process_time()
        time.sleep(1.5)
        st1 = stats(host, port)
        status, wall = probe(host, port, moved, warm_start)
        conn = http.client.HTTPConnection(host, port, timeout=10)
        conn.request("GET", "/api/examples")
        alive = conn.getresponse().status == 200 and proc.poll() is None
        conn.close()
        sampler.stop.set()
        sampler.join()
        out["load"] = report_clients(clients)
        out["load"]["abandoned"] = disc.done
        out["load"]["load_generator_cpu_s"] = own1 - own0
        out["load"]["abandon_errors"] = disc.errors
        out["load"]["probe_after"] = {"status": status, "wall_ms": wall}
        out["load"]["server_counts"] = delta(st0, st1)
        samples = [x for x in sampler.samples if x["t"] >= t_load]
        warm_t = t_load + min(args.warmup, args.duration / 2)
        at_start, at_warm = rss_at(samples, t_load), rss_at(samples, warm_t)
        at_end = rss_at(samples, t_end)
        after = [x for x in samples if warm_t <= x["t"] <= t_end]
        out["memory"] = {
            "rss_kb_server_start": out.pop("rss_kb_at_start"),
            "rss_kb_load_start": at_start["rss_kb"],
            "rss_kb_after_warmup": at_warm["rss_kb"], "warmup_s": warm_t - t_load,
            "rss_kb_end": at_end["rss_kb"],
            "rss_kb_max_after_warmup": max(x["rss_kb"] for x in after),
            "growth_after_warmup_kb": max(x["rss_kb"] for x in after) - at_warm["rss_kb"],
            "threads_max": max(x["threads"] for x in samples),
            "threads_end": samples[-1]["threads"],
            "load_cpu_s": at_end["cpu_s"] - at_start["cpu_s"],
        }
        out["samples"] = sampler.samples
        out["alive"] = alive
        out["stderr"] = stderr_lines[:50]
        r1, rn = out["single"]["wall_ms"]["p95"], out["load"]["wall_ms"]["p95"]
        s1, sn = out["single"]["server_ms"]["p95"], out["load"]["server_ms"]["p95"]
        out["ratio_p95_wall"] = rn / r1
        out["ratio_p95_server"] = sn / s1
        L, m = out["load"], out["memory"]
        for name, c in L["per_client"].items():
            log(f"{name}: {c['server_ms']['n']} warm designs, server p50 {c['server_ms']['p50']:.1f} / "
                f"p95 {c['server_ms']['p95']:.1f} ms, wall p50 {c['wall_ms']['p50']:.1f} / "
                f"p95 {c['wall_ms']['p95']:.1f} ms; statuses {c['statuses']}")
        log(f"{args.clients} clients: {L['server_ms']['n']} warm designs "
            f"({L['server_ms']['n'] / args.duration:.1f}/s), server p50 {L['server_ms']['p50']:.1f} / p95 "
            f"{sn:.1f} ms, wall p50 {L['wall_ms']['p50']:.1f} / p95 {rn:.1f} ms; p95 ratio to one client: "
            f"wall {out['ratio_p95_wall']:.2f}, server {out['ratio_p95_server']:.2f}")
        log(f"statuses {L['statuses']}, connection errors {L['connection_errors']}, abandoned "
            f"{sum(disc.done.values())} (server counts {L['server_counts']}); probe after: {status} in "
            f"{wall:.0f} ms; alive {alive}")
        log(f"RSS: server start {m['rss_kb_server_start'] / 1024:.1f} MB, load start "
            f"{m['rss_kb_load_start'] / 1024:.1f} MB, after {m['warmup_s']:.0f} s "
            f"{m['rss_kb_after_warmup'] / 1024:.1f} MB, end {m['rss_kb_end'] / 1024:.1f} MB, max after "
            f"warm-up {m['rss_kb_max_after_warmup'] / 1024:.1f} MB (growth "
            f"{m['growth_after_warmup_kb'] / 1024:.1f} MB); threads max {m['threads_max']}, end "
            f"{m['threads_end']}; server CPU {m['load_cpu_s']:.1f} s over {args.duration:.0f} s (this "
            f"script's: {L['load_generator_cpu_s']:.1f} s)")
        if stderr_lines:
            log(f"server stderr: {stderr_lines[:5]}")

        # The verdict.
        fives = {k: out["single"]["statuses"].get(k, 0) + L["statuses"].get(k, 0)
                 for k in set(out["single"]["statuses"]) | set(L["statuses"]) if k >= 500}
        if fives:
            failures.append(f"5xx answers: {fives}")
        if out["single"]["connection_errors"] or L["connection_errors"]:
            failures.append(f"connection errors: {out['single']['connection_errors'] + L['connection_errors']}")
        if not alive or stderr_lines:
            failures.append(f"server alive {alive}, stderr {stderr_lines[:3]}")
        if status != 200 or out["disconnects_alone"]["probe"]["status"] != 200:
            failures.append("a probe after the abandoned requests failed")
        d = out["disconnects_alone"]
        bound = args.max_abandoned_cost * out["single"]["server_cpu_ms_per_request"]
        if d["server_cpu_ms_per_full_abandoned"] > bound:
            failures.append(f"an abandoned request sent whole costs the server "
                            f"{d['server_cpu_ms_per_full_abandoned']:.0f} ms CPU (bound {bound:.0f}: "
                            f"{args.max_abandoned_cost} × a warm request's)")
        answered = d["server_counts"]["computed"] - d["server_counts"]["gone_after_design"]
        if answered:
            failures.append(f"{answered} abandoned requests were drawn and answered")
        lc = L["server_counts"]
        answered, read = lc["computed"] - lc["gone_after_design"], sum(L["statuses"].values())
        if answered != read:
            # Each computed and answered request is one a dragging client read: none of the
            # abandoned ones was drawn and answered.
            failures.append(f"{answered} designs computed and answered under load, the clients read {read}")
        if m["growth_after_warmup_kb"] > 1024 * args.max_growth_mb:
            failures.append(f"RSS grew {m['growth_after_warmup_kb'] / 1024:.1f} MB after the warm-up "
                            f"(bound {args.max_growth_mb} MB)")
        if out["ratio_p95_wall"] > args.max_ratio:
            failures.append(f"p95 wall ratio {out['ratio_p95_wall']:.2f} (bound {args.max_ratio})")
        out["failures"] = failures
    finally:
        sampler.stop.set()
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
    if args.out:
        Path(args.out).write_text(json.dumps(out, indent=1, default=str))
        log(f"report: {args.out}")
    if failures:
        for f in failures:
            log(("FAILED: " if args.check else "not met: ") + f)
        if args.check:
            sys.exit(1)
    else:
        log("every bound met")


if __name__ == "__main__":
    main()
