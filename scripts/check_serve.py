"""The interactive designer (`ncgear serve`) in a real browser, and its API under abuse.

Drives Debian's Chromium with Playwright (PyPI): the page opens on a bundled example with no
console error; a trajectory loaded through `open-file` shows the l1, l3 and deviation that
`ncgear design` prints for the same file; dragging a handle re-designs (new deviation, server
time shown); a module gives teeth; the design.json download equals the CLI's design of the same
points; the loads panel on that design draws the torque chart and shows numbers, its peak carrier
torque that of `ncgear loads` on the CLI's design (within 1 %), and the endpoint's answer on the
page's own design that of `ncgear loads` on it; a DXF of several loops is refused naming its
layers, then read from the layer typed in the page as the CLI reads it; a malformed upload shows
its error and the page keeps working. Then the API alone: warm edits of a bundled example a fraction of a millimetre to
millimetres off it (p50/p95 server time printed, not asserted: speed lives in the benchmarks), the
loads of a design with a bad scene (a negative arm mass named by its key), an oversized body, and a
few hundred malformed requests (seeded) — every answer JSON, never a 5xx, the server alive after
each.

Usage: python scripts/check_serve.py NCGEAR_BIN CHROMIUM [SCREENSHOT_DIR]
"""

import json
import math
import random
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

from playwright.sync_api import sync_playwright

ROOT = Path(__file__).resolve().parent.parent
BIN, CHROMIUM = sys.argv[1], sys.argv[2]
SHOTS = Path(sys.argv[3]) if len(sys.argv) > 3 else None
# A trajectory the page has not bundled, loaded through the file input.
UPLOAD = ROOT / "assets/cases/designer_odd2.csv"
# The page's default loads scene (GET /api/loads/scene reads the same file).
ROTOR = ROOT / "assets/loads/rotor.toml"


def fail(msg):
    print(f"check_serve: FAILED: {msg}", file=sys.stderr)
    sys.exit(1)


def request(url, method="GET", body=None, raw=None):
    data = raw if raw is not None else (None if body is None else json.dumps(body).encode())
    req = urllib.request.Request(url, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    try:
        with urllib.request.urlopen(req, timeout=60) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.read()


def cli_design(points_or_file, *flags):
    """`ncgear design … --json` on a file or on points written to a CSV."""
    with tempfile.TemporaryDirectory() as tmp:
        path = points_or_file
        if not isinstance(points_or_file, Path):
            path = Path(tmp) / "points.csv"
            path.write_text("".join(f"{x!r},{y!r}\n" for x, y in points_or_file))
        out = subprocess.run([BIN, "design", str(path), "--out", str(Path(tmp) / "out"), "--json",
                              "--accept-failed", *flags], capture_output=True, text=True)
        if out.returncode != 0:
            fail(f"ncgear design {path} {flags}: {out.stderr}")
        return json.loads(out.stdout)


def cli_loads(design_file):
    """`ncgear loads --json` on assets/loads/rotor.toml naming `design_file` (a design.json)."""
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "scene.toml"
        scene.write_text(f"design = {json.dumps(str(Path(design_file).resolve()))}\n" + ROTOR.read_text())
        out = subprocess.run([BIN, "loads", str(scene), "--out", str(Path(tmp) / "loads"), "--json",
                              "--accept-failed"], capture_output=True, text=True)
        if out.returncode != 0:
            fail(f"ncgear loads on {design_file}: {out.stderr}")
        return json.loads(out.stdout)


def start_server():
    proc = subprocess.Popen([BIN, "serve", "--port", "0"], stdout=subprocess.PIPE, text=True)
    line = proc.stdout.readline()
    url = line.split()[2] if "http://" in line else None
    if not url:
        fail(f"no URL from ncgear serve: {line!r}")
    return proc, url


def drag(page, target, dx, dy):
    """Drags `target` by five steps of (dx, dy) pixels, then waits for the page to be ready."""
    box = target.bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 6):
        page.mouse.move(x + dx * k, y + dy * k)
    page.mouse.up()
    page.wait_for_timeout(100)
    wait_ready(page)


def wait_ready(page, timeout_ms=60000):
    page.wait_for_function(
        "() => { const s = document.querySelector('[data-testid=status]').textContent;"
        " return s !== 'designing' && s !== 'loading'; }", timeout=timeout_ms)
    status = page.get_by_test_id("status").text_content()
    if status != "ready":
        fail(f"the page says {status!r} instead of ready")


def text(page, testid):
    return page.get_by_test_id(testid).text_content()


def browser_checks(url):
    errors = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=[
            "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync"])
        page = browser.new_page(viewport={"width": 1400, "height": 900}, accept_downloads=True)
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(url)
        wait_ready(page)
        if not page.get_by_test_id("handle-0").count():
            fail("no handle on the bundled example")
        if errors:
            fail(f"console errors on opening the page: {errors}")
        # The agronomic figures at the page's plant spacing (140 mm): the spacing identity.
        spacing = text(page, "feature-spacing-mm")
        if spacing != "140.0 mm":
            fail(f"plant spacing 140 mm set, the page reports {spacing!r}")
        print(f"check_serve: opened on g1_ellipse; taking angle {text(page, 'feature-take-deg')}, "
              f"pushing angle {text(page, 'feature-push-deg')}, height {text(page, 'feature-height-mm')}")
        if SHOTS:
            SHOTS.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(SHOTS / "designer.png"))

        # A trajectory nobody bundled, through the file input: the CLI's numbers.
        page.get_by_test_id("open-file").set_input_files(str(UPLOAD))
        wait_ready(page)
        want = cli_design(UPLOAD)
        got = [text(page, t) for t in ("l1-mm", "l3-mm", "deviation-mm")]
        exp = [f"{want['l1_mm']:.6f}", f"{want['l3_mm']:.6f}", f"{want['roundtrip']['max_deviation_mm']:.4f}"]
        if got != exp:
            fail(f"{UPLOAD.name}: the page shows l1, l3, deviation {got}, ncgear design {exp}")
        print(f"check_serve: {UPLOAD.name} loaded: l1 {got[0]} mm, l3 {got[1]} mm, deviation {got[2]} mm (as the CLI)")
        # A warning about the deviation shows where on the path it holds.
        page.locator(".warnings li.has-arc").first.click()
        arc = page.get_by_test_id("warning-arc").locator("circle").count()
        if arc == 0:
            fail("clicking the deviation warning highlights no point of the path")
        print(f"check_serve: the deviation warning highlights {arc} points of the path")

        # Drag a handle: a new design within a second, its server time shown.
        before = text(page, "deviation-mm")
        t0 = time.time()
        drag(page, page.get_by_test_id("handle-3"), 4, -3)
        after, server_ms = text(page, "deviation-mm"), float(text(page, "server-ms"))
        if after == before:
            fail(f"dragging handle-3 left the deviation at {before} mm")
        print(f"check_serve: drag re-designed in {time.time() - t0:.2f} s wall "
              f"(server {server_ms:.0f} ms): deviation {before} → {after} mm")
        if time.time() - t0 > 1.5:
            fail("the drag took more than a second to show")

        # A module: teeth on the gears, and the download is the CLI's design of these points.
        page.get_by_test_id("module").fill("2")
        page.get_by_test_id("module").dispatch_event("change")
        wait_ready(page, 120000)
        teeth = text(page, "teeth")
        if not teeth.startswith("z = "):
            fail(f"module 2: the page shows teeth {teeth!r}")
        if SHOTS:
            page.evaluate("window.scrollTo(0, 0)")
            page.screenshot(path=str(SHOTS / "designer_teeth.png"))
        points = page.evaluate("points()")
        with page.expect_download() as dl:
            page.get_by_test_id("download-json").click()
        downloaded = json.loads(Path(dl.value.path()).read_text())
        want = cli_design(points, "--module", "2")
        for key in ("l1_mm", "l3_mm", "center_distance_mm", "needle_angle_deg"):
            if downloaded[key] != want[key]:
                fail(f"download-json {key} = {downloaded[key]!r}, ncgear design {want[key]!r}")
        for a, b in ((downloaded["roundtrip"], want["roundtrip"]), (downloaded["teeth"]["mesh"], want["teeth"]["mesh"])):
            if json.dumps(a, sort_keys=True) != json.dumps(b, sort_keys=True):
                fail("download-json differs from ncgear design in its round trip or mesh check")
        print(f"check_serve: module 2 → {teeth}; design.json download equals ncgear design --module 2")

        # A malformed upload: its error in the page, which keeps working.
        page.get_by_test_id("open-file").set_input_files(
            files=[{"name": "broken.csv", "mimeType": "text/csv", "buffer": b"x,y\n1,2\nnot,a number\n"}])
        page.wait_for_function("() => document.querySelector('[data-testid=status]').classList.contains('error')")
        err = text(page, "status")
        if "broken.csv" not in err:
            fail(f"the malformed upload's error does not name the file: {err!r}")
        # A drawing holding several loops: refused naming its layers, then read from the layer
        # typed in the page's field — the CLI's points and numbers for the same file and layer.
        drawing = ROOT / "assets/drawings/g1_layers.dxf"
        page.get_by_test_id("open-file").set_input_files(str(drawing))
        page.wait_for_function("() => document.querySelector('[data-testid=status]').classList.contains('error')")
        several = text(page, "status")
        if 'layer "TARGET": 1 loop' not in several or "layer or id" not in several or "--layer" in several:
            fail(f"a drawing of several loops: the page says {several!r}")
        page.get_by_test_id("drawing-pick").fill("TARGET")
        page.get_by_test_id("drawing-pick").dispatch_event("change")
        wait_ready(page, 120000)
        module = page.get_by_test_id("module").input_value().strip()
        want = cli_design(drawing, "--layer", "TARGET", *(["--module", module] if module else []))
        got = [text(page, t) for t in ("l1-mm", "l3-mm")]
        exp = [f"{want['l1_mm']:.6f}", f"{want['l3_mm']:.6f}"]
        if got != exp or page.evaluate("points().length") != len(want["target_points"]):
            fail(f"{drawing.name} on layer TARGET: the page shows l1, l3 {got}, ncgear design {exp}")
        page.get_by_test_id("drawing-pick").fill("")
        print(f"check_serve: {drawing.name}: several loops named in the page; layer TARGET → l1 {got[0]} mm, l3 {got[1]} mm (as the CLI)")
        # A synthesis spec through the poses panel: the arm and the poses on the gears.
        page.get_by_test_id("open-poses").set_input_files(str(ROOT / "assets/synthesis/g1_five_poses.toml"))
        wait_ready(page)
        arm = text(page, "synthesis-arm")
        if "l1 = 90.000 mm, l3 = 170.000 mm" not in arm:
            fail(f"the poses panel shows {arm!r}")
        errs = [text(page, f"pose-error-{k}") for k in range(5)]
        if any(float(e.split()[0]) > 0.01 for e in errs) or page.get_by_test_id("pose").count() != 5:
            fail(f"the five G1 poses on the synthesised gears: {errs}")
        print(f"check_serve: poses panel: {arm}; pose errors {errs}")
        # Three of the poses (a family), then pose 1 dragged: synthesised again through the moved
        # pose, which the new gears pass.
        g1 = (ROOT / "assets/synthesis/g1_five_poses.toml").read_text()
        head, *poses = g1.split("[[pose]]")
        poses[-1] = poses[-1].split("[targets]")[0]
        three = head + "".join("[[pose]]" + poses[k] for k in (0, 2, 4))
        page.get_by_test_id("open-poses").set_input_files(
            files=[{"name": "three.toml", "mimeType": "text/plain", "buffer": three.encode()}])
        wait_ready(page)
        arm0, cx0 = text(page, "synthesis-arm"), float(page.get_by_test_id("pose").nth(1).get_attribute("cx"))
        drag(page, page.get_by_test_id("pose").nth(1), 4, -2)
        arm1, cx1 = text(page, "synthesis-arm"), float(page.get_by_test_id("pose").nth(1).get_attribute("cx"))
        errs = [text(page, f"pose-error-{k}") for k in range(3)]
        if arm1 == arm0 or not cx1 > cx0 + 1.0 or any(float(e.split()[0]) > 0.05 for e in errs):
            fail(f"dragging pose 1: {arm0!r} → {arm1!r}, tip x {cx0} → {cx1} mm, errors {errs}")
        print(f"check_serve: pose 1 dragged {cx1 - cx0:.1f} mm: {arm1}; pose errors {errs}")
        # Target bands alone through the same panel: every band met on the gears, no pose drawn.
        page.get_by_test_id("open-poses").set_input_files(str(ROOT / "assets/synthesis/rice_targets.toml"))
        wait_ready(page)
        arm = text(page, "synthesis-arm")
        bands = {k: text(page, f"target-{k}")
                 for k in ("take_angle_deg", "push_angle_deg", "height_mm", "hole_width_mm")}
        if "(targets)" not in arm or any("missed" in v for v in bands.values()) \
                or page.get_by_test_id("pose").count() != 0:
            fail(f"the rice target bands in the poses panel: {arm!r}, {bands}")
        print(f"check_serve: target bands alone: {arm}; {bands}")
        # An oversized file: refused in the page with its size, before any upload.
        page.get_by_test_id("open-file").set_input_files(
            files=[{"name": "huge.csv", "mimeType": "text/csv", "buffer": b"1.0,2.0\n" * (9 << 17)}])
        page.wait_for_function("() => document.querySelector('[data-testid=status]').textContent.includes('huge.csv')")
        huge = text(page, "status")
        if "8 MB" not in huge:
            fail(f"the oversized upload's error does not say the limit: {huge!r}")
        print(f"check_serve: oversized upload → {huge!r}")
        page.get_by_test_id("module").fill("")
        page.get_by_test_id("example").select_option("g1_ellipse")
        wait_ready(page)
        print(f"check_serve: malformed upload → {err!r}; the page still designs")
        # The loads of the bundled G1 example: without a module the loads alone (the page says
        # to set a module to rate the teeth), then with module 2 rated, as `ncgear loads`.
        page.get_by_test_id("loads-button").click()
        page.wait_for_function(
            "() => document.querySelector('[data-testid=loads-status]').textContent === 'ready'", timeout=60000)
        note = text(page, "loads-note-0")
        if text(page, "safety-h") != "–" or "set a module" not in note:
            fail(f"loads without a module: S_H {text(page, 'safety-h')!r}, note {note!r}")
        print(f"check_serve: loads without a module: peak carrier torque {text(page, 'carrier-torque-peak')} N·m; {note!r}")
        page.get_by_test_id("module").fill("2")
        page.get_by_test_id("module").dispatch_event("change")
        wait_ready(page, 120000)
        if "stale" not in (page.get_by_test_id("loads-panel").get_attribute("class") or ""):
            fail("the loads of the previous design are not marked stale after a new design")
        loads_checks(page, url, page.evaluate("points()"))
        browser.close()
    # The one error allowed: Chromium's network log of the malformed upload's deliberate 400.
    errors = [e for e in errors if "status of 400" not in e]
    if errors:
        fail(f"console errors: {errors}")


def loads_checks(page, url, points):
    """The loads panel on the design on screen (module 2) against `ncgear loads`."""
    # The click leaves the module field: its change designs again, and the loads wait for it.
    page.get_by_test_id("loads-button").click()
    page.wait_for_function(
        "() => !['computing', 'waiting for the design'].includes("
        "document.querySelector('[data-testid=loads-status]').textContent)", timeout=120000)
    status = text(page, "loads-status")
    if status != "ready":
        fail(f"the loads panel says {status!r}")
    chart = page.get_by_test_id("loads-chart")
    if not (chart.is_visible() and chart.get_by_test_id("loads-carrier").count() == 1
            and chart.get_by_test_id("loads-planet").count() == 1):
        fail("no carrier and planet mesh torque curves in loads-chart")
    shown = {}
    for t in ("carrier-torque-peak", "mean-power", "safety-h", "safety-f", "life-h"):
        try:
            shown[t] = float(text(page, t))
        except ValueError:
            fail(f"{t} shows {text(page, t)!r}, not a number")
    reversals = text(page, "reversals")
    try:
        angles = [float(a.strip().rstrip("°")) for a in reversals.split(",")]
    except ValueError:
        fail(f"reversals shows {reversals!r}")
    if chart.get_by_test_id("loads-reversal").count() != len(angles):
        fail(f"{len(angles)} reversals listed, {chart.get_by_test_id('loads-reversal').count()} marked")
    # `ncgear design --module 2` on the points on screen, then `ncgear loads` on its design.json
    # with the bundled scene: the peak carrier torque the page shows, within 1 %.
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "points.csv"
        csv.write_text("".join(f"{x!r},{y!r}\n" for x, y in points))
        out = subprocess.run([BIN, "design", str(csv), "--out", str(Path(tmp) / "d"), "--module", "2",
                              "--accept-failed"], capture_output=True, text=True)
        if out.returncode != 0:
            fail(f"ncgear design --module 2: {out.stderr}")
        cli = cli_loads(Path(tmp) / "d" / "design.json")
    want = cli["summary"]["carrier_torque_peak_Nm"]
    if abs(shown["carrier-torque-peak"] - want) > 0.01 * abs(want):
        fail(f"the page shows a peak carrier torque of {shown['carrier-torque-peak']} N·m, "
             f"ncgear design --module 2 + ncgear loads {want} N·m")
    for key, t in (("min_S_H", "safety-h"), ("min_S_F", "safety-f")):
        if abs(shown[t] - cli["summary"][key]["value"]) > 0.01 * cli["summary"][key]["value"]:
            fail(f"{t} shows {shown[t]}, ncgear loads {cli['summary'][key]['value']}")
    # The endpoint on the page's own design and scene: `ncgear loads` on that design.json.
    design, scene = page.evaluate("startOf(state.design)"), page.evaluate("loadsScene()")
    status, body = request(url + "api/loads", "POST", {"design": design, "scene": scene})
    if status != 200:
        fail(f"POST /api/loads with the page's design answered {status}: {body[:300]!r}")
    api = json.loads(body)
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "design.json").write_text(json.dumps(design))
        own = cli_loads(Path(tmp) / "design.json")
    for key in ("carrier_torque_peak_Nm", "mean_power_W", "reversals_deg", "life_h"):
        a, b = api["summary"][key], own["summary"][key]
        if json.dumps(a) != json.dumps(b):
            fail(f"POST /api/loads summary.{key} = {a!r}, ncgear loads on the same design.json {b!r}")
    if api["summary"]["min_S_H"] != own["summary"]["min_S_H"]:
        fail(f"POST /api/loads min_S_H {api['summary']['min_S_H']}, ncgear loads {own['summary']['min_S_H']}")
    print(f"check_serve: loads (module 2, {scene['operation']['carrier_rpm']} r/min, "
          f"{scene['operation']['arms']} arms): peak carrier torque {shown['carrier-torque-peak']} N·m "
          f"(ncgear loads {want:.4f}), mean power {shown['mean-power']} W, reversals {reversals}, "
          f"S_H {shown['safety-h']}, S_F {shown['safety-f']}, life {shown['life-h']} h; the endpoint "
          f"on the page's design equals ncgear loads on it")
    if SHOTS:
        page.get_by_test_id("loads-panel").screenshot(path=str(SHOTS / "designer_loads.png"))
    # One arm instead of two: the panel computes again, the torque changes.
    page.get_by_test_id("loads-arms").fill("1")
    page.get_by_test_id("loads-arms").dispatch_event("change")
    page.wait_for_function(
        "() => document.querySelector('[data-testid=loads-status]').textContent === 'ready'"
        f" && document.querySelector('[data-testid=carrier-torque-peak]').textContent !== '{text(page, 'carrier-torque-peak')}'",
        timeout=60000)
    print(f"check_serve: one arm → peak carrier torque {text(page, 'carrier-torque-peak')} N·m")
    page.get_by_test_id("loads-arms").fill("2")
    page.get_by_test_id("loads-arms").dispatch_event("change")
    page.wait_for_function(
        "() => document.querySelector('[data-testid=loads-status]').textContent === 'ready'", timeout=60000)


def api_checks(url):
    status, body = request(url + "api/examples/g1_ellipse")
    pts = json.loads(body)["points"]
    status, body = request(url + "api/design", "POST", {"points": pts})
    cur = json.loads(body)
    rng = random.Random(7)
    times = []
    base = [p[:] for p in pts]
    for _ in range(60):
        c, amp, w = rng.randrange(len(pts)), rng.uniform(-1.0, 1.0), rng.uniform(5, 25)
        for j in range(len(pts)):
            dj = min(abs(j - c), len(pts) - abs(j - c))
            f = amp * math.exp(-(dj / w) ** 2)
            base[j][0] += 0.6 * f
            base[j][1] += 0.4 * f
        status, body = request(url + "api/design", "POST", {"points": base, "start": cur, "view": True})
        if status != 200:
            fail(f"warm edit answered {status}: {body[:200]!r}")
        d = json.loads(body)
        times.append(d["server_ms"])
        del d["view"], d["server_ms"]
        cur = d
    times.sort()
    print(f"check_serve: 60 warm edits of g1_ellipse (each a bump of ≤ 1 mm, cumulative): server time "
          f"p50 {statistics.median(times):.1f} ms, p95 {times[int(0.95 * len(times)) - 1]:.1f} ms")

    # The loads of a toothed design: the bundled scene, then a negative arm mass named by its key.
    status, body = request(url + "api/design", "POST", {"points": pts, "options": {"module": 2}})
    toothed = json.loads(body)
    status, body = request(url + "api/loads/scene")
    scene = json.loads(body)["scene"]
    status, body = request(url + "api/loads", "POST", {"design": toothed, "scene": scene})
    if status != 200:
        fail(f"POST /api/loads answered {status}: {body[:300]!r}")
    loads = json.loads(body)
    if not (loads["summary"]["carrier_torque_peak_Nm"] > 0 and loads["rating"]["min_S_H"]["value"] > 0):
        fail(f"POST /api/loads: {loads['summary']}")
    bad = json.loads(json.dumps(scene))
    bad["arm"]["mass_kg"] = -0.5
    status, body = request(url + "api/loads", "POST", {"design": toothed, "scene": bad})
    e = json.loads(body)
    if status != 400 or e.get("field") != "scene.arm.mass_kg" or "arm.mass_kg" not in e.get("error", ""):
        fail(f"a negative arm mass answered {status} {e}")
    print(f"check_serve: POST /api/loads → peak carrier torque {loads['summary']['carrier_torque_peak_Nm']:.3f} N·m; "
          f"a negative arm mass → 400 {e['field']}: {e['error']}")
    # Seeded abuse of the loads: bad scenes and designs, every answer JSON and never a 5xx.
    rng = random.Random(13)
    for k in range(60):
        sc = json.loads(json.dumps(scene))
        table = rng.choice(["operation", "arm", "gears", "needle", "material", "rating", "bogus", "design"])
        if table in ("bogus", "design"):
            sc[table] = rng.choice(["../../etc/passwd", 1, None, {}])
        elif rng.random() < 0.2:
            sc[table] = rng.choice(bad_values_loads())
        else:
            key = rng.choice(list(sc[table].keys()) + ["bogus"])
            sc[table][key] = rng.choice(bad_values_loads())
        body = {"design": rng.choice([toothed, toothed, {}, None, [1, 2]]), "scene": sc}
        if rng.random() < 0.1:
            body = {"points": pts[::7], "options": {"module": rng.choice([None, 2, -1])}, "scene": sc}
        status, raw = request(url + "api/loads", "POST", body)
        if status >= 500 and status != 503:
            fail(f"loads request {k} ({table}) answered {status}: {raw[:200]!r}")
        if status != 200:
            try:
                e = json.loads(raw)
                assert isinstance(e.get("error"), str) and e["error"]
            except Exception:
                fail(f"loads request {k}: a {status} without a JSON error: {raw[:200]!r}")
    print("check_serve: 60 malformed loads requests answered with JSON errors (no 5xx)")

    status, body = request(url + "api/design", "POST", raw=b"[" + b"1," * (5 << 20) + b"1]")
    if status != 413 or "error" not in json.loads(body):
        fail(f"an oversized body got {status}")
    # Seeded abuse: malformed JSON, wrong types, non-finite and absurd values, unknown paths.
    rng = random.Random(11)
    bad_values = [None, "x", -1, 0, 1e308, [], {}, [[0, 0]], [[float("nan"), 1]] * 10, True]
    for k in range(300):
        kind = k % 6
        if kind == 0:
            status, body = request(url + "api/design", "POST", raw=bytes(rng.randrange(256) for _ in range(rng.randrange(1, 200))))
        elif kind == 1:
            status, body = request(url + "api/design", "POST", {"points": rng.choice(bad_values)})
        elif kind == 2:
            opt = rng.choice(["tol_mm", "order", "module", "center", "max_pressure_angle", "min_concave_radius", "refine", "limits", "bogus"])
            status, body = request(url + "api/design", "POST", {"points": pts, "options": {opt: rng.choice(bad_values + [1e-9, 500, "off"])}})
        elif kind == 3:
            status, body = request(url + "api/parse", "POST", {"name": rng.choice(["a.csv", "b.json", "c.txt", "../../etc/passwd"]), "text": rng.choice(["", "1,2", "{", "nan,nan\n" * 20, "x,y\n" + "1,1\n" * 30])})
        elif kind == 4:
            status, body = request(url + rng.choice(["api/export", "api/nothing", "../../etc/passwd", "assets/../Cargo.toml", "api/examples/%00"]), rng.choice(["GET", "POST", "PUT"]), {"points": pts, "format": rng.choice(["json", "exe", "dxf", None])})
        else:
            noisy = [[x + rng.gauss(0, 5), y + rng.gauss(0, 5)] for x, y in pts[:: rng.choice([1, 7, 40])]]
            status, body = request(url + "api/design", "POST", {"points": noisy, "options": {"order": rng.choice([None, 2, 60])}})
        if status >= 500 and status != 503:
            fail(f"request {k} (kind {kind}) answered {status}: {body[:200]!r}")
        if status != 200:
            try:
                e = json.loads(body)
                assert isinstance(e.get("error"), str) and e["error"]
            except Exception:
                fail(f"request {k} (kind {kind}): a {status} without a JSON error: {body[:200]!r}")
    status, _ = request(url + "api/examples")
    if status != 200:
        fail("the server stopped answering after the malformed requests")
    print("check_serve: 300 malformed requests answered with JSON errors (no 5xx); oversized body → 413")


def bad_values_loads():
    return [None, "x", "auto", -1, 0, 0.5, 9, 1e308, -1e-300, 3001, [], {}, [0.0, 0.0], [1, 0], [[0, 0, 0]],
            "planting", "steel", "gold", True]


def main():
    proc, url = start_server()
    try:
        api_checks(url)
        browser_checks(url)
    finally:
        proc.terminate()
        proc.wait(timeout=10)
    print("check_serve: passed")


if __name__ == "__main__":
    main()
