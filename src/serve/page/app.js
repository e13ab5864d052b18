// ncgear designer: the page. It draws what POST /api/design answers and edits the target as
// the loaded points plus a smooth displacement: HANDLES control points at equal arc length, each
// moving the path by a periodic Catmull–Rom (interpolating) blend, so a handle follows the pointer
// exactly and the edit stays smooth. Plain JS, no build step, no library.
"use strict";

const HANDLES = 12;
const DEBOUNCE_MS = 60;
const SVG_NS = "http://www.w3.org/2000/svg";
const $ = (id) => document.getElementById(id);

const state = {
  name: "", orig: [], u: [], nodes: [], disp: [],
  design: null, phiIndex: 0, playing: false,
  view: { cx: 0, cy: 0, w: 400 },
  undo: [], redo: [], controller: null, timer: null, clock: null, synthesis: null, spec: null, highlight: null,
  // The loads panel: the bundled scene (the defaults), the last answer and the design it is of.
  loadsScene: null, loads: null, loadsOf: null, loadsSent: null, loadsController: null, loadsPending: false,
};

// ---- status --------------------------------------------------------------------------------
function setStatus(text, kind) {
  const s = $("status");
  s.textContent = text;
  s.className = "status" + (kind ? " " + kind : "");
  $("cancel").disabled = kind !== "busy";
  // Progress of a running request: the seconds it has taken so far, beside the status.
  clearInterval(state.clock);
  $("elapsed").textContent = "";
  if (kind === "busy") {
    const t0 = performance.now();
    state.clock = setInterval(() => { $("elapsed").textContent = ((performance.now() - t0) / 1000).toFixed(1) + " s"; }, 100);
  }
}

async function api(path, body, signal) {
  const r = await fetch(path, body === undefined ? { signal } : {
    method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify(body), signal,
  });
  if (!r.ok) {
    let msg = r.status + " " + r.statusText;
    try { const e = await r.json(); msg = e.error + (e.field ? " (" + e.field + ")" : ""); } catch (_) { /* not JSON */ }
    throw new Error(msg);
  }
  return r;
}

// ---- the edited path -------------------------------------------------------------------------
function loadPoints(name, points) {
  state.name = name;
  state.orig = points;
  const n = points.length;
  const s = [0];
  for (let j = 1; j <= n; j++) {
    const a = points[j - 1], b = points[j % n];
    s.push(s[j - 1] + Math.hypot(b[0] - a[0], b[1] - a[1]));
  }
  const total = s[n] || 1;
  state.u = points.map((_, j) => HANDLES * s[j] / total);
  state.nodes = [];
  for (let k = 0; k < HANDLES; k++) {
    let best = 0;
    for (let j = 0; j < n; j++) if (Math.abs(state.u[j] - k) < Math.abs(state.u[best] - k)) best = j;
    state.nodes.push(best);
  }
  // Node k sits at its point's own parameter: the blend is 1 there.
  state.nodes.forEach((j, k) => { state.u[j] = k; });
  state.disp = Array.from({ length: HANDLES }, () => [0, 0]);
  state.undo = []; state.redo = [];
  state.design = null;
  state.synthesis = null;
  state.highlight = null;
  fitView(points);
}

function blend(u) {
  const i = Math.floor(u), t = u - i, t2 = t * t, t3 = t2 * t;
  const w = [(-t3 + 2 * t2 - t) / 2, (3 * t3 - 5 * t2 + 2) / 2, (-3 * t3 + 4 * t2 + t) / 2, (t3 - t2) / 2];
  return [-1, 0, 1, 2].map((o, q) => [((i + o) % HANDLES + HANDLES) % HANDLES, w[q]]);
}

function points() {
  return state.orig.map((p, j) => {
    let x = p[0], y = p[1];
    for (const [k, w] of blend(state.u[j])) { x += w * state.disp[k][0]; y += w * state.disp[k][1]; }
    return [x, y];
  });
}

function handlePositions() {
  const pts = points();
  return state.nodes.map((j) => pts[j]);
}

// ---- options ---------------------------------------------------------------------------------
function options() {
  const num = (id) => { const v = $(id).value.trim(); return v === "" ? null : Number(v); };
  const o = {
    center: [num("center-x") || 0, num("center-y") || 0],
    tol_mm: num("tol"),
    order: num("order"),
    limits: $("limits").value,
    sense: $("sense").value,
    max_pressure_angle: num("max-pressure"),
    min_concave_radius: num("min-concave"),
    module: num("module"),
    idler_offset: $("idler-offset").value,
  };
  for (const k of Object.keys(o)) if (o[k] === null) delete o[k];
  if (o.module === 0) delete o.module;
  return o;
}

// ---- designing -------------------------------------------------------------------------------
function startOf(d) {
  if (!d) return undefined;
  const s = Object.assign({}, d);
  delete s.view; delete s.server_ms;
  return s;
}

async function redesign(warm) {
  if (state.controller) state.controller.abort();
  const controller = new AbortController();
  state.controller = controller;
  setStatus("designing", "busy");
  const spacing = Number($("spacing").value);
  const body = { points: points(), options: options(), view: true };
  if (spacing > 0) body.spacing_mm = spacing;
  if (warm && state.design) body.start = startOf(state.design);
  try {
    const r = await api("/api/design", body, controller.signal);
    const d = await r.json();
    if (state.controller !== controller) return;
    state.design = d;
    state.controller = null;
    render();
    setStatus("ready");
    designChanged();
  } catch (e) {
    if (e.name === "AbortError") return;
    if (state.controller === controller) state.controller = null;
    setStatus(e.message, "error");
    render();
    if (state.loadsPending) computeLoads(); // of the design still on screen
  }
}

function scheduleWarm() {
  setStatus("designing", "busy");
  clearTimeout(state.timer);
  state.timer = setTimeout(() => redesign(true), DEBOUNCE_MS);
}

function current() {
  return { disp: state.disp.map((d) => d.slice()), options: formValues() };
}

function snapshot() {
  state.undo.push(current());
  state.redo = [];
}

// Undo (from = undo, to = redo) or redo: the state left is kept on the other stack.
function travel(from, to) {
  const s = from.pop();
  if (!s) return;
  to.push(current());
  restore(s);
}

function formValues() {
  const v = {};
  for (const el of $("options").elements) v[el.id] = el.value;
  return v;
}

function restore(s) {
  state.disp = s.disp.map((d) => d.slice());
  for (const [id, val] of Object.entries(s.options)) if ($(id)) $(id).value = val;
  redesign(true);
}

// ---- drawing ---------------------------------------------------------------------------------
function el(name, attrs, parent) {
  const e = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

const path = (pts, close) => pts.map((p, i) => (i ? "L" : "M") + p[0].toFixed(3) + "," + p[1].toFixed(3)).join("") + (close ? "Z" : "");

function fitView(pts) {
  const xs = pts.map((p) => p[0]).concat([0]), ys = pts.map((p) => p[1]).concat([0]);
  const [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
  state.view = { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, w: 1.3 * Math.max(x1 - x0, y1 - y0, 50) };
}

function pxPerMm() {
  const r = $("canvas").getBoundingClientRect();
  return Math.min(r.width, r.height) / state.view.w;
}

function render() {
  const svg = $("canvas");
  const r = svg.getBoundingClientRect();
  const s = pxPerMm() || 1;
  const w = r.width / s, h = r.height / s;
  svg.setAttribute("viewBox", `${state.view.cx - w / 2} ${-state.view.cy - h / 2} ${w} ${h}`);
  svg.textContent = "";
  const world = el("g", { transform: "scale(1,-1)" }, svg);
  const lw = (px) => (px / s).toFixed(4);
  const d = state.design, v = d && d.view;
  const pts = points();
  // Gears and arms at the carrier angle of the slider.
  if (v) {
    const o = v.center_mm;
    el("path", { d: path(v.gears_mm[0], true), transform: `translate(${o[0]},${o[1]})`, fill: "#dbe9f6", stroke: "#1f77b4", "stroke-width": lw(1), "data-testid": "gear-sun" }, world);
    const pose = v.poses[state.phiIndex % v.poses.length];
    pose.forEach((arm, a) => {
      el("path", { d: path([o, arm.planet_mm]), stroke: "#444", "stroke-width": lw(4), opacity: a ? 0.35 : 0.6 }, world);
      el("path", { d: path(v.gears_mm[1], true), transform: `translate(${arm.intermediate_mm[0]},${arm.intermediate_mm[1]}) rotate(${arm.intermediate_deg})`, fill: "#dff2df", stroke: "#2ca02c", "stroke-width": lw(1), opacity: a ? 0.5 : 1 }, world);
      el("path", { d: path(v.gears_mm[2], true), transform: `translate(${arm.planet_mm[0]},${arm.planet_mm[1]}) rotate(${arm.planet_deg})`, fill: "#ece2f4", stroke: "#9467bd", "stroke-width": lw(1), opacity: a ? 0.5 : 1 }, world);
      el("path", { d: path([arm.planet_mm, arm.tip_mm]), stroke: "#8c564b", "stroke-width": lw(3), opacity: a ? 0.5 : 1 }, world);
      el("circle", { cx: arm.tip_mm[0], cy: arm.tip_mm[1], r: lw(4), fill: "#8c564b" }, world);
    });
    el("path", { d: path(v.traced_mm, true), fill: "none", stroke: "#1f77b4", "stroke-width": lw(2), "data-testid": "traced" }, world);
  }
  el("path", { d: path(pts, true), fill: "none", stroke: "#999", "stroke-width": lw(1.5), "stroke-dasharray": `${lw(4)} ${lw(3)}`, "data-testid": "target" }, world);
  // The deviation along the path: each target point coloured by its distance from the traced path.
  if (v && v.deviation_mm.length === pts.length) {
    const tol = (d.checks && options().tol_mm) || 0.05;
    pts.forEach((p, j) => {
      const e = v.deviation_mm[j];
      if (e <= tol) return;
      el("circle", { cx: p[0], cy: p[1], r: lw(2 + Math.min(6, 2 * Math.log10(1 + e / tol))), fill: e > 10 * tol ? "#d62728" : "#ff9f1c", opacity: 0.8 }, world);
    });
  }
  // The points of the warning clicked, on the path.
  const arc = state.highlight ? arcOf(state.highlight) : null;
  if (arc) {
    const g = el("g", { "data-testid": "warning-arc" }, world);
    for (const j of arc) el("circle", { cx: pts[j][0], cy: pts[j][1], r: lw(6), fill: "#d62728", opacity: 0.35 }, g);
  }
  // Key poses of a synthesis: the tip and the needle's direction (planet axis → tip).
  if (state.synthesis) {
    for (const [k, p] of state.synthesis.poses.entries()) {
      const a = p.needle_deg * Math.PI / 180, l = 25 / s;
      el("path", { d: path([[p.tip_mm[0] - l * Math.cos(a), p.tip_mm[1] - l * Math.sin(a)], p.tip_mm]), stroke: "#d62728", "stroke-width": lw(3) }, world);
      const c = el("circle", { cx: p.tip_mm[0], cy: p.tip_mm[1], r: lw(6), fill: "#ffffff", "fill-opacity": 0.01, stroke: "#d62728", "stroke-width": lw(2), "data-testid": "pose", "data-k": k, class: "pose-handle" }, world);
      c.addEventListener("pointerdown", startPoseDrag);
    }
  }
  el("circle", { cx: 0, cy: 0, r: lw(3), fill: "#000", transform: v ? `translate(${v.center_mm[0]},${v.center_mm[1]})` : "" }, world);
  handlePositions().forEach((p, k) => {
    const c = el("circle", { cx: p[0], cy: p[1], r: lw(7), class: "handle", "data-testid": "handle-" + k, "data-k": k }, world);
    c.addEventListener("pointerdown", startDrag);
  });
  renderReadouts();
  renderRatio();
  renderLoadsChart();
}

function renderPoses() {
  const syn = state.synthesis;
  $("poses-panel").hidden = !syn;
  if (!syn) return;
  const c = syn.candidates[syn.chosen].dyad;
  $("synthesis-arm").textContent = `arm ${syn.chosen + 1} of ${syn.candidates.length} (${syn.dyad_kind}): O = (${c.center_mm[0].toFixed(3)}, ${c.center_mm[1].toFixed(3)}) mm, l1 = ${c.l1_mm.toFixed(3)} mm, l3 = ${c.l3_mm.toFixed(3)} mm, carrier ${syn.carrier.toUpperCase()}`;
  const table = $("poses-table");
  table.textContent = "";
  const row = (name, value, id, bad) => {
    const tr = document.createElement("tr");
    const th = document.createElement("th"), td = document.createElement("td");
    th.textContent = name; td.textContent = value; td.setAttribute("data-testid", id);
    if (bad) td.style.color = "#8a1010";
    tr.append(th, td);
    table.appendChild(tr);
  };
  syn.poses.forEach((p, k) => row(`pose ${k}`, `${p.error_mm.toFixed(4)} mm, ${p.error_deg.toFixed(4)}°`, "pose-error-" + k, p.error_mm > 0.05 || Math.abs(p.error_deg) > 0.05));
  for (const t of syn.targets) row(t.index, `${t.value.toFixed(2)} in [${t.band[0]}, ${t.band[1]}]` + (t.margin >= 0 ? "" : ` — missed by ${(-t.margin).toFixed(2)}`), "target-" + t.index, t.margin < 0);
}

function renderRatio() {
  const svg = $("ratio");
  svg.textContent = "";
  const v = state.design && state.design.view;
  if (!v) return;
  const is = v.ratio.map((p) => p[1]);
  const lo = Math.min(...is), hi = Math.max(...is), span = Math.max(hi - lo, 1e-9);
  el("path", { d: path(v.ratio.map((p) => [p[0], 95 - 90 * (p[1] - lo) / span])), fill: "none", stroke: "#1f77b4", "stroke-width": 1.5, "vector-effect": "non-scaling-stroke" }, svg);
  $("ratio-label").textContent = `sun ratio i21 over the sun's polar angle 0…360°: ${lo.toFixed(3)} … ${hi.toFixed(3)}`;
}

function renderReadouts() {
  const d = state.design;
  const set = (id, t) => { $(id).textContent = t; };
  if (!d) { ["l1-mm", "l3-mm", "deviation-mm", "pressure-deg", "concave-mm", "idler-deg", "server-ms"].forEach((id) => set(id, "–")); return; }
  set("l1-mm", d.l1_mm.toFixed(6));
  set("l3-mm", d.l3_mm.toFixed(6));
  set("deviation-mm", d.roundtrip.max_deviation_mm.toFixed(4));
  set("pressure-deg", d.limits.pressure_angle_deg.toFixed(2));
  set("concave-mm", d.limits.tightest_concave_radius_mm == null ? "none (convex)" : d.limits.tightest_concave_radius_mm.toFixed(2) + " mm");
  set("idler-deg", (d.idler_offset_deg || 0).toFixed(2));
  set("server-ms", d.server_ms.toFixed(1));
  set("teeth", d.teeth ? `z = ${d.teeth.z}, m = ${d.teeth.module_mm} mm` : "none");
  set("binding", d.limits.binding.length ? "binding: " + d.limits.binding.join(", ") : "");
  const checks = $("checks");
  checks.textContent = "";
  for (const c of d.checks) {
    const li = document.createElement("li");
    li.textContent = c.id + (c.pass ? " ✓" : " ✗");
    li.title = c.name || c.description || "";
    if (!c.pass) li.className = "fail";
    checks.appendChild(li);
  }
  const table = $("features");
  table.textContent = "";
  const f = d.view && d.view.features;
  const rows = f ? [
    ["taking angle", f.take_angle_deg.toFixed(1) + "° below horizontal", "feature-take-deg"],
    ["pushing angle", f.push_angle_deg.toFixed(1) + "° below horizontal", "feature-push-deg"],
    ["angle difference", (f.push_angle_deg - f.take_angle_deg).toFixed(1) + "°", "feature-difference-deg"],
    ["trajectory height", f.height_mm.toFixed(1) + " mm", "feature-height-mm"],
    ["hole width at depth", f.hole_width_mm.toFixed(1) + " mm", "feature-hole-mm"],
    ["arm clearance", f.min_arm_clearance_mm.toFixed(1) + " mm", "feature-clearance-mm"],
    ["plant spacing", f.plant_spacing_mm.toFixed(1) + " mm", "feature-spacing-mm"],
  ] : [["figures", (d.view && d.view.features_error) || "–", "feature-error"]];
  for (const [name, value, id] of rows) {
    const tr = document.createElement("tr");
    const th = document.createElement("th"), td = document.createElement("td");
    th.textContent = name; td.textContent = value; td.setAttribute("data-testid", id);
    tr.append(th, td);
    table.appendChild(tr);
  }
  renderPoses();
  const warnings = $("warnings");
  warnings.textContent = "";
  d.warnings.concat(d.teeth ? d.teeth.warnings || [] : []).forEach((w, k) => {
    const li = document.createElement("li");
    li.textContent = w;
    li.setAttribute("data-testid", "warning-" + k);
    // A warning about the path: clicking it highlights the points it concerns.
    if (arcOf(w)) {
      li.className = "has-arc";
      li.title = "click to show where on the path";
      li.addEventListener("click", () => {
        state.highlight = state.highlight === w ? null : w;
        render();
      });
    }
    warnings.appendChild(li);
  });
}

// The target points a warning concerns: those farther from the traced path than the tolerance
// (deviation and round-trip warnings), or the points it names by number; null for the others.
function arcOf(w) {
  const v = state.design && state.design.view;
  if (!v) return null;
  if (/deviat|round trip|C12|traces/i.test(w)) {
    const tol = options().tol_mm || 0.05;
    const idx = v.deviation_mm.map((e, j) => (e > tol ? j : -1)).filter((j) => j >= 0);
    return idx.length ? idx : null;
  }
  const m = /points? ((?:\d+(?:, | and )?)+)/.exec(w);
  if (m) {
    const idx = m[1].split(/, | and /).map(Number).filter((j) => j < state.orig.length);
    return idx.length ? idx : null;
  }
  return null;
}

// ---- loads -----------------------------------------------------------------------------------
// The loads of the design on screen (POST /api/loads): the page sends its design.json object and
// the scene, the bundled assets/loads/rotor.toml (GET /api/loads/scene: the one copy of the
// defaults) with the panel's fields set; the server reads the design back as `ncgear loads` reads
// a design file. No second design: the loads are those of the design the page holds.
function setLoadsStatus(text, kind) {
  const s = $("loads-status");
  s.textContent = text;
  s.className = "loads-status" + (kind ? " " + kind : "");
}

async function initLoads() {
  const d = await (await api("/api/loads/scene")).json();
  const s = d.scene;
  state.loadsScene = s;
  const select = $("loads-material");
  for (const m of [""].concat(d.materials)) {
    const o = document.createElement("option");
    o.value = m;
    o.textContent = m ? m.replace(/_/g, " ") : "none (loads only)";
    select.appendChild(o);
  }
  select.value = (s.material && s.material.preset) || "";
  $("loads-rpm").value = s.operation.carrier_rpm;
  $("loads-arms").value = s.operation.arms;
  $("loads-arm-mass").value = s.arm ? s.arm.mass_kg : "";
  $("loads-arm-mass").disabled = !s.arm;
  const b = s.gears && s.gears.face_width_mm;
  $("loads-face-width").value = typeof b === "number" ? b : "";
  $("loads-face-width").disabled = !s.gears;
  $("loads-form").title = "Defaults: " + d.file + " (an empty face width is \"auto\": the narrowest in 6…15·m that meets the safety targets)";
}

// The scene sent: the bundled one with the panel's fields (an empty field keeps the default).
function loadsScene() {
  const s = JSON.parse(JSON.stringify(state.loadsScene));
  const num = (id) => { const v = $(id).value.trim(); return v === "" ? null : Number(v); };
  if (num("loads-rpm") !== null) s.operation.carrier_rpm = num("loads-rpm");
  if (num("loads-arms") !== null) s.operation.arms = num("loads-arms");
  if (s.arm && num("loads-arm-mass") !== null) s.arm.mass_kg = num("loads-arm-mass");
  if (s.gears) {
    const b = $("loads-face-width").value.trim();
    s.gears.face_width_mm = b === "" || b === "auto" ? "auto" : Number(b);
  }
  const m = $("loads-material").value;
  if (m) s.material = Object.assign({}, s.material || {}, { preset: m });
  else { s.material = null; s.rating = null; }
  return s;
}

async function computeLoads() {
  if (!state.loadsScene) return;
  // A design on its way (an option just changed, e.g. the module field left by this click):
  // the loads are those of the design it brings.
  if (state.controller) { state.loadsPending = true; setLoadsStatus("waiting for the design", "busy"); return; }
  state.loadsPending = false;
  if (!state.design) { setLoadsStatus("no design yet", "error"); return; }
  if (state.loadsController) state.loadsController.abort();
  const controller = new AbortController();
  state.loadsController = controller;
  const design = state.design, scene = loadsScene();
  setLoadsStatus("computing", "busy");
  try {
    const r = await api("/api/loads", { design: startOf(design), scene }, controller.signal);
    const l = await r.json();
    if (state.loadsController !== controller) return;
    state.loadsController = null;
    state.loads = l;
    state.loadsOf = design;
    state.loadsSent = scene;
    renderLoads();
    setLoadsStatus("ready");
    $("loads-status").title = `server ${l.server_ms.toFixed(0)} ms`;
  } catch (e) {
    if (e.name === "AbortError") return;
    if (state.loadsController === controller) state.loadsController = null;
    setLoadsStatus(e.message, "error");
  }
}

// A new design on screen: its loads at once when asked for, else the loads shown are marked stale.
function designChanged() {
  if ($("loads-auto").checked || state.loadsPending) computeLoads();
  else if (state.loads && state.loadsOf !== state.design) {
    $("loads-panel").classList.add("stale");
    setLoadsStatus("the design changed: press Loads");
  }
}

function renderLoads() {
  const l = state.loads, s = l.summary, rt = l.rating;
  $("loads-panel").hidden = false;
  $("loads-panel").classList.remove("stale");
  const set = (id, t) => { $(id).textContent = t; };
  set("carrier-torque-peak", s.carrier_torque_peak_Nm.toFixed(3));
  set("carrier-torque-rms", s.carrier_torque_rms_Nm.toFixed(3));
  set("mean-power", s.mean_power_W.toFixed(2));
  set("planet-torque-peak", s.planet_mesh_torque_peak_Nm.toFixed(3));
  set("reversals", s.reversals_deg.length ? s.reversals_deg.map((r) => r.toFixed(1) + "°").join(", ") : "none");
  const b = rt ? rt.face_width_mm : l.gears.face_width_mm;
  const auto = state.loadsSent.gears && state.loadsSent.gears.face_width_mm === "auto";
  set("loads-face-width-used", b == null ? "none (massless gears)" : b + " mm" + (auto ? " (auto)" : ""));
  const mesh = (m) => m.replace("_", "–");
  // Where an extreme is: travel angle, mesh, gear and tooth.
  const where = (e, target) => `(target ${target}) at ${e.travel_deg.toFixed(1)}°, ${mesh(e.mesh)}, ${e.gear} tooth ${e.tooth}`;
  if (rt) {
    set("safety-h", rt.min_S_H.value.toFixed(3));
    set("safety-h-where", where(rt.min_S_H, rt.options.S_H_min));
    set("safety-f", rt.min_S_F.value.toFixed(3));
    set("safety-f-where", where(rt.min_S_F, rt.options.S_F_min) + " root");
    const life = rt.life_h;
    set("life-h", life == null ? "unlimited" : life >= 1e5 ? life.toExponential(2) : life.toFixed(0));
    set("life-where", (life == null ? "" : "h ") + `(${rt.life_limited_by}, ${rt.options.material.name})`);
  } else {
    const why = l.left_out && l.left_out.length ? "set a module to rate the teeth" : "no material";
    for (const id of ["safety-h", "safety-f", "life-h"]) set(id, "–");
    for (const id of ["safety-h-where", "safety-f-where", "life-where"]) set(id, why);
  }
  const notes = $("loads-notes");
  notes.textContent = "";
  const lines = (l.left_out || []).concat(l.verdict && !l.verdict.passed ? l.verdict.failures || [] : [], rt ? rt.notes : []);
  lines.forEach((n, k) => {
    const li = document.createElement("li");
    li.textContent = n;
    li.setAttribute("data-testid", "loads-note-" + k);
    notes.appendChild(li);
  });
  renderLoadsChart();
}

// The carrier torque (all arms) and the first arm's planet mesh torque over the carrier's travel,
// the torque reversals (the teeth cross their backlash) marked, and the slider's carrier angle.
function renderLoadsChart() {
  const l = state.loads, svg = $("loads-chart");
  if (!l) return;
  svg.textContent = "";
  const [x0, x1, y0, y1] = [40, 314, 18, 132];
  const t = l.travel_deg, c = l.carrier_torque_Nm, p = l.planet_mesh_torque_Nm;
  const all = c.concat(p, [0]);
  const lo = Math.min(...all), hi = Math.max(...all), span = Math.max(hi - lo, 1e-9);
  const X = (deg) => x0 + (x1 - x0) * deg / 360, Y = (v) => y1 - (y1 - y0) * (v - lo) / span;
  const curve = (v) => path(t.map((d, k) => [X(d), Y(v[k])]).concat([[X(360), Y(v[0])]]));
  const text = (x, y, str, attrs) => { el("text", Object.assign({ x, y, fill: "#555" }, attrs || {}), svg).textContent = str; };
  el("rect", { x: x0, y: y0, width: x1 - x0, height: y1 - y0, fill: "none", stroke: "#ddd" }, svg);
  for (const d of [0, 90, 180, 270, 360]) {
    el("line", { x1: X(d), x2: X(d), y1: y0, y2: y1, stroke: "#eee" }, svg);
    text(X(d), y1 + 11, d + "°", { "text-anchor": "middle" });
  }
  el("line", { x1: x0, x2: x1, y1: Y(0), y2: Y(0), stroke: "#999", "stroke-dasharray": "3 2" }, svg);
  text(x0 - 3, Y(hi) + 3, hi.toFixed(1), { "text-anchor": "end" });
  text(x0 - 3, Y(0) + 3, "0", { "text-anchor": "end" });
  text(x0 - 3, Y(lo) + 3, lo.toFixed(1), { "text-anchor": "end" });
  text(4, y0 - 6, "N·m");
  el("path", { d: curve(p), fill: "none", stroke: "#9467bd", "stroke-width": 1.2, "data-testid": "loads-planet" }, svg);
  el("path", { d: curve(c), fill: "none", stroke: "#1f77b4", "stroke-width": 1.6, "data-testid": "loads-carrier" }, svg);
  for (const r of l.summary.reversals_deg) {
    el("line", { x1: X(r), x2: X(r), y1: y0, y2: y1, stroke: "#d62728", "stroke-dasharray": "2 2" }, svg);
    el("circle", { cx: X(r), cy: Y(0), r: 2.5, fill: "#d62728", "data-testid": "loads-reversal" }, svg);
  }
  // The slider's carrier angle: pose k is at 2k° of travel; arm 1 of the drawing is the first arm.
  const phi = 2 * state.phiIndex;
  el("line", { x1: X(phi), x2: X(phi), y1: y0, y2: y1, stroke: "#444", opacity: 0.4 }, svg);
  text(x0 + 2, y0 - 6, "carrier (all arms)", { fill: "#1f77b4" });
  text(x0 + 92, y0 - 6, "planet mesh (arm 1)", { fill: "#9467bd" });
  text(x0 + 192, y0 - 6, "┆ reversal", { fill: "#d62728" });
}

// ---- interaction -----------------------------------------------------------------------------
function toWorld(ev) {
  const svg = $("canvas");
  const p = svg.createSVGPoint();
  p.x = ev.clientX; p.y = ev.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  return [q.x, -q.y];
}

function startDrag(ev) {
  ev.stopPropagation();
  ev.preventDefault();
  const k = Number(ev.target.getAttribute("data-k"));
  snapshot();
  const start = toWorld(ev), d0 = state.disp[k].slice();
  const move = (e) => {
    const p = toWorld(e);
    state.disp[k] = [d0[0] + p[0] - start[0], d0[1] + p[1] - start[1]];
    render();
    scheduleWarm();
  };
  const up = () => {
    window.removeEventListener("pointermove", move);
    window.removeEventListener("pointerup", up);
  };
  window.addEventListener("pointermove", move);
  window.addEventListener("pointerup", up);
}

// Dragging a key pose moves its tip (the needle keeps its direction); on release the spec, with
// the pose moved, is synthesised again. A spec that no longer has an arm says so in the status
// bar and the last synthesis stays.
function startPoseDrag(ev) {
  ev.stopPropagation();
  ev.preventDefault();
  const k = Number(ev.target.getAttribute("data-k"));
  const pose = state.synthesis.poses[k], tip0 = pose.tip_mm.slice(), start = toWorld(ev);
  let moved = false;
  const move = (e) => {
    const p = toWorld(e);
    pose.tip_mm = [tip0[0] + p[0] - start[0], tip0[1] + p[1] - start[1]];
    moved = true;
    render();
  };
  const up = () => {
    window.removeEventListener("pointermove", move);
    window.removeEventListener("pointerup", up);
    if (!moved || !state.spec) return;
    const spec = JSON.parse(JSON.stringify(state.spec));
    spec.pose[k].x_mm = pose.tip_mm[0];
    spec.pose[k].y_mm = pose.tip_mm[1];
    pose.tip_mm = tip0;
    synthesizeSpec({ name: "poses.json", text: JSON.stringify(spec) });
  };
  window.addEventListener("pointermove", move);
  window.addEventListener("pointerup", up);
}

function startPan(ev) {
  const s = pxPerMm(), x0 = ev.clientX, y0 = ev.clientY, v0 = Object.assign({}, state.view);
  const move = (e) => { state.view.cx = v0.cx - (e.clientX - x0) / s; state.view.cy = v0.cy + (e.clientY - y0) / s; render(); };
  const up = () => { window.removeEventListener("pointermove", move); window.removeEventListener("pointerup", up); };
  window.addEventListener("pointermove", move);
  window.addEventListener("pointerup", up);
}

// Loads the points a request answers (`{name, points}`), then runs the full design on them.
async function openWith(request) {
  setStatus("designing", "busy");
  try {
    const p = await (await request()).json();
    loadPoints(p.name, p.points);
    $("example").value = p.name;
    await redesign(false);
  } catch (e) { setStatus(e.message, "error"); }
}

const openExample = (name) => openWith(() => api("/api/examples/" + encodeURIComponent(name)));
const MAX_UPLOAD_BYTES = 8 << 20; // the server's body limit

// A synthesis spec: the arm, timing and gears through its poses; the traced path becomes the
// target to edit further (the poses stay drawn until another path is opened).
async function openPoses(file) {
  setStatus("designing", "busy"); // at once: the file is read before the request
  await synthesizeSpec({ name: file.name, text: await file.text() });
}

// Synthesises a spec (`{name, text}`) and shows it, its path becoming the target.
async function synthesizeSpec(upload) {
  setStatus("designing", "busy");
  try {
    const r = await api("/api/synthesize", upload);
    const syn = await r.json();
    loadPoints(syn.name, syn.design.target_points);
    state.synthesis = syn.synthesis;
    state.spec = syn.spec;
    state.design = syn.design;
    const o = syn.design.carrier.center_mm;
    $("center-x").value = o[0];
    $("center-y").value = o[1];
    render();
    setStatus("ready");
    designChanged();
  } catch (e) { setStatus(e.message, "error"); render(); }
}
// A drawing (DXF, SVG) is read with the page's "layer or id" and "units" fields; changing them
// reads the last drawing again.
const isDrawing = (file) => /\.(dxf|svg)$/i.test(file.name);
let lastDrawing = null;
const openFile = (file) => openWith(async () => {
  if (file.size > MAX_UPLOAD_BYTES) {
    throw new Error(`${file.name}: ${(file.size / 1048576).toFixed(1)} MB, larger than the 8 MB a trajectory may have here (about 100 000 points): thin the points first`);
  }
  lastDrawing = isDrawing(file) ? file : null;
  const pick = $("drawing-pick").value.trim();
  const units = $("drawing-units").value;
  const body = { name: file.name, text: await file.text() };
  if (lastDrawing) Object.assign(body, { layer: pick || null, id: pick || null, units: units || null });
  return api("/api/parse", body);
});

async function download(format) {
  setStatus("designing", "busy");
  try {
    const r = await api("/api/export", { points: points(), options: options(), format });
    const blob = await r.blob();
    const disp = r.headers.get("Content-Disposition") || "";
    const m = /filename="([^"]+)"/.exec(disp);
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = m ? m[1] : "design." + format;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setStatus("ready");
  } catch (e) { setStatus(e.message, "error"); }
}

function saveWork() {
  const work = { ncgear_work: 1, name: state.name, points: state.orig, displacements_mm: state.disp, options: formValues() };
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([JSON.stringify(work)], { type: "application/json" }));
  a.download = (state.name || "work").replace(/\.[^.]*$/, "") + ".ncgear-work.json";
  document.body.appendChild(a);
  a.click();
  a.remove();
}

async function loadWork(file) {
  setStatus("designing", "busy");
  try {
    const w = JSON.parse(await file.text());
    if (w.ncgear_work !== 1 || !Array.isArray(w.points) || !Array.isArray(w.displacements_mm) || w.displacements_mm.length !== HANDLES) {
      throw new Error(file.name + ": not a saved ncgear work file");
    }
    loadPoints(w.name || file.name, w.points);
    restore({ disp: w.displacements_mm, options: w.options || {} });
  } catch (e) { setStatus(e.message, "error"); }
}

function init() {
  $("canvas").addEventListener("pointerdown", startPan);
  $("canvas").addEventListener("wheel", (e) => {
    e.preventDefault();
    state.view.w *= Math.exp(0.001 * e.deltaY);
    render();
  }, { passive: false });
  $("spacing").addEventListener("change", () => redesign(true));
  $("open-file").addEventListener("change", (e) => { if (e.target.files[0]) openFile(e.target.files[0]); e.target.value = ""; });
  for (const f of ["drawing-pick", "drawing-units"]) $(f).addEventListener("change", () => { if (lastDrawing) openFile(lastDrawing); });
  $("open-poses").addEventListener("change", (e) => { if (e.target.files[0]) openPoses(e.target.files[0]); e.target.value = ""; });
  $("load-work").addEventListener("change", (e) => { if (e.target.files[0]) loadWork(e.target.files[0]); e.target.value = ""; });
  $("example").addEventListener("change", (e) => openExample(e.target.value));
  $("optimize").addEventListener("click", () => redesign(false));
  $("cancel").addEventListener("click", () => {
    if (state.controller) { state.controller.abort(); state.controller = null; }
    setStatus("ready");
    if (state.loadsPending) computeLoads();
  });
  $("undo").addEventListener("click", () => travel(state.undo, state.redo));
  $("redo").addEventListener("click", () => travel(state.redo, state.undo));
  document.addEventListener("keydown", (e) => {
    if ((e.ctrlKey || e.metaKey) && e.key === "z") $("undo").click();
    if ((e.ctrlKey || e.metaKey) && e.key === "y") $("redo").click();
  });
  for (const input of $("options").elements) {
    input.addEventListener("focus", () => snapshot());
    input.addEventListener("change", () => redesign(false));
  }
  $("phi-slider").addEventListener("input", (e) => {
    state.phiIndex = Number(e.target.value);
    $("phi-deg").textContent = 2 * state.phiIndex + "°";
    render();
  });
  $("play").addEventListener("click", () => {
    state.playing = !state.playing;
    $("play").textContent = state.playing ? "Pause" : "Play";
    const step = () => {
      if (!state.playing) return;
      state.phiIndex = (state.phiIndex + 1) % 180;
      $("phi-slider").value = state.phiIndex;
      $("phi-deg").textContent = 2 * state.phiIndex + "°";
      render();
      setTimeout(() => requestAnimationFrame(step), 30);
    };
    step();
  });
  for (const f of ["json", "svg", "dxf", "step"]) $("download-" + f).addEventListener("click", () => download(f));
  $("save-work").addEventListener("click", saveWork);
  document.body.addEventListener("dragover", (e) => { e.preventDefault(); document.body.classList.add("drop"); });
  document.body.addEventListener("dragleave", () => document.body.classList.remove("drop"));
  document.body.addEventListener("drop", (e) => {
    e.preventDefault();
    document.body.classList.remove("drop");
    if (e.dataTransfer.files[0]) openFile(e.dataTransfer.files[0]);
  });
  window.addEventListener("resize", render);
  $("loads-button").addEventListener("click", computeLoads);
  for (const input of $("loads-form").elements) {
    input.addEventListener("change", () => { if (state.loads || $("loads-auto").checked) computeLoads(); });
  }
  initLoads().catch((e) => setLoadsStatus(e.message, "error"));
  api("/api/examples").then((r) => r.json()).then((list) => {
    for (const ex of list) {
      const o = document.createElement("option");
      o.value = ex.name; o.textContent = ex.file;
      $("example").appendChild(o);
    }
    openExample(list[0].name);
  }).catch((e) => setStatus(e.message, "error"));
}

init();
