#!/usr/bin/env python3
"""Independent check of `ncgear dynamics` on a rotor scene (numpy + scipy; no code shared with the
crate).

Usage:
    python3 scripts/check_rotor.py DESIGN.json SCENE.toml DYNAMICS.json LOADS.json
        [--tol-force 0.02] [--tol-tip 0.02] [--tip-floor-um 1] [--tol-loss-deg 1]
        [--rtol 1e-10] [--poincare-tol 1e-6] [--max-turns 12] [--case NAME]

SCENE.toml is the dynamics scene (`[scene] model = "rotor"`), DYNAMICS.json what `ncgear dynamics`
wrote for it, LOADS.json what `ncgear loads` wrote for the same tables (its `gears` mass
properties, its flanks and forces at travel 0 for the start, and, for a needle given as
`profile = "planting"`, its `needle_table_N` (the rows the crate's table has, linear between
them; `needle_force_N` at the samples when a report lacks it): the inputs taken from it, as
scripts/check_loads.py takes them). Everything else is rebuilt here:

* Kinematics: scripts/check_loads.py's `Design.motion` (imported, not copied): its own rolling
  formulation of the train from design.json's pitch tables, CCW frame (a CW design mirrored
  y -> -y). Rates θ′(φ) and the body vectors' derivatives by FFT on a fine uniform grid; between
  grid points the carrier-angle functions are read by cubic Hermite interpolation (values and
  spectral derivatives; error ~h⁴, h = 2π/(16 × the samples); against a grid twice as fine,
  < 2e-11 of each function's peak, most of it the finer grid's own RK4 planet angle).
* Mesh geometry, own: at each pitch point P the common tangent t of the pitch curves (from the
  driver's polar curve, r′·e_r + r·e_θ), oriented counter-clockwise about the driven gear's axis,
  n = t turned +90° (towards the driven axis); the line of action of flank s = ±1 is
  l_s = sin α·n + s·cos α·t (α the rack's pressure angle); the lever arms ρ = (P − C) × l_s of
  the driver and the driven gear. The approach along the line is δ_s = ρ_drv·q_drv − ρ_drn·q_drn
  (the sun fixed); δ₊ and δ₋ have opposite signs.
* Contact: a hybrid automaton per mesh, mode ∈ {flank +1, flank −1, free}. In contact on flank
  s, F = k·(δ_s − b) + c·(dδ_s/dt) (no clamp); free, F = 0. b is half the normal backlash (the
  dead zone ±b on the line of action). The mode changes at the zeros of δ_s − b: in contact, the
  crossing downward (contact loss); free, either flank's crossing upward (re-contact, which may
  be on the other flank). The zeros are located as terminal events of solve_ivp (dense output,
  root to machine precision) and the integration restarts in the new mode, so no step straddles
  a discontinuity of the right-hand side. For 1e-12 of a turn after a restart the new mode's
  events keep their mode's side (the root just found, ±1e-21 m, is not found again).
  The damping acts on the approach's rate dδ_s/dt = v_s + Ω·(ρ′_drv·q_drv − ρ′_drn·q_drn)
  (v_s = ρ_drv·q̇_drv − ρ_drn·q̇_drn; ρ′ the lever arms' spectral derivatives in φ), as
  docs/dynamics.md states. `--damping-speed levers` takes v_s instead (ncgear's model before
  2026-12-02, whose damper could hold the flanks on the dead zone's edge: a sliding chatter).
* Equations of motion, own formulation: Lagrange's equations in Hamiltonian (first-order) form
  on the generalized coordinates q = (Δθ2, Δθ3), the rotations of the intermediate and of the
  planet (+ arm) away from the kinematic law, with the generalized momenta
  p_i = ∂T/∂q̇_i = v_C·(ẑ × S_i) + J_i·ω_i as states:
        T_i = ½ m_i|v_C|² + ω_i·v_C·(ẑ × S_i) + ½ J_i ω_i²,   ω_i = Ω·θ_i′(φ) + q̇_i,
        q̇_i = (p_i − v_C·(ẑ × S_i))/J_i − Ω·θ_i′(φ),
        ṗ_i = ∂T/∂q_i − ∂V/∂q_i + Q_i = −ω_i·(v_C·S_i) + S_i × g + Σ_meshes ±F·ρ + Q_i,
  S_i = R(θ_kin + q_i)·S_body (first moment about the moving axis C, kg·m), J_i about the axis,
  Q_3 ∋ (B − A) × F_needle, and the vibration damping's −c_i·q̇_i. This needs only the first
  derivatives of the kinematics (v_C = Ω·C′(φ), θ′), not the accelerations the Newton–Euler form
  of the crate uses. The carrier turns at exactly Ω (φ = Ωt); train 1 alone is integrated.
* Damping (docs/dynamics.md): mesh c_j = 2ζ_j·√(k̄_j·m_e,j) with k̄ the (constant) stiffness,
  m_e = J_D/ρ̄_D² (sun mesh), J_D·J_A/(J_D·ρ̄_A² + J_A·ρ̄_D′²) (planet mesh), ρ̄ the turn's mean
  |ρ| of flank +1; vibration damping c_i = 2ζ·J_i·ω₁, ω₁ the lowest eigenvalue of M⁻¹K
  (M = diag(J_D, J_A), K = Σ k̄_j g_j g_jᵀ, g_1 = (−ρ̄_D, 0), g_2 = (ρ̄_D′, −ρ̄_A)).
* Stiffness: `kind = "constant"`, k = c·b (N/mm per mm of face width, b the face width);
  `kind = "iso"` with `pairs = "mean"`: ISO 6336-1:2006 clause 9 on the local equivalent spur
  pair, from docs/dynamics.md's formulas (radii = the pitch curves' signed radii of curvature
  (r² + r′²)^{3/2}/(r² + 2r′² − r·r″) at the contact, z_n = 2ρ/m, q′ = 0.04723 + 0.15551/z_n1
  + 0.25791/z_n2 with 1 the driver, c′ = 0.8·C_B/q′, C_B = [1 + 0.5(1.2 − h_fP/m)]·[1 −
  0.02(20° − α)], c_γα = c′(0.75·ε_α + 0.25), ε_α of the pair with addendum h_a·m), × b × the
  scene's scale, by travel; k̄ its mean over the turn. Convex pairs only; the pairs alternating
  and concave contacts are not modelled here (exit 2).
* Integration: scipy's DOP853 (rtol 1e-10), piecewise between the report's samples and the
  needle table's knots (its kinks), events as above. Turns from the quasi-static start (the
  deflections that carry loads.json's forces at travel 0 on its flanks, at rest relative to the
  kinematic law) until the periodic residual max|y(T) − y(0)|/max|y| (deviations and their
  rates) is below --poincare-tol; the last turn is compared.

Compared with DYNAMICS.json on its samples: each mesh's dynamic normal force (max difference /
its peak ≤ --tol-force), the tip's distance from its static path (the nearest point of the
static polyline within ±45° of travel, as ncgear searches it; max difference / its peak ≤
--tol-tip, or ≤ the absolute --tip-floor-um when the peak is below 50 × that floor: without
backlash the deviation is a few µm, and 2 % of it, 0.1 µm, is below what the comparison of two
polyline distances resolves at 0.5° samples), each mesh's contact-loss intervals as resolved to
--resolve-deg of travel (0.01°, 6 µs at 300 r/min, a twentieth of the fastest mode's period:
contacts and flights shorter than that, the chatter of a sliding stretch, joined or dropped on
both sides; every interval of either side matched by one of the other, both ends within
--tol-loss-deg of travel), and the
linearised natural frequencies (0.1 %). A table per case is printed. Exit 0 when every check
passes, 1 otherwise, 2 on unusable input.
"""

import argparse
import json
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

try:
    import numpy as np
    from scipy.integrate import solve_ivp
except ImportError as e:  # pragma: no cover
    print(f"check_rotor: ERROR needs numpy and scipy: {e}", file=sys.stderr)
    sys.exit(2)

import check_loads as cl  # noqa: E402  (the kinematics, the needle table, the TOML reader)

TAU = 2.0 * math.pi
G0 = cl.G0


class InputError(Exception):
    pass


# ----------------------------------------------------------------------------------------------
# Scene effects
# ----------------------------------------------------------------------------------------------


def pair(v, what):
    """A number or [a, b] -> [a, b] floats."""
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return [float(v), float(v)]
    if isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) for x in v):
        return [float(v[0]), float(v[1])]
    raise InputError(f"{what}: expected a number or [sun, planet], got {v!r}")


class Effects:
    def __init__(self, raw, design_raw):
        sc = raw.get("scene") or {}
        if sc.get("model") != "rotor":
            raise InputError("[scene] model is not \"rotor\"")
        eff = raw.get("effects")
        if eff is None:
            raise InputError("no [effects] table")
        st = eff.get("mesh_stiffness")
        if not isinstance(st, dict) or "kind" not in st:
            raise InputError("effects.mesh_stiffness: expected { kind = ... }")
        teeth = design_raw.get("teeth") or {}
        opts = teeth.get("options") or {}
        rack = opts.get("rack") or {}
        self.iso = st["kind"] == "iso"
        if self.iso:
            if st.get("pairs", "alternating") != "mean":
                raise InputError("effects.mesh_stiffness: ISO with the pairs alternating is not "
                                 "modelled by this check (pairs = \"mean\" is)")
            if not teeth or "alpha_rad" not in rack:
                raise InputError("effects.mesh_stiffness: kind = \"iso\" and the design has no "
                                 "teeth")
            self.iso_scale = float(st.get("scale", 1.0))
            if not (self.iso_scale > 0 and math.isfinite(self.iso_scale)):
                raise InputError("effects.mesh_stiffness.scale must be positive")
            self.module_mm = float(teeth.get("module_mm") or opts["module_mm"])
            self.addendum = float(rack.get("addendum", 1.0))
            self.dedendum = self.addendum + float(rack.get("clearance", 0.25))
            self.c_spec = None
        elif st["kind"] == "constant":
            if "c_n_per_mm_mm" not in st:
                raise InputError("effects.mesh_stiffness: constant needs c_n_per_mm_mm")
            self.c_spec = pair(st["c_n_per_mm_mm"], "effects.mesh_stiffness.c_n_per_mm_mm")
            if any(not (c > 0 and math.isfinite(c)) for c in self.c_spec):
                raise InputError("effects.mesh_stiffness.c_n_per_mm_mm must be positive")
        else:
            raise InputError(f"effects.mesh_stiffness.kind = {st['kind']!r}: expected "
                             "\"constant\" or \"iso\"")
        md = eff.get("mesh_damping")
        self.zeta = pair(md["zeta"], "effects.mesh_damping.zeta") if md else [0.0, 0.0]
        self.alpha_teeth = rack.get("alpha_rad")
        bl = eff.get("backlash")
        if bl is None:
            self.backlash_mm = [0.0, 0.0]
        elif bl == "teeth":
            if "backlash_mm" not in opts or self.alpha_teeth is None:
                raise InputError("effects.backlash = \"teeth\" and the design has no teeth")
            jn = float(opts["backlash_mm"]) * math.cos(float(self.alpha_teeth))
            self.backlash_mm = [jn, jn]
        else:
            self.backlash_mm = pair(bl, "effects.backlash")
        if any(b < 0 or not math.isfinite(b) for b in self.backlash_mm + self.zeta):
            raise InputError("effects: negative backlash or damping ratio")
        vd = eff.get("vibration_damping")
        self.vib_zeta = float(vd["zeta"]) if vd else 0.0
        if eff.get("drive") is not None:
            raise InputError("effects.drive: a compliant drive is not modelled (nor by ncgear)")
        steady = raw.get("steady") or {}
        self.scene_poincare_tol = float(steady.get("poincare_tol", 1e-6))


# ----------------------------------------------------------------------------------------------
# Carrier-angle functions: a table on a uniform grid, read by cubic Hermite interpolation
# ----------------------------------------------------------------------------------------------


class PhiTable:
    """Periodic functions f_k(φ) sampled on a uniform grid over [0, 2π): values and spectral
    derivatives, read by cubic Hermite interpolation (C¹, error O(h⁴))."""

    def __init__(self, cols):
        self.names = list(cols)
        F = np.stack([np.asarray(cols[k], dtype=float) for k in self.names], axis=1)
        self.n = F.shape[0]
        self.h = TAU / self.n
        dF = cl.spectral_derivative(F, 1, axis=0)
        self.F = np.vstack([F, F[:1]])
        self.D = np.vstack([dF, dF[:1]]) * self.h
        self.index = {k: i for i, k in enumerate(self.names)}

    def __call__(self, phi):
        u = (phi % TAU) / self.h
        i = int(u)
        if i >= self.n:
            i = self.n - 1
        s = u - i
        s2 = s * s
        s3 = s2 * s
        return ((2 * s3 - 3 * s2 + 1) * self.F[i] + (s3 - 2 * s2 + s) * self.D[i]
                + (3 * s2 - 2 * s3) * self.F[i + 1] + (s3 - s2) * self.D[i + 1])


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def perp(v):
    return np.stack([-v[..., 1], v[..., 0]], -1)


def mesh_levers(P, t_raw, C_drv, C_drn, alpha):
    """Lever arms of flanks [+1, −1] on (driver, driven) at pitch points P (N,2) with the raw
    common tangent t_raw (N,2); C the axes (N,2) or (2,). Returns dict of (N,) arrays (mm)."""
    t = unit(t_raw)
    flip = cl.cross(P - C_drn, t) < 0
    t = np.where(flip[:, None], -t, t)
    n = perp(t)  # towards the driven axis
    out = {}
    for s, tag in ((1.0, "p"), (-1.0, "m")):
        l = math.sin(alpha) * n + s * math.cos(alpha) * t
        out["drv_" + tag] = cl.cross(P - C_drv, l)
        out["drn_" + tag] = cl.cross(P - C_drn, l)
        out["line_" + tag] = l
    # the driven gear's normal must point to its axis
    assert np.all(np.sum(n * (C_drn - P), axis=-1) > 0), "normal not towards the driven axis"
    return out


def radius_of_curvature(curve, u):
    """Signed radius of curvature of the polar curve r(u) (mm; negative where concave)."""
    r, r1, r2 = curve(u), curve(u, deriv=1), curve(u, deriv=2)
    return (r * r + r1 * r1) ** 1.5 / (r * r + 2.0 * r1 * r1 - r * r2)


def iso_mesh_stiffness(rho1, rho2, eff, alpha, face_mm):
    """ISO 6336-1:2006 clause 9 on the local equivalent spur pair (docs/dynamics.md), pairs
    "mean": the mean mesh stiffness c_γα·b over a base pitch, N/m. rho1, rho2 the driver's and
    the driven gear's pitch radii (mm, the pitch curves' radii of curvature at the contact);
    only convex pairs (external gears) are modelled here."""
    if np.any(rho1 <= 0) or np.any(rho2 <= 0):
        raise InputError("ISO stiffness: a concave pitch curve at the contact (an internal "
                         "equivalent gear) is not modelled by this check")
    m = eff.module_mm
    zn1, zn2 = 2.0 * rho1 / m, 2.0 * rho2 / m
    q = 0.04723 + 0.15551 / zn1 + 0.25791 / zn2  # no profile shift
    alpha_deg = math.degrees(alpha)
    cb = (1.0 + 0.5 * (1.2 - eff.dedendum)) * (1.0 - 0.02 * (20.0 - alpha_deg))
    c_single = 0.8 * cb / q  # c′ = c′_th·C_M·C_R·C_B, C_M = 0.8, C_R = 1, N/(mm·µm)
    ha = eff.addendum * m
    rb1, rb2 = rho1 * math.cos(alpha), rho2 * math.cos(alpha)
    ra1, ra2 = rho1 + ha, rho2 + ha
    a = rho1 + rho2
    eps_a = (np.sqrt(ra1**2 - rb1**2) + np.sqrt(ra2**2 - rb2**2) - a * math.sin(alpha)) / (
        math.pi * m * math.cos(alpha))
    c_gamma = c_single * (0.75 * eps_a + 0.25)  # N/(mm·µm)
    return eff.iso_scale * c_gamma * face_mm * 1e6, eps_a


# ----------------------------------------------------------------------------------------------
# The model
# ----------------------------------------------------------------------------------------------


class Rotor:
    def __init__(self, design, scene, eff, loads, face_mm, alpha, n_grid, rate_damping=False):
        self.design, self.scene, self.eff = design, scene, eff
        self.omega = TAU * scene.rpm / 60.0
        self.alpha = alpha
        mo = design.motion(n_grid)
        self.mo = mo
        tau = mo["tau"]
        mm = 1e-3
        # mass properties (loads.json `gears`, body frames mirrored to CCW as check_loads does)
        g = loads["gears"]

        def mp(name):
            x = g[name]
            return (float(x["mass_kg"]), design.vec_to_ccw(np.asarray(x["com_mm"], dtype=float)),
                    float(x["inertia_kg_mm2"]))

        m2, c2b, j2 = mp("intermediate")
        m3, c3b, j3 = mp("planet")
        ma, cab, ia = scene.arm_mass, design.vec_to_ccw(scene.arm_com), scene.arm_inertia
        self.J = [j2 * 1e-6, (j3 + ia + ma * float(cab @ cab)) * 1e-6]  # about the axes, kg·m²
        S2b = m2 * c2b * mm
        S3b = (m3 * c3b + ma * cab) * mm  # kg·m
        th2, th3 = mo["th2"], mo["th3"]
        p2 = th2 - mo["th2_turns"] * tau
        w2k = mo["th2_turns"] + cl.spectral_derivative(p2, 1)
        w3k = cl.spectral_derivative(th3, 1)
        D, A = mo["D"] * mm, mo["A"] * mm
        dD = cl.spectral_derivative(D, 1, axis=0)
        dA = cl.spectral_derivative(A, 1, axis=0)
        S2 = cl.rot(th2, S2b)
        S3 = cl.rot(th3, S3b)
        bk = (mo["B"] - mo["A"]) * mm
        # pitch points and tangents (mm): sun mesh on the sun's curve at u = φ + ε (sun fixed),
        # planet mesh on the intermediate's curve at body angle c2, world angle φ − ε
        eps = design.eps
        sun, mid = design.curve["sun"], design.curve["intermediate"]
        u1 = tau + eps
        r1, dr1 = sun(u1), sun(u1, deriv=1)
        e1, e1p = np.stack([np.cos(u1), np.sin(u1)], -1), np.stack([-np.sin(u1), np.cos(u1)], -1)
        t1 = dr1[:, None] * e1 + r1[:, None] * e1p
        psi = tau - eps
        r2, dr2 = mid(mo["c2"]), mid(mo["c2"], deriv=1)
        e2, e2p = np.stack([np.cos(psi), np.sin(psi)], -1), np.stack([-np.sin(psi), np.cos(psi)], -1)
        t2 = dr2[:, None] * e2 + r2[:, None] * e2p
        P1, P2 = mo["P1"] * mm, mo["P2"] * mm
        L1 = mesh_levers(P1, t1, np.zeros(2), D, alpha)
        L2 = mesh_levers(P2, t2, D, A, alpha)
        self.L1, self.L2 = L1, L2
        # sanity: the pitch point lies on the line of centres, so the flanks' approaches for
        # the same rotation have opposite signs: ρ(+)·ρ(−) < 0 for each gear
        for L, nm in ((L1, "sun mesh"), (L2, "planet mesh")):
            for gear in ("drn",) if L is L1 else ("drv", "drn"):
                if np.any(L[gear + "_p"] * L[gear + "_m"] >= 0):
                    raise InputError(f"{nm}: the flanks' lever arms do not have opposite signs")
        cols = {}
        if eff.iso:
            pla = design.curve["planet"]
            rho_sun = radius_of_curvature(sun, u1)
            rho_int1 = radius_of_curvature(mid, tau + eps + math.pi - th2)
            rho_int2 = radius_of_curvature(mid, mo["c2"])
            rho_pla = radius_of_curvature(pla, mo["c3"])
            k1, e1_ = iso_mesh_stiffness(rho_sun, rho_int1, eff, alpha, face_mm)
            k2, e2_ = iso_mesh_stiffness(rho_int2, rho_pla, eff, alpha, face_mm)
            cols = {"k1": k1, "k2": k2}
            self.iso_eps = (e1_, e2_)
        if rate_damping:  # the levers' rates, for the damping on dδ/dt (--damping-speed rate)
            for nm_, v_ in (("r1p", L1["drn_p"]), ("r1m", L1["drn_m"]), ("r2dp", L2["drv_p"]),
                            ("r2dm", L2["drv_m"]), ("r2np", L2["drn_p"]), ("r2nm", L2["drn_m"])):
                cols["d" + nm_] = self.omega * cl.spectral_derivative(v_, 1)
        self.rate_damping = rate_damping
        self.n_pre = len(cols)
        self.table = PhiTable({**cols,
            "vDx": self.omega * dD[:, 0], "vDy": self.omega * dD[:, 1],
            "vAx": self.omega * dA[:, 0], "vAy": self.omega * dA[:, 1],
            "S2x": S2[:, 0], "S2y": S2[:, 1], "S3x": S3[:, 0], "S3y": S3[:, 1],
            "w2k": w2k, "w3k": w3k, "bx": bk[:, 0], "by": bk[:, 1],
            "r1p": L1["drn_p"], "r1m": L1["drn_m"],
            "r2dp": L2["drv_p"], "r2dm": L2["drv_m"], "r2np": L2["drn_p"], "r2nm": L2["drn_m"],
        })
        self.static_tip_mm = mo["B"]
        # stiffness (N/m: constant, or ISO's by travel with its mean), damping
        if eff.iso:
            self.k = [float(np.mean(cols["k1"])), float(np.mean(cols["k2"]))]  # the means
        else:
            self.k = [c * face_mm * 1e3 for c in eff.c_spec]
        self.b = [0.5 * x * 1e-3 for x in eff.backlash_mm]  # half the normal backlash, m
        rD = float(np.mean(np.abs(L1["drn_p"])))
        rD2 = float(np.mean(np.abs(L2["drv_p"])))
        rA = float(np.mean(np.abs(L2["drn_p"])))
        JD, JA = self.J
        me = [JD / rD**2, JD * JA / (JD * rA**2 + JA * rD2**2)]
        self.m_e = me
        self.c = [2.0 * eff.zeta[j] * math.sqrt(self.k[j] * me[j]) for j in (0, 1)]
        K = (self.k[0] * np.outer([-rD, 0.0], [-rD, 0.0])
             + self.k[1] * np.outer([rD2, -rA], [rD2, -rA]))
        Mh = np.diag([JD**-0.5, JA**-0.5])
        lam = np.linalg.eigvalsh(Mh @ K @ Mh)
        self.freqs_hz = np.sqrt(np.maximum(lam, 0.0)) / TAU
        w1 = TAU * self.freqs_hz[0]
        self.cv = [2.0 * eff.vib_zeta * J * w1 for J in self.J]
        gdir = scene.gravity_dir
        self.g = design.vec_to_ccw(G0 * gdir)  # m/s², CCW frame
        self.evals = 0

    # needle force: linear between the table's rows, CCW frame; per segment a linear function
    def needle_knots_deg(self):
        if self.scene.needle is None:
            return []
        return sorted(set(float(x) % 360.0 for x in self.scene.needle[:, 0]))

    def needle_ccw(self, travel_deg):
        return self.design.vec_to_ccw(self.scene.needle_force(np.atleast_1d(travel_deg)))[0]

    # the state's kinematic pieces
    def unpack(self, phi, y):
        f = self.table(phi).tolist()
        pre, f = f[: self.n_pre], f[self.n_pre:]
        if self.eff.iso:
            self.k_now = pre[:2]
        if self.rate_damping:
            d = pre[-6:]  # Ω·ρ′ of r1p, r1m, r2dp, r2dm, r2np, r2nm
            self.lever_rates = ((d[0], d[1]), ((d[2], d[4]), (d[3], d[5])))
        (vDx, vDy, vAx, vAy, S2x, S2y, S3x, S3y, w2k, w3k, bx, by,
         r1p, r1m, r2dp, r2dm, r2np, r2nm) = f
        q2, q3, p2, p3 = y
        c, s = math.cos(q2), math.sin(q2)
        S2 = (c * S2x - s * S2y, s * S2x + c * S2y)
        c3, s3 = math.cos(q3), math.sin(q3)
        S3 = (c3 * S3x - s3 * S3y, s3 * S3x + c3 * S3y)
        JD, JA = self.J
        w2 = (p2 - (vDx * -S2[1] + vDy * S2[0])) / JD
        w3 = (p3 - (vAx * -S3[1] + vAy * S3[0])) / JA
        qd2 = w2 - self.omega * w2k
        qd3 = w3 - self.omega * w3k
        b = (c3 * bx - s3 * by, s3 * bx + c3 * by)
        lev = ((r1p, r1m), ((r2dp, r2np), (r2dm, r2nm)))
        return S2, S3, w2, w3, qd2, qd3, b, (vDx, vDy, vAx, vAy), lev

    @staticmethod
    def approach(lev, j, flank, q2, q3):
        """δ_s of mesh j, flank index (0: +1, 1: −1)."""
        if j == 0:
            return -lev[0][flank] * q2
        rd, rn = lev[1][flank]
        return rd * q2 - rn * q3

    def forces(self, phi, y, modes):
        """Mesh forces (N) for the modes [(flank index or None), ...] and the pieces."""
        S2, S3, w2, w3, qd2, qd3, b, v, lev = self.unpack(phi, y)
        q2, q3 = y[0], y[1]
        F = [0.0, 0.0]
        for j in (0, 1):
            f = modes[j]
            if f is None:
                continue
            d = self.approach(lev, j, f, q2, q3)
            vd = self.approach(lev, j, f, qd2, qd3)
            if self.rate_damping:  # dδ/dt = v_s + Ω·(ρ′_drv·q_drv − ρ′_drn·q_drn)
                vd += self.approach(self.lever_rates, j, f, q2, q3)
            k = self.k_now[j] if self.eff.iso else self.k[j]
            F[j] = k * (d - self.b[j]) + self.c[j] * vd
        return F, (S2, S3, w2, w3, qd2, qd3, b, v, lev)

    def rhs(self, t, y, modes, fn0, fn1, phi0):
        self.evals += 1
        phi = self.omega * t
        F, (S2, S3, w2, w3, qd2, qd3, b, v, lev) = self.forces(phi, y, modes)
        vDx, vDy, vAx, vAy = v
        gx, gy = self.g
        Q2 = S2[0] * gy - S2[1] * gx - self.cv[0] * qd2
        Q3 = S3[0] * gy - S3[1] * gx - self.cv[1] * qd3
        if modes[0] is not None:
            Q2 += F[0] * lev[0][modes[0]]
        if modes[1] is not None:
            rd, rn = lev[1][modes[1]]
            Q2 -= F[1] * rd
            Q3 += F[1] * rn
        fx = fn0[0] + (phi - phi0) * fn1[0]
        fy = fn0[1] + (phi - phi0) * fn1[1]
        Q3 += b[0] * fy - b[1] * fx
        dp2 = -w2 * (vDx * S2[0] + vDy * S2[1]) + Q2
        dp3 = -w3 * (vAx * S3[0] + vAy * S3[1]) + Q3
        return [qd2, qd3, dp2, dp3]

    def gap(self, t, y, j, f):
        phi = self.omega * t
        ff = self.table(phi)
        idx = self.table.index
        if j == 0:
            rho = ff[idx["r1p"] if f == 0 else idx["r1m"]]
            d = -rho * y[0]
        else:
            rd = ff[idx["r2dp"] if f == 0 else idx["r2dm"]]
            rn = ff[idx["r2np"] if f == 0 else idx["r2nm"]]
            d = rd * y[0] - rn * y[1]
        return d - self.b[j]

    def momenta(self, phi, q, qd):
        """p from q, q̇ at φ."""
        f = self.table(phi)
        i = self.table.index
        out = []
        for k, (C, S, w) in enumerate(((("vDx", "vDy"), ("S2x", "S2y"), "w2k"),
                                       (("vAx", "vAy"), ("S3x", "S3y"), "w3k"))):
            c, s = math.cos(q[k]), math.sin(q[k])
            Sx0, Sy0 = f[i[S[0]]], f[i[S[1]]]
            Sx, Sy = c * Sx0 - s * Sy0, s * Sx0 + c * Sy0
            vx, vy = f[i[C[0]]], f[i[C[1]]]
            omega_abs = self.omega * f[i[w]] + qd[k]
            out.append(vx * -Sy + vy * Sx + self.J[k] * omega_abs)
        return out


# ----------------------------------------------------------------------------------------------
# Integration over turns
# ----------------------------------------------------------------------------------------------


def integrate_turn(model, t0, y0, modes0, n_samples, rtol, atol):
    """One turn from t0: the states at the n_samples uniform samples of travel (the first at
    t0), the modes at them, the mode transitions (t, mesh, from, to, speed)."""
    om = model.omega
    T = TAU / om
    phi0 = om * t0
    # segment boundaries: the samples and the needle's knots (travel = φ mod 2π, deg)
    marks = [phi0 + TAU * k / n_samples for k in range(n_samples + 1)]
    knots = model.needle_knots_deg()
    turn0 = math.floor(phi0 / TAU)
    for kd in knots:
        for turn in (turn0, turn0 + 1):
            p = TAU * turn + math.radians(kd)
            if phi0 < p < phi0 + TAU:
                marks.append(p)
    marks = sorted(set(marks))
    # dedupe near-equal
    clean = [marks[0]]
    for p in marks[1:]:
        if p - clean[-1] > 1e-12:
            clean.append(p)
    marks = clean
    sample_phis = [phi0 + TAU * k / n_samples for k in range(n_samples)]
    states, modes_at = [], []
    trans = []
    y = list(y0)
    modes = list(modes0)
    si = 0
    for a, b in zip(marks[:-1], marks[1:]):
        while si < n_samples and abs(sample_phis[si] - a) < 1e-12:
            states.append(list(y))
            modes_at.append(list(modes))
            si += 1
        ta, tb = a / om, b / om
        # needle force on this segment, linear in φ (exactly the table between its knots)
        if knots:
            fa = model.needle_ccw(math.degrees(a) % 360.0)
            fb = model.needle_ccw(math.degrees(b) % 360.0)
            slope = (fb - fa) / (b - a)
        else:
            fa = slope = np.zeros(2)
        t = ta
        guard = 0
        while t < tb:
            guard += 1
            if guard > 10000:
                raise RuntimeError("more than 10000 contact changes in one segment")
            # The mode's events. For 1e-12 of a turn after a restart each takes the side of its
            # mode: a restart on a zero of δ − b must not find that zero again (the located root
            # is exact to a few ulps of t, and δ − b there is ±1e-21 m of either sign; found
            # again, contact would flip for ever at one instant).
            guard_s = 1e-12 * T if trans and trans[-1][0] == t else 0.0
            evs, meta = [], []
            for j in (0, 1):
                if modes[j] is None:
                    for f in (0, 1):
                        ev = (lambda tt, yy, j=j, f=f, t0=t + guard_s:
                              -1e-30 if tt <= t0 else model.gap(tt, yy, j, f))
                        ev.terminal, ev.direction = True, 1.0
                        evs.append(ev)
                        meta.append((j, f))
                else:
                    f = modes[j]
                    ev = (lambda tt, yy, j=j, f=f, t0=t + guard_s:
                          1e-30 if tt <= t0 else model.gap(tt, yy, j, f))
                    ev.terminal, ev.direction = True, -1.0
                    evs.append(ev)
                    meta.append((j, None))
            m_now = tuple(modes)
            sol = solve_ivp(
                lambda tt, yy: model.rhs(tt, yy, m_now, fa, slope, a),
                (t, tb), y, method="DOP853", rtol=rtol, atol=atol,
                events=evs,
            )
            if sol.status == -1:
                raise RuntimeError(f"solve_ivp failed at t = {t}: {sol.message}")
            if sol.status == 1:
                hit = [i for i, te in enumerate(sol.t_events) if len(te)]
                i = hit[0]
                te = float(sol.t_events[i][0])
                ye = list(sol.y_events[i][0])
                j, new = meta[i]
                old = modes[j]
                if new is None and model.b[j] == 0.0:
                    new = 1 - old  # no dead zone: the load passes to the other flank at once
                # approach speed on the flank struck / left
                _, _, _, _, qd2, qd3, _, _, lev = model.unpack(om * te, ye)
                fl = new if new is not None else old
                spd = model.approach(lev, j, fl, qd2, qd3)
                trans.append((te, j, old, new, spd))
                modes[j] = new
                y, t = ye, te
                # an event within a femtosecond of the segment's end: the state there is the
                # event's (solve_ivp cannot step such an interval, and would find it again)
                if tb - te <= 1e-12 * T:
                    break
            else:
                y, t = list(sol.y[:, -1]), tb
    states.append(list(y))  # the end of the turn
    modes_at.append(list(modes))
    if len(states) != n_samples + 1:
        raise RuntimeError(f"{len(states) - 1} states for {n_samples} samples")
    return states, modes_at, trans


def deviations(model, phi, y):
    """(q, q̇) at φ for the state y = (q, p)."""
    _, _, _, _, qd2, qd3, _, _, _ = model.unpack(phi, y)
    return np.array([y[0], y[1]]), np.array([qd2, qd3])


def settle(model, y0, modes0, n_samples, rtol, atol, tol, max_turns, log):
    T = TAU / model.omega
    y, modes = y0, modes0
    for turn in range(max_turns):
        t0 = turn * T
        states, modes_at, trans = integrate_turn(model, t0, y, modes, n_samples, rtol, atol)
        # residual over the turn's scale
        qv = [deviations(model, model.omega * t0 + TAU * k / n_samples, s)
              for k, s in enumerate(states[:-1])]
        qs, vs = np.array([x[0] for x in qv]), np.array([x[1] for x in qv])
        q0, v0 = qv[0]
        q1, v1 = deviations(model, model.omega * t0 + TAU, states[-1])
        r = max(float(np.max(np.abs(q1 - q0))) / max(float(np.max(np.abs(qs))), 1e-300),
                float(np.max(np.abs(v1 - v0))) / max(float(np.max(np.abs(vs))), 1e-300))
        log(f"turn {turn + 1}: residual {r:.2e}, {len(trans)} contact changes, "
            f"{model.evals} RHS evaluations so far")
        if r < tol or turn + 1 == max_turns:
            return t0, states[:-1], modes_at[:-1], trans, r, turn + 1
        y, modes = states[-1], modes_at[-1]


# ----------------------------------------------------------------------------------------------
# Comparison helpers
# ----------------------------------------------------------------------------------------------


def windowed_distance(points, poly, w):
    """Distance of points[k] to the closed polyline poly searched within ±w vertices of k."""
    n = len(poly)
    out = np.empty(len(points))
    for k, q in enumerate(points):
        idx = (k + np.arange(-w, w + 1)) % n
        p0 = poly[idx]
        d = poly[(idx + 1) % n] - p0
        L2 = np.maximum(np.sum(d * d, axis=1), 1e-300)
        tt = np.clip(np.sum((q - p0) * d, axis=1) / L2, 0.0, 1.0)
        out[k] = float(np.sqrt(np.min(np.sum((p0 + tt[:, None] * d - q) ** 2, axis=1))))
    return out


def merge_wrap(intervals):
    """Loss intervals [from, to] (deg): [a, 360] and [0, b] joined as one across 0 -> [a, b]."""
    iv = [list(map(float, x)) for x in intervals]
    ends = [x for x in iv if abs(x[1] - 360.0) < 1e-9]
    starts = [x for x in iv if abs(x[0]) < 1e-9]
    if ends and starts and ends[0] is not starts[0]:
        a, b = ends[0][0], starts[0][1]
        iv = [x for x in iv if x is not ends[0] and x is not starts[0]] + [[a, b]]
    return sorted(iv, key=lambda x: x[0])


def resolve(intervals, min_deg):
    """Loss intervals as resolved in travel: two separated by a contact shorter than min_deg
    joined, then those shorter than min_deg dropped. Where the flanks slide along the dead
    zone's edge both models chatter between contact and flight at intervals that depend on the
    integrator (see the module docs); what they resolve in common is the sliding stretch."""
    iv = sorted((list(x) for x in intervals), key=lambda x: x[0])
    out = []
    for a, b in iv:
        if out and (a - out[-1][1]) % 360.0 < min_deg:
            out[-1][1] = b
        else:
            out.append([a, b])
    if len(out) > 1 and (out[0][0] - out[-1][1]) % 360.0 < min_deg:
        out[0][0] = out.pop()[0]
    return [x for x in out if (x[1] - x[0]) % 360.0 >= min_deg]


def angle_gap(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


def match_intervals(ours, theirs, tol):
    """Worst end gap over the pairing of each interval of either side with the nearest of the
    other (both ends within tol of travel); the unmatched ones."""
    worst = 0.0
    bad = []
    for lab, xs, ys in (("ours", ours, theirs), ("theirs", theirs, ours)):
        starts = np.array([y[0] for y in ys]) if ys else np.zeros(0)
        order = np.argsort(starts)
        s_sorted = starts[order]
        for x in xs:
            cand = []
            if len(ys):
                # the intervals of the other side starting within tol (round the turn)
                for c in (x[0] - 360.0, x[0], x[0] + 360.0):
                    lo, hi = np.searchsorted(s_sorted, [c - tol, c + tol])
                    cand.extend(order[lo:hi].tolist())
                if not cand:  # none within tol: the nearest start, for the reported gap
                    k = int(np.argmin([angle_gap(x[0], st) for st in starts]))
                    cand = [k]
            d = min((max(angle_gap(x[0], ys[i][0]), angle_gap(x[1], ys[i][1])) for i in cand),
                    default=math.inf)
            worst = max(worst, d)
            if d > tol:
                bad.append(f"{lab} [{x[0]:.2f}, {x[1]:.2f}]")
    return worst, bad


# ----------------------------------------------------------------------------------------------
# Main
# ----------------------------------------------------------------------------------------------


def main(argv=None):
    ap = argparse.ArgumentParser(description="Independent check of `ncgear dynamics` (rotor).")
    ap.add_argument("design")
    ap.add_argument("scene")
    ap.add_argument("dynamics")
    ap.add_argument("loads")
    ap.add_argument("--case", default=None, help="name in the table (default: the scene's)")
    ap.add_argument("--tol-force", type=float, default=0.02)
    ap.add_argument("--tol-tip", type=float, default=0.02)
    ap.add_argument("--tip-floor-um", type=float, default=1.0)
    ap.add_argument("--tol-loss-deg", type=float, default=1.0)
    ap.add_argument("--tol-freq", type=float, default=1e-3)
    ap.add_argument("--resolve-deg", type=float, default=0.01,
                    help="contacts and flights shorter than this (travel °) not resolved")
    ap.add_argument("--rtol", type=float, default=1e-10)
    ap.add_argument("--poincare-tol", type=float, default=1e-6)
    ap.add_argument("--max-turns", type=int, default=12)
    ap.add_argument("--grid", type=int, default=16, help="kinematics grid: samples × this")
    ap.add_argument("--damping-speed", choices=("levers", "rate"), default="rate",
                    help="the mesh damping's speed: dδ/dt as documented (rate), or v_s = ρ·Δθ̇ "
                    "(levers: ncgear's model before 2026-12-02)")
    ap.add_argument("--dump", help="write our series to this .npz")
    args = ap.parse_args(argv)
    wall = time.time()

    def err(msg):
        print(f"check_rotor: ERROR {msg}", file=sys.stderr)
        return 2

    try:
        design = cl.Design(args.design)
        scene = cl.Scene(args.scene)
        raw = scene.raw
        eff = Effects(raw, design.raw)
        with open(args.dynamics) as fh:
            dyn = json.load(fh)
        with open(args.loads) as fh:
            loads = json.load(fh)
    except (cl.InputError, InputError, OSError, KeyError, ValueError, TypeError) as e:
        return err(e)
    case = args.case or (raw.get("scene") or {}).get("name") or os.path.basename(args.scene)
    try:
        travel = np.asarray(dyn["travel_deg"], dtype=float)
        nt = len(travel)
        if nt < 16 or np.max(np.abs(travel - 360.0 * np.arange(nt) / nt)) > 1e-9:
            raise InputError("dynamics.json travel_deg is not a uniform grid from 0")
        if dyn.get("model") != "rotor":
            raise InputError("dynamics.json is not a rotor report")
        ltravel = np.asarray(loads["travel_deg"], dtype=float)
        if len(ltravel) != nt:
            raise InputError("loads.json and dynamics.json have different samples")
        face = (scene.gears or {}).get("face_width_mm")
        if not isinstance(face, (int, float)):
            raise InputError("gears.face_width_mm must be a number (mm)")
        face = float(face)
        if eff.alpha_teeth is not None:
            alpha = float(eff.alpha_teeth)
        else:
            alpha = math.radians(float((scene.gears or {}).get("pressure_angle_deg", 20.0)))
        if scene.needle_other and loads.get("needle_table_N"):
            # the table the loads use, linear between its rows (finer than the samples)
            tab = np.asarray(loads["needle_table_N"], dtype=float)
            scene.use_reported_needle(tab[:, 0], tab[:, 1:])
        elif scene.needle_other:
            nf = loads.get("needle_force_N")
            if nf is None or len(nf) != nt:
                raise InputError("the needle is not a force table and loads.json states no "
                                 "needle_force_N")
            scene.use_reported_needle(ltravel, nf)
        model = Rotor(design, scene, eff, loads, face, alpha, nt * args.grid,
                      rate_damping=args.damping_speed == "rate")
    except (cl.InputError, InputError, KeyError, ValueError, TypeError) as e:
        return err(e)

    def log(msg):
        print(f"check_rotor: {case}: {msg}", flush=True)

    log(f"k = {model.k[0]:.4e}, {model.k[1]:.4e} N/m; c = {model.c[0]:.4e}, {model.c[1]:.4e} "
        f"N·s/m (m_e {model.m_e[0]:.4e}, {model.m_e[1]:.4e} kg); b = ±{model.b[0] * 1e6:.2f}, "
        f"±{model.b[1] * 1e6:.2f} µm; vibration c = {model.cv[0]:.4e}, {model.cv[1]:.4e}; "
        f"f = {model.freqs_hz[0]:.2f}, {model.freqs_hz[1]:.2f} Hz; J = {model.J[0]:.4e}, "
        f"{model.J[1]:.4e} kg·m²")

    # ---- quasi-static start at travel 0: loads.json's forces on its flanks --------------------
    lm = loads["meshes"]
    F0 = [float(lm[k]["normal_force_N"][0]) for k in ("sun_intermediate", "intermediate_planet")]
    fl0 = [int(lm[k]["flank"][0]) for k in ("sun_intermediate", "intermediate_planet")]
    lev = model.unpack(0.0, [0.0, 0.0, 0.0, 0.0])[-1]
    modes = [None if f == 0 else (0 if f > 0 else 1) for f in fl0]
    q2 = q3 = 0.0
    if modes[0] is not None:
        q2 = -(F0[0] / model.k[0] + model.b[0]) / lev[0][modes[0]]
    if modes[1] is not None:
        rd, rn = lev[1][modes[1]]
        q3 = (rd * q2 - (F0[1] / model.k[1] + model.b[1])) / rn
    p = model.momenta(0.0, [q2, q3], [0.0, 0.0])
    y0 = [q2, q3, p[0], p[1]]
    atol = [1e-14, 1e-14, 1e-14 * model.J[0] * model.omega * 1e3,
            1e-14 * model.J[1] * model.omega * 1e3]
    try:
        t0, states, modes_at, trans, res, turns = settle(
            model, y0, modes, nt, args.rtol, atol, args.poincare_tol, args.max_turns, log)
    except RuntimeError as e:
        print(f"check_rotor: FAIL {case}: {e}")
        return 1

    # ---- our series at the samples ------------------------------------------------------------
    om = model.omega
    F_ours = np.zeros((nt, 2))
    tip = np.zeros((nt, 2))
    q_ours = np.zeros((nt, 2))
    for k in range(nt):
        phi = om * t0 + TAU * k / nt
        F, pieces = model.forces(phi, states[k], modes_at[k])
        F_ours[k] = F
        b = pieces[6]
        q_ours[k] = states[k][:2]
        tip[k] = model.mo["A"][k * args.grid] + np.asarray(b) * 1e3
    static = model.static_tip_mm[:: args.grid]
    dev_ours = windowed_distance(tip, static, max(nt // 8, 2))
    travel_of = lambda t: math.degrees(om * (t - t0)) % 360.0  # noqa: E731
    losses_ours = []
    for j in (0, 1):
        open_at = 0.0 if modes_at[0][j] is None else None
        iv = []
        for (t, jj, old, new, spd) in trans:
            if jj != j:
                continue
            if new is None:
                open_at = travel_of(t)
            elif open_at is not None:
                iv.append([open_at, travel_of(t)])
                open_at = None
        if open_at is not None:
            iv.append([open_at, 360.0])
        losses_ours.append(merge_wrap(iv))
    if args.dump:
        tr = np.array([[math.degrees(om * (t - t0)) % 360.0, j, -9 if a is None else a,
                        -9 if b_ is None else b_, v] for (t, j, a, b_, v) in trans])
        np.savez(args.dump, F=F_ours, tip=tip, dev=dev_ours, q=q_ours, transitions=tr)

    # ---- compare --------------------------------------------------------------------------------
    rows, failures, notes = [], [], []

    def row(quantity, diff, peak, ratio, limit, unit=""):
        ok = ratio <= limit
        rows.append((quantity, diff, peak, ratio, limit, ok, unit))
        if not ok:
            failures.append(f"{quantity}: {ratio:.4g} > {limit:.4g}")

    names = ("sun_intermediate", "intermediate_planet")
    try:
        for j, nm in enumerate(names):
            th = np.asarray(dyn["meshes"][nm]["dynamic_force_n"], dtype=float)
            if th.shape != (nt,):
                raise InputError(f"meshes.{nm}.dynamic_force_n: {th.shape}, expected ({nt},)")
            peak = float(np.max(np.abs(th)))
            d = np.abs(F_ours[:, j] - th)
            kk = int(np.argmax(d))
            row(f"{nm} dynamic force N (worst at {travel[kk]:.1f}°)", float(d[kk]), peak,
                float(d[kk]) / max(peak, 1e-300), args.tol_force)
        tdev = np.asarray(dyn["tip_deviation_mm"], dtype=float)
        peak = float(np.max(tdev))
        d = np.abs(dev_ours - tdev)
        kk = int(np.argmax(d))
        floor_mm = args.tip_floor_um * 1e-3
        if peak < 50 * floor_mm:
            row(f"tip deviation mm, abs (peak < {50 * args.tip_floor_um:g} µm)", float(d[kk]),
                peak, float(d[kk]) / floor_mm, 1.0)
        else:
            row(f"tip deviation mm (worst at {travel[kk]:.1f}°)", float(d[kk]), peak,
                float(d[kk]) / peak, args.tol_tip)
        sm = dyn["summary"]["meshes"]
        for j, nm in enumerate(names):
            raw_t = merge_wrap(sm[nm]["contact_loss_deg"])
            theirs = resolve(raw_t, args.resolve_deg)
            ours = resolve(losses_ours[j], args.resolve_deg)
            worst, bad = match_intervals(ours, theirs, args.tol_loss_deg)
            n_o, n_t = len(ours), len(theirs)
            if (len(raw_t), len(losses_ours[j])) != (n_t, n_o):
                notes.append(f"{nm}: {len(losses_ours[j])} ours, {len(raw_t)} theirs raw "
                             f"contact-loss intervals; {n_o}, {n_t} resolved to "
                             f"{args.resolve_deg:g}°")
            if n_o == 0 and n_t == 0:
                rows.append((f"{nm} contact loss: none in either", 0.0, 0.0, 0.0,
                             args.tol_loss_deg, True, "°"))
                continue
            ok = not bad
            rows.append((f"{nm} contact-loss intervals ({n_o} ours, {n_t} theirs) °", worst,
                         float(sum((b - a) % 360.0 for a, b in theirs)), worst,
                         args.tol_loss_deg, ok, "°"))
            if not ok:
                failures.append(f"{nm} contact loss unmatched: {', '.join(bad[:8])}"
                                + (" …" if len(bad) > 8 else ""))
        fr = dyn["summary"].get("natural_frequencies_hz")
        if fr:
            e = max(abs(a - b) / b for a, b in zip(sorted(model.freqs_hz), sorted(fr)))
            row("natural frequencies Hz, rel", e * max(fr), max(fr), e, args.tol_freq)
    except (InputError, KeyError, TypeError, ValueError) as e:
        return err(f"{args.dynamics}: {e}")

    steady = dyn.get("steady") or {}
    print(f"check_rotor: {case}: ours {turns} turns (residual {res:.1e}), theirs "
          f"{steady.get('turns')} turns (residual {steady.get('residual', float('nan')):.1e}); "
          f"{model.evals} RHS evaluations, {len(trans)} contact changes in our last turn, "
          f"{time.time() - wall:.1f} s")
    w = max(len(r[0]) for r in rows)
    print(f"  {'':4} {'case':<14} {'quantity':<{w}} {'largest diff':>13} {'peak':>11} "
          f"{'ratio':>10} {'limit':>8}")
    for q, diff, peak, ratio, limit, ok, unit in rows:
        print(f"  {'ok  ' if ok else 'FAIL'} {case:<14} {q:<{w}} {diff:13.4e} {peak:11.4e} "
              f"{ratio:10.3e} {limit:8.3g}")
    key = []
    for q, diff, peak, ratio, limit, ok, unit in rows:
        if "dynamic force" in q:
            key.append(f"{q.split()[0]} force {ratio:.1e}")
        elif q.startswith("tip"):
            key.append(f"tip {diff * 1e3:.2g} µm of {peak * 1e3:.3g} µm")
        elif "contact-loss" in q:
            key.append(f"{q.split()[0]} loss {diff:.2g}°")
    print("check_rotor: key: " + ", ".join(key))
    for n_ in notes:
        print(f"  note: {n_}")
    if res >= args.poincare_tol:
        print(f"  note: our model did not settle in {turns} turns (residual {res:.2e})")
    if not steady.get("settled", True):
        print("  note: ncgear's run did not settle")
    if failures:
        print(f"check_rotor: {case}: FAILED")
        for f in failures:
            print(f"  - {f}")
        return 1
    print(f"check_rotor: {case}: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
