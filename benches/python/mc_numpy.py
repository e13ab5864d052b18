"""Vectorised numpy version of the Monte Carlo loop of `cargo bench --bench tolerance`:
50 000 random assemblies of the paper's four terms, peak of |e(t)| over the common period 2π s
on the same grid (20 points per shortest period, 10 500 points) from precomputed sin/cos tables,
in blocks of 1000 samples (one matrix product per block), with parabolic refinement of the grid
maximum (numpy cannot refine every sample with a root finder cheaply).
Run: python3 benches/python/mc_numpy.py [SAMPLES]  (50 000 by default; a multiple of 1000)"""
import sys
import time
import numpy as np

A = np.array([-0.699, -13.0, -8.778, -25.887])
W = np.array([75.0, 525.0, 275.0, 63.0])
C = np.radians([0.0, 20.0, 90.0, 20.0])
S = np.array([0.0, 1.0, -1.0, -1.0])
FREE = np.array([False, True, True, True])
N_SAMPLES, BLOCK = (int(sys.argv[1]) if len(sys.argv) > 1 else 50_000), 1000
n = int(np.ceil(2 * np.pi / (2 * np.pi / W.max()) * 20))
t = np.arange(n) * (2 * np.pi / n)
sin_t, cos_t = np.sin(np.outer(W, t)), np.cos(np.outer(W, t))


def run(seed):
    rng = np.random.default_rng(seed)
    out = np.empty(N_SAMPLES)
    for b in range(0, N_SAMPLES, BLOCK):
        beta = rng.uniform(0, 2 * np.pi, size=(BLOCK, 4))
        phi = np.where(FREE, S * beta + C, C)
        f = (A * np.cos(phi)) @ sin_t + (A * np.sin(phi)) @ cos_t
        g = np.abs(f)
        j = g.argmax(axis=1)
        y0, y1, y2 = g[np.arange(BLOCK), j - 1], g[np.arange(BLOCK), j], g[np.arange(BLOCK), (j + 1) % n]
        den = y0 - 2 * y1 + y2
        out[b:b + BLOCK] = y1 - 0.125 * (y2 - y0) ** 2 / np.where(den == 0, -1e-300, den)
    return out


start = time.perf_counter()
v = run(1)
elapsed = time.perf_counter() - start
rb = 50 * np.cos(np.radians(20))
print(f"numpy: {N_SAMPLES} samples x {n} grid points in {elapsed:.3f} s; mean {v.mean() * 1e-3 / rb * 206264.806:.2f} arcsec")
