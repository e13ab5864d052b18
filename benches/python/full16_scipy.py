"""The 16-DOF full scene (assets/dynamics/full16.toml) re-implemented in numpy and integrated
with scipy.integrate.solve_ivp(RK45) at rtol 1e-6 / atol 1e-12 from rest over 50 mesh periods,
with and without splitting at the known switch times. Compare with
`cargo run --release --example dynamics_speed` (same model, same tolerances).

Run: python3 benches/python/full16_scipy.py   (pip install numpy scipy)
"""
import math, time
import numpy as np
from scipy.integrate import solve_ivp

z1, z2, mod, alpha, b_face, rho = 25, 40, 3e-3, math.radians(20.0), 0.02, 7850.0
r1, r2 = mod * z1 / 2, mod * z2 / 2
rb1, rb2 = r1 * math.cos(alpha), r2 * math.cos(alpha)
ra1, ra2 = r1 + mod, r2 + mod
pb = 2 * math.pi * rb1 / z1
n1n2 = (rb1 + rb2) * math.tan(alpha)
n1a = n1n2 - math.sqrt(ra2**2 - rb2**2)
n1p = rb1 * math.tan(alpha)
n1e = math.sqrt(ra1**2 - rb1**2)
eps = (n1e - n1a) / pb
m1, m2 = math.pi * r1**2 * b_face * rho, math.pi * r2**2 * b_face * rho
J1, J2 = 0.5 * m1 * r1**2, 0.5 * m2 * r2**2
me = J1 * J2 / (J1 * rb2**2 + J2 * rb1**2)
kmax, kmin = 4.5e8, 2.5e8
kmean = kmax * (eps - 1) + kmin * (2 - eps)
cm = 2 * 0.05 * math.sqrt(kmean * me)
we = 2 * math.pi * 6000 * z1 / 60
t0 = 2 * math.pi / we
w1, w2 = we / z1, we / z2
er, bl, dmax, L, mu = 10e-6, 50e-6, 10e-6, 2e-3, 0.05
Mp = 50.0
Mq = Mp * rb2 / rb1
# DOFs: 0 θp,1 x1,2 y1,3 θ1,4 x2,5 y2,6 θ2,7 xb1,8 yb1,9 xb2,10 yb2,11 xb3,12 yb3,13 xb4,14 yb4,15 θq
M = np.array([0.01, m1, m1, J1, m2, m2, J2] + [0.5] * 8 + [0.05])
coef = {2: 1.0, 5: -1.0, 3: rb1, 6: -rb2}
ext = np.zeros(16)
ext[0] += Mp
ext[15] -= Mq
for i in [2, 5, 8, 10, 12, 14]:
    ext[i] += M[i] * -9.81
# linear springs: (coeff dict, k, c)
springs = [({0: 1.0, 3: -1.0}, 3e4, 5.0), ({6: 1.0, 15: -1.0}, 3e4, 5.0)]
for g, bs in [((1, 2), (7, 8, 9, 10)), ((4, 5), (11, 12, 13, 14))]:
    springs.append(({g[0]: 1.0, bs[0]: -0.5, bs[2]: -0.5}, 5e7, 200.0))
    springs.append(({g[1]: 1.0, bs[1]: -0.5, bs[3]: -0.5}, 5e7, 200.0))
for i in range(7, 15):
    springs.append(({i: 1.0}, 2e8, 2000.0))
Ks = np.zeros((16, 16))
Cs = np.zeros((16, 16))
for c, k, d in springs:
    for i, a in c.items():
        for j, b in c.items():
            Ks[i, j] += k * a * b
            Cs[i, j] += d * a * b
cvec = np.zeros(16)
for i, c in coef.items():
    cvec[i] = c


def kpair(s):
    if s < 0 or s >= eps:
        return 0.0
    if s < eps - 1 or s >= 1:
        return kmax / 2
    return kmin


def rhs(t, y):
    q, v = y[:16], y[16:]
    f = ext - Ks @ q - Cs @ v
    g, gd = cvec @ q, cvec @ v
    e, ed = er * math.sin(we * t), er * we * math.cos(we * t)
    s1 = (t / t0) % 1.0
    ktot = kmax if s1 < eps - 1 else kmin
    vel = pb / t0
    fm = 0.0
    for j in (0, 1):
        s = s1 + j
        share = kpair(s) / ktot
        k, c = ktot * share, cm * share
        sl = s * pb
        if sl < L:
            rel, reld = dmax * (L - sl) / L, -dmax * vel / L
        elif sl > eps * pb - L:
            rel, reld = dmax * (sl - (eps * pb - L)) / L, dmax * vel / L
        else:
            rel, reld = 0.0, 0.0
        d = g - e - rel
        dd = gd - ed - reld
        fd = d - bl if d > bl else (d + bl if d < -bl else 0.0)
        F = k * fd + c * dd
        fm += F
        if k > 0:
            lp = n1a + sl
            lg = n1n2 - lp
            lam = 1.0 if sl < n1p - n1a else -1.0
            ff = mu * lam * max(F, 0.0)
            f[1] += ff
            f[4] -= ff
            f[3] += ff * lp
            f[6] -= ff * lg
    f -= fm * cvec
    a = w1 * t
    amp = m1 * 20e-6 * w1 * w1
    f[1] += amp * math.cos(a)
    f[2] += amp * math.sin(a)
    return np.concatenate([v, f / M])


def breakpoints(T):
    tp = (n1p - n1a) / pb
    offs = [0.0, eps - 1, L / pb, (eps * pb - L) / pb - 1, tp, tp - 1]
    out = sorted({(j + o) * t0 for j in range(-1, int(T / t0) + 2) for o in offs if 0 < (j + o) * t0 < T})
    return out


T = 50 * t0
for split in (False, True):
    best, nfev, dte = 1e9, 0, 0.0
    for _ in range(3):
        y = np.zeros(32)
        knots = [0.0] + (breakpoints(T) if split else []) + [T]
        nfev = 0
        t_start = time.perf_counter()
        for a, b in zip(knots[:-1], knots[1:]):
            sol = solve_ivp(rhs, (a, b), y, method="RK45", rtol=1e-6, atol=1e-12)
            y = sol.y[:, -1]
            nfev += sol.nfev
        best = min(best, time.perf_counter() - t_start)
        dte = cvec @ y[:16] - er * math.sin(we * T)
    print(f"scipy RK45 breakpoints={split}: {nfev} RHS evals, best of 3: {best*1e3:.1f} ms, final DTE {dte*1e6:.6f} µm")
