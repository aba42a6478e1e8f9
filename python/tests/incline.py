"""The block on an incline of the verification set (crates/nmm/src/verify/cases.rs,
`incline`), as TOML text: a 0.5 m × 0.25 m block on a fixed base, both dipping θ, dynamic
under gravity; monitor `c` at the block's centre.

The block slides down the plane by ½ g (sin θ − cos θ tan φ) t² (0 when φ ≥ θ)."""

import math

G = 9.81


def place(points, angle_deg, offset):
    s, c = math.sin(math.radians(angle_deg)), math.cos(math.radians(angle_deg))
    return [[offset[0] + c * x - s * y, offset[1] + s * x + c * y] for x, y in points]


def fmt(p):
    return f"[{p[0]:.17e}, {p[1]:.17e}]"


def incline_toml(theta=30.0, phi=20.0, dt=1e-3, steps=1000):
    rot = lambda pts: place(pts, -theta, [0.0, 2.5])  # noqa: E731
    base = rot([[0.0, -0.5], [4.0, -0.5], [4.0, 0.0], [0.0, 0.0]])
    slider = rot([[0.5, 0.0], [1.0, 0.0], [1.0, 0.25], [0.5, 0.25]])
    c = rot([[0.75, 0.125]])[0]
    poly = lambda pts: "[" + ", ".join(fmt(p) for p in pts) + "]"  # noqa: E731
    return f"""# A block on a plane dipping {theta} degrees (tests/contact_friction.rs, incline)
[analysis]
mode = "dynamic"
dt = {dt}
steps = {steps}
gravity = [0.0, -9.81]

[cover]
size = 0.0625

[[material]]
name = "rock"
density = 2000.0
young = 1.0e9
poisson = 0.25

[[block]]
name = "base"
material = "rock"
vertices = {poly(base)}
fixed = true

[[block]]
name = "slider"
material = "rock"
vertices = {poly(slider)}

[[interface]]
friction_angle = {phi}
normal_penalty = 1.0e9
shear_penalty = 1.0e9

[[monitor]]
name = "c"
point = {fmt(c)}
"""


def slip(ux, uy, theta=30.0):
    """Displacement down the plane from the monitor's ux, uy."""
    s, c = math.sin(math.radians(theta)), math.cos(math.radians(theta))
    return ux * c - uy * s


def closed_form(t, theta=30.0, phi=20.0):
    s, c = math.sin(math.radians(theta)), math.cos(math.radians(theta))
    return max(0.5 * G * (s - c * math.tan(math.radians(phi))) * t * t, 0.0)
