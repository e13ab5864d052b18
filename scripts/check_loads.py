#!/usr/bin/env python3
"""Independent rigid-body check of `ncgear loads` (numpy only; shares no code with the crate).

Usage:
    python3 scripts/check_loads.py DESIGN.json SCENE.toml [LOADS.json] [--tol 0.01]

From the design file alone it rebuilds the planting rotor's motion by its own means and computes
the loads by its own formulation (docs/loads.md states the model and the conventions):

* Kinematics (docs/math/chain.md §2, §6.5; CCW frame, a CW design mirrored y -> -y):
  D = a·e(φ + ε), A = l1·e(φ), l1 = 2a·cos ε.  Rolling without slip of the sun (fixed) on the
  intermediate, contact on the line of centres at sun body angle φ + ε:
        dθ2/dφ = a / (a − r_sun(φ + ε))                        (quadrature, spectral)
  and of the intermediate on the planet, contact at intermediate body angle c2 = φ − ε − θ2 and
  planet body angle c3 = φ + π − ε − θ3, equal contact speeds relative to the carrier:
        dc3/dφ = r_int(c2) · (dθ2/dφ − 1) / r_planet(c3)        (RK4, planet table)
  Tables are read by trigonometric (band-limited) interpolation. Tip B = A + l3·e(θ3 + γ).
* Accelerations: FFT spectral derivatives of the periodic motion on a fine uniform grid.
* Carrier torque by the power balance  T·ω = dE/dt − Σ m g·v_G − Σ F·v_B  (all arms);
  planet mesh torque by the angular-momentum balance of planet gear + arm about A;
  frame force = Σ m a_G − (Σ m_moving + m_sun)·g − Σ F_needle;
  sun torque by the angular-momentum balance of the whole rotor about O.
* Gear mass properties recomputed from the pitch curves (scene [gears]) and compared (5 %).
* Invariants of the report: O = Σ_arms (R_D + R_A), carrier torque = Σ (D × R_D + A × R_A),
  normal forces ≥ 0.

The gear mass properties used are the ones loads.json states (`gears`). A scene whose face
width is not a number (`"auto"`) is checked at the width the report states; a needle given
otherwise than by a `force_N` table (`profile = ...`) takes its force from the report's
`needle_table_N` (the table the loads use, linear between its rows; before it existed, the
samples of `needle_force_N`): the one input then not rebuilt here (the report says so in a
note), and the per-sample `needle_force_N` is checked against it.

Without LOADS.json: the kinematics (against design.json's target points and the traced.csv
beside it) are checked, and our loads computed with our own mass properties (peaks printed;
--dump writes the series). Exit 0 when every check passes, 1 otherwise, 2 on unusable input.
"""

import argparse
import json
import math
import os
import sys

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

import numpy as np

G0 = 9.80665  # m/s²
TAU = 2.0 * math.pi


class InputError(Exception):
    pass


# ----------------------------------------------------------------------------------------------
# Periodic band-limited functions
# ----------------------------------------------------------------------------------------------


class Trig:
    """Trigonometric interpolant of uniform samples f(2πj/n), j = 0..n−1, period 2π."""

    def __init__(self, samples, rel_cut=1e-15):
        y = np.asarray(samples, dtype=float)
        n = len(y)
        c = np.fft.rfft(y) / n
        if n % 2 == 0:
            c[-1] *= 0.5  # Nyquist term: counted twice by 2·Re below
        # Drop the negligible tail (keeps evaluation at arbitrary points cheap).
        scale = max(np.max(np.abs(c)), 1e-300)
        keep = np.nonzero(np.abs(c) > rel_cut * scale)[0]
        kmax = int(keep[-1]) if len(keep) else 0
        self.c = c[: kmax + 1].copy()
        self.k = np.arange(kmax + 1, dtype=float)
        self.n = n

    def __call__(self, x, deriv=0):
        x = np.asarray(x, dtype=float)
        flat = x.ravel()
        out = np.empty(flat.shape)
        coef = self.c * (1j * self.k) ** deriv
        coef = coef.copy()
        coef[1:] *= 2.0
        if deriv > 0:
            coef[0] = 0.0
        step = max(1, 4_000_000 // max(len(coef), 1))
        for s in range(0, len(flat), step):
            xs = flat[s : s + step]
            out[s : s + step] = np.real(np.exp(1j * np.outer(xs, self.k)) @ coef)
        return out.reshape(x.shape)

    def uniform(self, m, shift=0.0):
        """Values at the m uniform points shift + 2πj/m (exact phase shift, zero padding)."""
        kmax = len(self.c) - 1
        if kmax >= m // 2:
            raise InputError(f"grid of {m} points too coarse for {kmax} harmonics")
        spec = np.zeros(m // 2 + 1, dtype=complex)
        spec[: kmax + 1] = self.c * np.exp(1j * self.k * shift)
        spec[1:] *= 2.0
        spec[0] *= 2.0
        return np.fft.irfft(spec * m / 2.0, n=m)


def spectral_derivative(y, order=1, axis=0):
    """d^order/dτ^order of samples of a 2π-periodic function on a uniform grid over [0, 2π)."""
    y = np.asarray(y, dtype=float)
    n = y.shape[axis]
    c = np.fft.rfft(y, axis=axis)
    k = np.arange(c.shape[axis], dtype=float)
    fac = (1j * k) ** order
    if n % 2 == 0:
        fac[-1] = 0.0 if order % 2 == 1 else fac[-1]
    shape = [1] * y.ndim
    shape[axis] = len(k)
    return np.fft.irfft(c * fac.reshape(shape), n=n, axis=axis)


def periodic_integral(f):
    """Mean and zero-start antiderivative of uniform samples of a 2π-periodic f over [0, 2π):
    F(τ_j) = mean·τ_j + P(τ_j) − P(0)."""
    n = len(f)
    c = np.fft.rfft(f)
    mean = c[0].real / n
    k = np.arange(len(c), dtype=float)
    ci = np.zeros_like(c)
    ci[1:] = c[1:] / (1j * k[1:])
    if n % 2 == 0:
        ci[-1] = 0.0
    p = np.fft.irfft(ci, n=n)
    tau = TAU * np.arange(n) / n
    return mean, mean * tau + p - p[0]


def rot(theta, v):
    """Rotate body vectors v (2,) or (N,2) by angles theta (N,) -> (N,2)."""
    c, s = np.cos(theta), np.sin(theta)
    v = np.asarray(v, dtype=float)
    if v.ndim == 1:
        return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]], axis=-1)
    return np.stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]], axis=-1)


def cross(p, q):
    return p[..., 0] * q[..., 1] - p[..., 1] * q[..., 0]


# ----------------------------------------------------------------------------------------------
# Design file and kinematics
# ----------------------------------------------------------------------------------------------


def uniform_table(pitch, name):
    t = np.asarray(pitch, dtype=float)
    if t.ndim != 2 or t.shape[1] != 2 or len(t) < 16:
        raise InputError(f"gears.{name}.pitch: expected [[theta_deg, r_mm], ...] (≥ 16 rows)")
    n = len(t)
    expect = 360.0 * np.arange(n) / n
    if np.max(np.abs(t[:, 0] - expect)) > 1e-6:
        raise InputError(f"gears.{name}.pitch: angles are not uniform from 0 over 360°")
    if np.min(t[:, 1]) <= 0:
        raise InputError(f"gears.{name}.pitch: non-positive radius")
    return t[:, 1].copy()


class Design:
    def __init__(self, path):
        with open(path) as fh:
            d = json.load(fh)
        self.raw = d
        try:
            self.a = float(d["center_distance_mm"])
            self.l3 = float(d["l3_mm"])
            self.eps_world = math.radians(float(d.get("idler_offset_deg") or 0.0))
            self.gamma_world = math.radians(float(d["needle_angle_deg"]))
            self.center = np.asarray(d["carrier"]["center_mm"], dtype=float)
            self.direction = 1 if int(d["carrier"]["direction"]) >= 0 else -1
            g = d["gears"]
            self.tables_world = {
                name: uniform_table(g[name]["pitch"], name)
                for name in ("sun", "intermediate", "planet")
            }
            self.th2_world0 = math.radians(float(g["intermediate"]["angle_at_zero_deg"]))
            self.th3_world0 = math.radians(float(g["planet"]["angle_at_zero_deg"]))
        except (KeyError, TypeError, ValueError) as e:
            raise InputError(f"{path}: missing or malformed key: {e}") from e
        self.s = float(self.direction)
        # CCW frame: a CW design's tables, angles and y coordinates mirrored.
        self.eps = self.s * self.eps_world
        self.gamma = self.s * self.gamma_world
        self.th2_0 = self.s * self.th2_world0
        self.th3_0 = self.s * self.th3_world0
        self.l1 = 2.0 * self.a * math.cos(self.eps)
        self.tables = {}
        for name, r in self.tables_world.items():
            if self.direction < 0:
                n = len(r)
                r = r[(-np.arange(n)) % n]  # r_ccw(θ) = r_world(−θ)
            self.tables[name] = r
        self.curve = {name: Trig(r) for name, r in self.tables.items()}

    def to_world(self, p):
        """CCW-frame points relative to O (mm) -> world points (mm)."""
        p = np.asarray(p, dtype=float)
        return np.stack([self.center[0] + p[..., 0], self.center[1] + self.s * p[..., 1]], -1)

    def vec_to_ccw(self, v):
        v = np.asarray(v, dtype=float)
        return np.stack([v[..., 0], self.s * v[..., 1]], -1)

    def motion(self, n):
        """Poses at the n travel angles τ_j = 2πj/n (CCW frame, mm, rad)."""
        a, eps = self.a, self.eps
        sun, mid, pla = self.curve["sun"], self.curve["intermediate"], self.curve["planet"]
        # θ2 on the doubled grid (steps and half steps), by quadrature of dθ2/dφ.
        m = 2 * n
        rs = sun.uniform(m, shift=eps)  # r_sun(φ + ε)
        if np.max(rs) >= a:
            raise InputError("sun radius reaches the centre distance")
        dth2 = a / (a - rs)
        mean2, int2 = periodic_integral(dth2)
        th2 = self.th2_0 + int2
        c2 = (TAU * np.arange(m) / m) - eps - th2
        r2 = mid(c2)
        # c3 by RK4 in φ with the planet table: dc3/dφ = r2(c2)·(θ2' − 1)/r3(c3).
        h = TAU / n
        g_num = r2 * (dth2 - 1.0)  # numerator on the doubled grid
        c3 = np.empty(n + 1)
        c3[0] = math.pi - eps - self.th3_0
        for j in range(n):
            i0, i1, i2 = 2 * j, 2 * j + 1, (2 * j + 2) % m
            y = c3[j]
            k1 = g_num[i0] / pla(y)
            k2 = g_num[i1] / pla(y + 0.5 * h * k1)
            k3 = g_num[i1] / pla(y + 0.5 * h * k2)
            k4 = g_num[i2] / pla(y + h * k3)
            c3[j + 1] = y + h * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0
        closure = c3[n] - c3[0] - TAU  # 0 for a train whose planet closes in one turn
        tau = TAU * np.arange(n) / n
        # The motion must be exactly periodic for the spectral derivatives: the closure errors
        # (round-off for conjugate tables; reported) are spread linearly over the turn.
        c3 = c3[:n] - closure * tau / TAU
        turns2 = round(mean2)
        th2 = th2[::2] - (mean2 - turns2) * tau
        c2 = c2[::2]
        th3 = tau + math.pi - eps - c3
        A = self.l1 * np.stack([np.cos(tau), np.sin(tau)], -1)
        D = a * np.stack([np.cos(tau + eps), np.sin(tau + eps)], -1)
        B = A + self.l3 * np.stack([np.cos(th3 + self.gamma), np.sin(th3 + self.gamma)], -1)
        u = tau + eps
        P1 = rs[::2, None] * np.stack([np.cos(u), np.sin(u)], -1)  # sun–intermediate pitch point
        P2 = D + r2[::2, None] * np.stack([np.cos(tau - eps), np.sin(tau - eps)], -1)
        sun_err = rs[::2] + mid(tau + eps + math.pi - th2) - a
        planet_err = r2[::2] + pla(c3) - a
        return {
            "tau": tau,
            "th2": th2,
            "th2_turns": turns2,  # whole turns of θ2 per carrier turn (2)
            "th2_closure": 2 * math.pi * (mean2 - turns2),
            "th3": th3,
            "c2": c2,
            "c3": c3,
            "A": A,
            "D": D,
            "B": B,
            "P1": P1,
            "P2": P2,
            "closure_rad": closure,
            "sun_mesh_err": float(np.max(np.abs(sun_err))),
            "planet_mesh_err": float(np.max(np.abs(planet_err))),
        }


def point_to_polyline(points, poly):
    """Distance of each point to the closed polyline poly (mm)."""
    p0 = poly
    p1 = np.roll(poly, -1, axis=0)
    d = p1 - p0
    L2 = np.maximum(np.sum(d * d, axis=1), 1e-300)
    out = np.empty(len(points))
    for i, q in enumerate(points):
        t = np.clip(np.sum((q - p0) * d, axis=1) / L2, 0.0, 1.0)
        proj = p0 + t[:, None] * d
        out[i] = np.sqrt(np.min(np.sum((proj - q) ** 2, axis=1)))
    return out


# ----------------------------------------------------------------------------------------------
# Scene and mass properties
# ----------------------------------------------------------------------------------------------


def load_toml(path):
    if tomllib is None:
        raise InputError("reading a scene needs Python ≥ 3.11 (tomllib)")
    with open(path, "rb") as fh:
        return tomllib.load(fh)


class Scene:
    def __init__(self, path):
        t = load_toml(path)
        self.raw = t
        op = t.get("operation")
        if op is None:
            raise InputError(f"{path}: no [operation] table")
        self.rpm = float(op["carrier_rpm"])
        self.arms = int(op.get("arms", 1))
        if self.arms < 1:
            raise InputError("operation.arms < 1")
        g = np.asarray(op.get("gravity", [0.0, 0.0]), dtype=float)
        if g.shape != (2,):
            raise InputError("operation.gravity must be [x, y]")
        norm = float(np.hypot(*g))
        self.gravity_dir = g / norm if norm > 0 else np.zeros(2)
        arm = t.get("arm")
        if arm is not None:
            self.arm_mass = float(arm.get("mass_kg", 0.0))
            self.arm_com = np.asarray(arm.get("com_mm", [0.0, 0.0]), dtype=float)
            self.arm_inertia = float(arm.get("inertia_kg_mm2", 0.0))
        else:
            self.arm_mass, self.arm_com, self.arm_inertia = 0.0, np.zeros(2), 0.0
        self.gears = t.get("gears")
        needle = t.get("needle")
        self.needle = None
        # a needle described otherwise (e.g. `profile = "planting"`): its force is taken from
        # the report (use_reported_needle), the only input not rebuilt here
        self.needle_other = needle is not None and not needle.get("force_N") and bool(needle)
        if needle is not None and needle.get("force_N"):
            tab = np.asarray(needle["force_N"], dtype=float)
            if tab.ndim != 2 or tab.shape[1] != 3:
                raise InputError("needle.force_N must be [[travel_deg, Fx, Fy], ...]")
            self.needle = tab
        design = t.get("design")
        self.design_path = (
            os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), design))
            if design
            else None
        )

    def use_reported_needle(self, travel_deg, force):
        """The needle force as the report states it (world N at its travel angles), read
        linearly between its samples: exact at every sample, for every arm."""
        f = np.asarray(force, dtype=float)
        self.needle = np.column_stack([np.asarray(travel_deg, dtype=float), f[:, 0], f[:, 1]])

    def needle_force(self, travel_deg):
        """World-frame needle force (N) at the arm's own travel angles (deg)."""
        x = np.asarray(travel_deg, dtype=float) % 360.0
        if self.needle is None:
            return np.zeros(x.shape + (2,))
        xp = self.needle[:, 0] % 360.0
        fx = np.interp(x, xp, self.needle[:, 1], period=360.0)
        fy = np.interp(x, xp, self.needle[:, 2], period=360.0)
        return np.stack([fx, fy], -1)


def gear_mass_properties(r, face_mm, density, bore_mm):
    """Pitch region r(θ) (uniform samples over 2π) extruded, less a central bore.
    Returns mass kg, com mm (body frame), inertia about the axis kg·mm², mean radius mm."""
    n = len(r)
    th = TAU * np.arange(n) / n
    w = TAU / n  # periodic trapezoid rule: spectrally accurate
    rb = 0.5 * bore_mm
    area = 0.5 * np.sum(r**2) * w - math.pi * rb**2  # mm²
    sx = np.sum(r**3 * np.cos(th)) * w / 3.0  # mm³ (the bore is centred: no first moment)
    sy = np.sum(r**3 * np.sin(th)) * w / 3.0
    jp = 0.25 * np.sum(r**4) * w - 0.5 * math.pi * rb**4  # mm⁴
    rho = density * 1e-9  # kg/mm³
    mass = rho * face_mm * area
    com = np.array([sx, sy]) / area
    inertia = rho * face_mm * jp
    return mass, com, inertia, float(np.mean(r))


# ----------------------------------------------------------------------------------------------
# Report helpers
# ----------------------------------------------------------------------------------------------


class Report:
    def __init__(self):
        self.rows = []
        self.failures = []
        self.notes = []
        self.key = {}  # headline numbers for the one-line summary

    def row(self, what, value, limit, ok, unit=""):
        self.rows.append((what, value, limit, ok, unit))
        if not ok:
            self.failures.append(f"{what}: {value:.4g}{unit} exceeds {limit:.4g}{unit}")

    def fail(self, msg):
        self.failures.append(msg)

    def note(self, msg):
        self.notes.append(msg)

    def print(self, title):
        print(f"check_loads: {title}")
        w = max([len(r[0]) for r in self.rows] + [10])
        for what, value, limit, ok, unit in self.rows:
            flag = "ok  " if ok else "FAIL"
            print(f"  {flag} {what:<{w}}  {value:11.3e}{unit:<3} (limit {limit:.3e}{unit})")
        for n in self.notes:
            print(f"  note: {n}")


def arr(d, key, what):
    if key not in d:
        raise InputError(f"loads.json: no `{what}`")
    return np.asarray(d[key], dtype=float)


def crossings(x_deg, y):
    """Travel angles (deg) where the periodic samples y change sign, linear between samples."""
    out = []
    n = len(y)
    for j in range(n):
        y0, y1 = y[j], y[(j + 1) % n]
        x0 = x_deg[j]
        x1 = x_deg[(j + 1) % n] + (360.0 if j + 1 == n else 0.0)
        if y0 == 0.0 and y1 != 0.0:
            # an exact zero counts once, where the sign after it differs from the one before
            prev = y[(j - 1) % n]
            if prev != 0.0 and np.sign(prev) != np.sign(y1):
                out.append(x0 % 360.0)
        elif y0 * y1 < 0:
            out.append((x0 + (x1 - x0) * y0 / (y0 - y1)) % 360.0)
    return sorted(out)


def angle_gap(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


# ----------------------------------------------------------------------------------------------
# The check
# ----------------------------------------------------------------------------------------------


def check_kinematics(design, design_path, rep, n=4096):
    mo = design.motion(n)
    tip_w = design.to_world(mo["B"])
    rep.row("intermediate closure over one turn, rad", abs(mo["th2_closure"]), 1e-6,
            abs(mo["th2_closure"]) <= 1e-6 and mo["th2_turns"] == 2)
    rep.row("planet closure over one turn, rad", abs(mo["closure_rad"]), 1e-6,
            abs(mo["closure_rad"]) <= 1e-6)
    rep.row("mesh error sun–intermediate, mm", mo["sun_mesh_err"], 1e-3, mo["sun_mesh_err"] <= 1e-3)
    rep.row("mesh error intermediate–planet, mm", mo["planet_mesh_err"], 1e-3,
            mo["planet_mesh_err"] <= 1e-3)
    tp = design.raw.get("target_points")
    rt = design.raw.get("roundtrip", {}) or {}
    rt_max = float(rt.get("max_deviation_mm") or 0.0)
    if tp:
        tp = np.asarray(tp, dtype=float)
        dist = point_to_polyline(tp, tip_w)
        lim = max(2.0 * rt_max, 0.01)
        rep.row("target points to our traced tip path, max mm", float(np.max(dist)), lim,
                float(np.max(dist)) <= lim, "")
        rep.note(f"design.json roundtrip.max_deviation_mm = {rt_max:.3g} (synchronous)")
    traced = os.path.join(os.path.dirname(os.path.abspath(design_path)), "traced.csv")
    if os.path.exists(traced):
        try:
            pts = np.loadtxt(traced, delimiter=",", skiprows=1)
            m = len(pts)
            tau = TAU * np.arange(m) / m
            # our tip at the same travel angles: B is smooth, read by trigonometric interpolation
            ours = np.stack([Trig(mo["B"][:, 0])(tau), Trig(mo["B"][:, 1])(tau)], -1)
            dev = float(np.max(np.linalg.norm(design.to_world(ours) - pts, axis=1)))
            rep.row("traced.csv vs our tip at the same carrier angles, max mm", dev, 1e-4,
                    dev <= 1e-4)
        except (ValueError, OSError) as e:
            rep.note(f"traced.csv not compared: {e}")
    return mo


def our_loads(design, scene, mo, mp):
    """Our loads on the grid of `mo` (CCW frame, SI): carrier torque by the power balance,
    planet mesh torque by the angular-momentum balance of planet gear + arm about A, frame force
    by Newton's law for the whole rotor, sun torque by the angular-momentum balance about O."""
    omega = TAU * scene.rpm / 60.0
    arms = scene.arms
    tau = mo["tau"]
    tau_deg = np.degrees(tau)
    g_vec = design.vec_to_ccw(G0 * scene.gravity_dir)  # m/s²
    mm = 1e-3

    m2, c2b, j2 = mp["intermediate"]
    m3, c3b, j3 = mp["planet"]
    ms, csb, _ = mp["sun"]
    ma, cab, ja = scene.arm_mass, scene.arm_com, scene.arm_inertia
    c2b, c3b, csb, cab = (design.vec_to_ccw(v) for v in (c2b, c3b, csb, cab))
    # inertia about each body's own centre of mass, kg·m²
    I2 = (j2 - m2 * float(c2b @ c2b)) * 1e-6
    I3 = (j3 - m3 * float(c3b @ c3b)) * 1e-6
    Ia = ja * 1e-6

    th2, th3 = mo["th2"], mo["th3"]
    bodies = [  # (mass, com position m, angle for the body spin, inertia about com)
        ("intermediate", m2, (mo["D"] + rot(th2, c2b)) * mm, "th2", I2),
        ("planet", m3, (mo["A"] + rot(th3, c3b)) * mm, "th3", I3),
        ("arm", ma, (mo["A"] + rot(th3, cab)) * mm, "th3", Ia),
    ]
    # angular speeds/accelerations: secular slope + spectral derivative of the periodic part
    spin = {}
    for key, slope in (("th2", mo["th2_turns"]), ("th3", 0)):
        p = mo[key] - slope * tau  # exactly periodic
        spin[key] = (
            omega * (slope + spectral_derivative(p, 1)),
            omega**2 * spectral_derivative(p, 2),
        )
    kin = []
    for name, m, G, key, I in bodies:
        v = omega * spectral_derivative(G, 1)
        acc = omega**2 * spectral_derivative(G, 2)
        kin.append((name, m, G, v, acc, spin[key][0], spin[key][1], I))
    B = mo["B"] * mm
    vB = omega * spectral_derivative(B, 1)
    A = mo["A"] * mm
    D = mo["D"] * mm

    n = len(tau)
    shift = n // arms

    def arm(x, k):
        return np.roll(x, -k * shift, axis=0)

    # kinetic energy, gravity power, needle power, linear and angular momentum rates
    E = np.zeros(n)
    P_grav = np.zeros(n)
    P_needle = np.zeros(n)
    m_total = 0.0
    sum_ma = np.zeros((n, 2))
    F_sum = np.zeros((n, 2))
    H = np.zeros(n)  # angular momentum about O of the moving bodies
    M_ext = np.zeros(n)  # moments about O of gravity on the moving bodies and of the needles
    for k in range(arms):
        for name, m, G, v, acc, w, alpha, I in kin:
            Gk, vk, ak, wk = arm(G, k), arm(v, k), arm(acc, k), arm(w, k)
            E += 0.5 * m * np.sum(vk * vk, axis=1) + 0.5 * I * wk**2
            P_grav += m * (vk @ g_vec)
            sum_ma += m * ak
            H += I * wk + m * cross(Gk, vk)
            M_ext += cross(Gk, m * np.broadcast_to(g_vec, Gk.shape))
            m_total += m
        Fk = design.vec_to_ccw(scene.needle_force((tau_deg + 360.0 * k / arms) % 360.0))
        P_needle += np.sum(Fk * arm(vB, k), axis=1)
        F_sum += Fk
        M_ext += cross(arm(B, k), Fk)
    dEdt = omega * spectral_derivative(E, 1)
    T_ours = (dEdt - P_grav - P_needle) / omega
    frame_ours = sum_ma - (m_total + ms) * g_vec - F_sum
    sun_com = csb * mm
    dHdt = omega * spectral_derivative(H, 1)
    sun_ours = dHdt - T_ours - M_ext - cross(sun_com, ms * g_vec)

    # planet mesh torque: angular momentum of planet gear + arm about A (first arm)
    F1 = design.vec_to_ccw(scene.needle_force(tau_deg))
    MA_ours = -cross(B - A, F1)
    for name, m, G, v, acc, w, alpha, I in kin:
        if name == "intermediate":
            continue
        MA_ours += I * alpha + cross(G - A, m * (acc - g_vec))

    return {
        "tau_deg": tau_deg, "T": T_ours, "MA": MA_ours, "frame": frame_ours, "sun": sun_ours,
        "E": E, "F1": F1, "A": A, "D": D, "n": n,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Independent rigid-body check of `ncgear loads` (numpy only)."
    )
    ap.add_argument("design")
    ap.add_argument("scene")
    ap.add_argument("loads", nargs="?")
    ap.add_argument("--tol", type=float, default=0.01,
                    help="max |ours − theirs| relative to the peak of theirs (default 0.01)")
    ap.add_argument("--inv-tol", type=float, default=1e-4,
                    help="tolerance of the report's own invariants, relative to the peak")
    ap.add_argument("--grid", type=int, default=0, help="our uniform grid (default ≥ 4096)")
    ap.add_argument("--dump", help="write our series to this .npz (debugging)")
    args = ap.parse_args(argv)

    rep = Report()
    try:
        design = Design(args.design)
        scene = Scene(args.scene)
    except (InputError, OSError, KeyError, ValueError) as e:
        print(f"check_loads: ERROR {e}", file=sys.stderr)
        return 2
    if scene.design_path and os.path.abspath(args.design) != scene.design_path:
        rep.note(f"the scene names {scene.design_path}; checking against {args.design}")

    loads = None
    if args.loads:
        try:
            with open(args.loads) as fh:
                loads = json.load(fh)
        except (OSError, ValueError) as e:
            print(f"check_loads: ERROR reading {args.loads}: {e}", file=sys.stderr)
            return 2

    # ---- our grid: a multiple of the report's samples (when uniform) and of the arms --------
    their_tau = None
    on_grid = False
    if loads is not None:
        their_tau = np.asarray(loads.get("travel_deg", []), dtype=float)
        if len(their_tau) < 8:
            print("check_loads: ERROR loads.json: no `travel_deg` samples", file=sys.stderr)
            return 2
        nt = len(their_tau)
        on_grid = np.max(np.abs(their_tau - 360.0 * np.arange(nt) / nt)) < 1e-9
    base = len(their_tau) if on_grid else 8
    base = base * scene.arms // math.gcd(base, scene.arms)
    target = args.grid or 4096
    n = base * max(1, -(-target // base))
    if n % 2:
        n *= 2

    # ---- kinematics ------------------------------------------------------------------------
    try:
        mo = check_kinematics(design, args.design, rep, n=n)
    except InputError as e:
        print(f"check_loads: ERROR {e}", file=sys.stderr)
        return 2

    # ---- mass properties -------------------------------------------------------------------
    ours_mp = {}
    if scene.gears is not None:
        stated = (loads or {}).get("gears") or {}
        try:
            face = scene.gears["face_width_mm"]
            if not isinstance(face, (int, float)):  # e.g. "auto": the width the report used
                if "face_width_mm" not in stated:
                    raise ValueError(f"face_width_mm = {face!r} and no width in loads.json")
                rep.note(f"face width {face!r} in the scene: the report's "
                         f"{float(stated['face_width_mm']):g} mm used")
                face = stated["face_width_mm"]
            face = float(face)
            dens = float(scene.gears["density_kg_m3"])
            bore = float(scene.gears.get("bore_mm", 0.0))
        except (KeyError, ValueError) as e:
            print(f"check_loads: ERROR scene [gears]: {e}", file=sys.stderr)
            return 2
        for name in ("sun", "intermediate", "planet"):
            ours_mp[name] = gear_mass_properties(design.tables_world[name], face, dens, bore)
    if loads is None:
        mp = {}
        for name in ("sun", "intermediate", "planet"):
            mass, com, inertia, _ = ours_mp.get(name, (0.0, np.zeros(2), 0.0, 1.0))
            mp[name] = (mass, com, inertia)
            rep.note(f"{name}: {mass:.4f} kg, com ({com[0]:.3f}, {com[1]:.3f}) mm, "
                     f"{inertia:.1f} kg·mm² (ours, from the pitch curve)")
        ours = our_loads(design, scene, mo, mp)
        if args.dump:
            np.savez(args.dump, **{k: v for k, v in ours.items() if k != "n"})
        rep.note(f"ours alone: peak carrier torque {np.max(np.abs(ours['T'])):.4g} Nm, "
                 f"peak planet mesh torque {np.max(np.abs(ours['MA'])):.4g} Nm, "
                 f"peak frame force {np.max(np.linalg.norm(ours['frame'], axis=1)):.4g} N")
        rep.print(f"kinematics and our loads for {args.design} (no loads.json given)")
        return finish(rep)

    try:
        gears = loads["gears"]
        mp = {}
        for name in ("sun", "intermediate", "planet"):
            g = gears.get(name) or {}
            mp[name] = (
                float(g.get("mass_kg", 0.0)),
                np.asarray(g.get("com_mm", [0.0, 0.0]), dtype=float),
                float(g.get("inertia_kg_mm2", 0.0)),
            )
    except (KeyError, TypeError, ValueError) as e:
        print(f"check_loads: ERROR loads.json gears: {e}", file=sys.stderr)
        return 2
    for name in ("sun", "intermediate", "planet"):
        if name not in ours_mp:
            if mp[name][0] != 0.0:
                rep.note(f"{name}: the scene has no [gears]; stated mass properties not checked")
            continue
        mass, com, inertia, rmean = ours_mp[name]
        tm, tc, ti = mp[name]
        e_m = abs(tm - mass) / mass
        e_c = float(np.linalg.norm(tc - com)) / rmean
        e_i = abs(ti - inertia) / inertia
        rep.row(f"{name} mass vs pitch region, rel", e_m, 0.05, e_m <= 0.05)
        rep.row(f"{name} com offset vs pitch region, /mean r", e_c, 0.05, e_c <= 0.05)
        rep.row(f"{name} inertia vs pitch region, rel", e_i, 0.05, e_i <= 0.05)

    needle_from_report = False
    needle_table = loads.get("needle_table_N")
    if scene.needle_other and needle_table:
        # the table the loads use (rows [travel_deg, Fx, Fy], linear between rows)
        tab = np.asarray(needle_table, dtype=float)
        scene.use_reported_needle(tab[:, 0], tab[:, 1:])
        needle_from_report = True
        rep.note("the scene's needle is not a force table: its table (needle_table_N, "
                 f"{len(tab)} rows) taken from loads.json as an input")
        nf = loads.get("needle_force_N")
        if nf is not None and len(nf) == len(their_tau):
            f = np.asarray(nf, dtype=float)
            e = float(np.max(np.abs(scene.needle_force(their_tau) - f)))
            pk = max(float(np.max(np.abs(f))), 1e-12)
            rep.row("needle force at the samples vs needle_table_N, max err / peak", e / pk,
                    1e-9, e / pk <= 1e-9)
    elif scene.needle_other:
        nf = loads.get("needle_force_N")
        if nf is None or len(nf) != len(their_tau):
            print("check_loads: ERROR the scene's needle has no force_N table and loads.json "
                  "states no needle_force_N to take it from", file=sys.stderr)
            return 2
        if not on_grid or len(their_tau) % scene.arms:
            rep.note("needle force from the report: other arms read between its samples")
        scene.use_reported_needle(their_tau, nf)
        needle_from_report = True
        rep.note("the scene's needle is not a force table: its force (first arm, per arm by "
                 "travel angle) taken from loads.json as an input")
    ours = our_loads(design, scene, mo, mp)
    tau_deg, T_ours, MA_ours = ours["tau_deg"], ours["T"], ours["MA"]
    frame_ours, sun_ours, F1 = ours["frame"], ours["sun"], ours["F1"]
    A, D, arms = ours["A"], ours["D"], scene.arms

    if args.dump:
        np.savez(args.dump, **{k: v for k, v in ours.items() if k != "n"})

    # ---- compare at the report's samples ---------------------------------------------------
    nt = len(their_tau)
    if on_grid:
        idx = np.arange(nt) * (n // nt)

        def at(x):
            return x[idx]
    else:
        rep.note("travel_deg is not a uniform grid from 0: our series read by interpolation")

        def at(x):
            return np.stack([np.interp(their_tau, tau_deg, col, period=360.0)
                             for col in np.atleast_2d(x.T)], -1).squeeze()

    def compare(label, ours, theirs, vector=False, key=None):
        ours = at(ours)
        if theirs.shape != ours.shape:
            rep.fail(f"{label}: {theirs.shape[0] if theirs.ndim else 0} values in loads.json "
                     f"for {len(their_tau)} travel_deg samples (shape {theirs.shape}, expected "
                     f"{ours.shape})")
            return None
        if vector:
            peak = float(np.max(np.linalg.norm(theirs, axis=1)))
            errs = [float(np.max(np.abs(ours[:, i] - theirs[:, i]))) for i in (0, 1)]
            for i, axis in enumerate("xy"):
                rel = errs[i] / peak if peak > 0 else errs[i]
                rep.row(f"{label} {axis}, max err / peak |F| ({peak:.4g} N)", rel, args.tol,
                        rel <= args.tol)
                if key:
                    rep.key[key + axis] = rel
            return peak
        peak = float(np.max(np.abs(theirs)))
        err = float(np.max(np.abs(ours - theirs)))
        rel = err / peak if peak > 0 else err
        rep.row(f"{label}, max err / peak ({peak:.4g})", rel, args.tol, rel <= args.tol)
        if key:
            rep.key[key] = rel
        return peak

    try:
        T_th = arr(loads, "carrier_torque_Nm", "carrier_torque_Nm")
        MA_th = arr(loads, "planet_mesh_torque_Nm", "planet_mesh_torque_Nm")
        frame_th = design.vec_to_ccw(arr(loads, "frame_force_N", "frame_force_N"))
    except InputError as e:
        print(f"check_loads: ERROR {e}", file=sys.stderr)
        return 2
    peak_T = compare("carrier torque Nm", T_ours, T_th, key="T")
    compare("planet mesh torque Nm", MA_ours, MA_th, key="M_A")
    compare("frame force N", frame_ours, frame_th, vector=True, key="F")
    if "sun_torque_Nm" in loads:
        compare("sun torque Nm", sun_ours, np.asarray(loads["sun_torque_Nm"], dtype=float),
                key="T_sun")

    # needle force as stated
    if not needle_from_report and loads.get("needle_force_N") is not None:
        nf = design.vec_to_ccw(np.asarray(loads["needle_force_N"], dtype=float))
        e = float(np.max(np.abs(at(F1) - nf))) if nf.shape == at(F1).shape else math.inf
        pk = max(float(np.max(np.abs(nf))) if nf.size else 0.0, 1e-12)
        rep.row("needle force as stated vs scene table, max err / peak", e / pk, 1e-9,
                e / pk <= 1e-9)

    # reversals
    rev_ours = crossings(their_tau, at(MA_ours))
    rev_th = list((loads.get("summary") or {}).get("reversals_deg") or [])
    worst = 0.0
    unmatched = []
    for x in rev_ours:
        d = min((angle_gap(x, y) for y in rev_th), default=math.inf)
        worst = max(worst, d)
        if d > 1.0:
            unmatched.append(f"ours {x:.2f}°")
    for y in rev_th:
        d = min((angle_gap(x, y) for x in rev_ours), default=math.inf)
        worst = max(worst, d)
        if d > 1.0:
            unmatched.append(f"theirs {y:.2f}°")
    rep.key["rev_gap_deg"] = worst if (rev_ours or rev_th) else 0.0
    if rev_ours or rev_th:
        rep.row(f"reversals ({len(rev_ours)} ours, {len(rev_th)} theirs), worst gap deg",
                worst, 1.0, not unmatched, "°")
        if unmatched:
            rep.note("reversals unmatched: " + ", ".join(unmatched)
                     + f"; ours {[round(x, 2) for x in rev_ours]}, theirs "
                     + f"{[round(float(y), 2) for y in rev_th]}")
    else:
        rep.note("no reversal in either")

    # ---- invariants of the report itself ---------------------------------------------------
    try:
        brg = loads["bearings"]
        RO = design.vec_to_ccw(np.asarray(brg["O_N"], dtype=float))
        RD = design.vec_to_ccw(np.asarray(brg["D_N"], dtype=float))
        RA = design.vec_to_ccw(np.asarray(brg["A_N"], dtype=float))
    except (KeyError, TypeError, ValueError) as e:
        rep.fail(f"loads.json bearings: {e}")
        RO = None
    if RO is not None:
        if nt % arms == 0:
            sh = nt // arms
            sumR = sum(np.roll(RD + RA, -k * sh, axis=0) for k in range(arms))
            tq = sum(
                cross(np.roll(at(D), -k * sh, axis=0), np.roll(RD, -k * sh, axis=0))
                + cross(np.roll(at(A), -k * sh, axis=0), np.roll(RA, -k * sh, axis=0))
                for k in range(arms)
            )
            pk = max(float(np.max(np.linalg.norm(RO, axis=1))), 1e-12)
            e = float(np.max(np.linalg.norm(sumR - RO, axis=1))) / pk
            rep.row("invariant O = Σ arms (D + A), max err / peak |O|", e, args.inv_tol,
                    e <= args.inv_tol)
            pk = max(peak_T or 0.0, 1e-12)
            e = float(np.max(np.abs(tq - T_th))) / pk
            rep.row("invariant T = Σ (D × R_D + A × R_A), max err / peak T", e, args.inv_tol,
                    e <= args.inv_tol)
        else:
            rep.note(f"{nt} samples not divisible by {arms} arms: bearing invariants skipped")
    meshes = loads.get("meshes") or {}
    for name in ("sun_intermediate", "intermediate_planet"):
        m_ = meshes.get(name)
        if m_ is None:
            rep.fail(f"loads.json: no meshes.{name}")
            continue
        f = np.asarray(m_.get("normal_force_N", []), dtype=float)
        if f.shape != (nt,):
            rep.fail(f"meshes.{name}.normal_force_N: {f.shape} values, expected {nt}")
            continue
        rep.row(f"{name} normal force ≥ 0: most negative, N", max(0.0, -float(np.min(f))), 0.0,
                float(np.min(f)) >= 0.0, "")
        pp = m_.get("pitch_point_mm")
        if pp is not None:
            pp = np.asarray(pp, dtype=float)
            mine = at(mo["P1" if name == "sun_intermediate" else "P2"])
            if pp.shape == mine.shape:
                e = float(np.max(np.linalg.norm(design.to_world(mine) - pp, axis=1)))
                rep.row(f"{name} pitch point vs ours, max mm", e, 1e-3, e <= 1e-3)
            else:
                rep.fail(f"meshes.{name}.pitch_point_mm: shape {pp.shape}, expected {mine.shape}")
        fl = np.asarray(m_.get("flank", []), dtype=float)
        if fl.shape == (nt,) and not np.all(np.isin(fl, (-1.0, 0.0, 1.0))):
            rep.fail(f"meshes.{name}.flank: values other than −1, 0, +1")

    rep.print(f"{args.loads} against the independent model ({n} samples, {arms} arm(s), "
              f"{scene.rpm:g} rpm)")
    print("check_loads: errors / peak: "
          + ", ".join(f"{k} {v:.2e}" if k != "rev_gap_deg" else f"reversal gap {v:.3f}°"
                      for k, v in rep.key.items()))
    return finish(rep)


def finish(rep):
    if rep.failures:
        print("check_loads: FAILED")
        for f in rep.failures:
            print(f"  - {f}")
        return 1
    print("check_loads: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
