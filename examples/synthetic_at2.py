#!/usr/bin/env python3
"""Writes examples/arch_earthquake_record.AT2: a SYNTHETIC strong-motion record in the PEER
NGA .AT2 layout (not a recorded earthquake: real PEER records are not redistributable here).

Stationary white noise (seeded) filtered by a Kanai-Tajimi soil filter (f_g = 2.5 Hz,
zeta_g = 0.6), shaped by a Saragoni-Hart envelope (peak at 2 s), baseline-corrected
(linear trend of the velocity removed), scaled to a PGA of 0.25 g; 8 s at DT = 0.005 s.
Run with no arguments from the repository root; standard library only.
"""
import math
import random

DT, N, PGA, SEED = 0.005, 1601, 0.25, 7
FG, ZG = 2.5, 0.6

rng = random.Random(SEED)
noise = [rng.gauss(0.0, 1.0) for _ in range(N)]
# Kanai-Tajimi: the absolute acceleration of a damped oscillator (f_g, zeta_g) driven by the
# noise, integrated with the average-acceleration Newmark scheme on a fine sub-step
wg = 2 * math.pi * FG
x = v = 0.0
out = []
sub = 10
h = DT / sub
for i in range(N):
    for _ in range(sub):
        a_in = noise[i]
        # x'' + 2 zg wg x' + wg^2 x = -a_in ; absolute acceleration = -(2 zg wg x' + wg^2 x)
        acc = -a_in - 2 * ZG * wg * v - wg * wg * x
        v_half = v + 0.5 * h * acc
        x += h * v_half
        acc2 = -a_in - 2 * ZG * wg * v_half - wg * wg * x
        v = v_half + 0.5 * h * acc2
    out.append(-(2 * ZG * wg * v + wg * wg * x))


def envelope(t, tp=2.0):
    # Saragoni-Hart: (t/tp)^b exp(b (1 - t/tp)) with b = 2
    b = 2.0
    return (t / tp) ** b * math.exp(b * (1 - t / tp))


a = [out[i] * envelope(i * DT) for i in range(N)]
# baseline: remove the linear trend of the velocity (a constant acceleration offset) so that
# the base ends near rest, then taper the last 0.5 s
vel = [0.0]
for i in range(1, N):
    vel.append(vel[-1] + 0.5 * DT * (a[i - 1] + a[i]))
slope = vel[-1] / ((N - 1) * DT)
a = [ai - slope for ai in a]
taper = int(0.5 / DT)
for k in range(taper):
    a[N - 1 - k] *= k / taper
for k in range(int(0.1 / DT)):
    a[k] *= k / (0.1 / DT)
peak = max(abs(ai) for ai in a)
a = [ai * PGA / peak for ai in a]  # in g

lines = [
    "PEER NGA STRONG MOTION DATABASE RECORD (SYNTHETIC: nmm examples/synthetic_at2.py, not a recorded motion)",
    f"Synthetic, Kanai-Tajimi fg={FG} Hz zg={ZG}, Saragoni-Hart envelope, seed {SEED}, PGA {PGA} g",
    "ACCELERATION TIME SERIES IN UNITS OF G",
    f"NPTS=  {N}, DT=   {DT:.4f} SEC",
]
for i in range(0, N, 5):
    lines.append("".join(f"{v:15.7E}" for v in a[i:i + 5]))
with open("examples/arch_earthquake_record.AT2", "w") as f:
    f.write("\n".join(lines) + "\n")
print(f"wrote {N} samples, PGA {PGA} g")
