"""Writes assets/orbit/signals.csv: a synthetic housing-frame record of the model in model.toml.

python3 assets/orbit/make_signals.py   (numpy; seed fixed)
Sun orbit from (A-9), plus sun runout 4 µm at the sun-relative speed, a 1.5 µm mesh line,
sensor offsets (25, -10) µm, drift (1.5, -0.8) µm/s and white noise 1 µm; 1 kHz for 4 s.
"""
import numpy as np

a, h = np.radians(20.0), 1.0
e = np.array([10.0, 6.0, 8.0]); th = np.array([0.0, 0.7, 2.1]); phi = np.radians([0.0, 120.0, 240.0])
E = e * np.exp(1j * th); beta = phi + h * (np.pi / 2 - a)
zp = 2 * h * np.cos(a) / 3j * np.sum(E * np.exp(1j * beta))
zm = -2 * h * np.cos(a) / 3j * np.sum(np.conj(E) * np.exp(1j * beta))
zs, zpl, zr, ws = 20, 25, 70, 300 * 2 * np.pi / 60
wc = ws * zs / (zs + zr); wp = -wc * zr / zpl; wsr = ws - wc; wm = zr * abs(wc)
t = np.arange(4000) / 1000.0
zc = zp * np.exp(1j * wp * t) + zm * np.exp(-1j * wp * t) + 4.0 * np.exp(1j * (wsr * t + 0.3)) \
    + 1.5 * np.exp(1j * wm * t)
z = np.exp(1j * wc * t) * zc
rng = np.random.default_rng(6)
x = z.real + 25 + 1.5 * t + rng.normal(0, 1, t.size)
y = z.imag - 10 - 0.8 * t + rng.normal(0, 1, t.size)
with open("assets/orbit/signals.csv", "w") as f:
    f.write("# synthetic housing-frame record of assets/orbit/model.toml (make_signals.py)\n")
    f.write("t_s,x_um,y_um,carrier_deg\n")
    for k in range(t.size):
        f.write(f"{t[k]:.4f},{x[k]:.5f},{y[k]:.5f},{np.degrees(wc * t[k]):.6f}\n")
print("Z+ =", zp, "Z- =", zm, "omega_p =", wp)
