#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Write the cable robot on four winches (runs/multibody/cable_robot_winches.toml and the winches'
CSV tables beside it): a 20 kg platform hangs from four steel wire ropes (ANCF cables), each from
the platform's corner up and over an outlet sheave at the top of a corner post (a fixed contact
cylinder across the post's diagonal plane), down the post through its winch (a [[guide]] with a [[slider_drive]]) and on into the rope store below it,
where the rope's tail hangs free. The winches reel their ropes in and out so that the platform's
centre follows a path: up from where it hangs, once round a horizontal circle, and back.

Each winch's travel is the change of its rope's length from the winch to the platform's corner,
taken along the shortest way from the winch up, over the sheave and straight to the corner
(seen along the sheave's axis, tangent, arc and tangent; the corner's offset along the axis as
the platform moves round the circle, the fleet angle, spread evenly along it, as the rope and
the cylinder unroll into a plane): the rigid-rope inverse kinematics. (A sphere would let the
rope leave the outlet in any direction, but a rope over a frictionless sphere is not stable: it
slides off sideways.) The ropes' stretch and sag, and the platform's tilt, are what
the run adds to it (docs/verification.md, "Guides").

    scripts/make_cable_robot.py                      # writes the scene and its tables
    scripts/make_cable_robot.py --out /tmp/robot.toml --t-end 2
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
POST = 3.0          # m: the posts stand at (+-POST, +-POST)
OUTLET_Z = 4.0      # m: the sheaves' centres
SHEAVE = 0.15       # m: the sheave's radius where the rope's centre line touches
WINCH_DROP = 1.5    # m: the winch below the sheave's centre
TAIL = 0.8          # m: rope in the store below the winch at the start
CORNER = 0.3        # m: the platform's attachment points at (+-CORNER, +-CORNER, LIFT) from its centre
LIFT = 0.05
START = np.array([0.0, 0.0, 1.5])   # the platform's centre as drawn
EA, EI, RHO_A = 1.2e6, 0.1, 0.08    # a 4 mm steel wire rope
MASS = 20.0
TENSION = 95.0      # N: about the ropes' pull where they hang the platform (their drawn stretch)
ELEMENT = 0.05      # m: the ropes' element length (the wrap round a sheave takes 6-7 of them)
CORNERS = {"ne": (1, 1), "nw": (-1, 1), "sw": (-1, -1), "se": (1, -1)}


def path(t: np.ndarray) -> np.ndarray:
    """The platform centre's path: rest until 0.5 s, up and out to the circle by 2.5 s, once round
    a horizontal circle of 0.4 m about (0, 0, 1.8) in 6 s, back to the start by 10.5 s, then at rest."""
    centre, radius = np.array([0.0, 0.0, 1.8]), 0.4
    on_circle = lambda a: centre + radius * np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], axis=-1)  # noqa: E731
    blend = lambda u: np.clip(u, 0, 1) ** 3 * (10 - 15 * np.clip(u, 0, 1) + 6 * np.clip(u, 0, 1) ** 2)  # noqa: E731
    t = np.asarray(t, dtype=float)
    p = np.tile(START, (t.size, 1))
    up = (t > 0.5) & (t <= 2.5)
    p[up] = START + blend((t[up] - 0.5) / 2.0)[:, None] * (on_circle(np.zeros(up.sum())) - START)
    # round the circle with a speed that rises and falls smoothly (its angle a blend of time)
    rnd = (t > 2.5) & (t <= 8.5)
    p[rnd] = on_circle(2 * math.pi * blend((t[rnd] - 2.5) / 6.0))
    back = (t > 8.5) & (t <= 10.5)
    p[back] = on_circle(np.zeros(back.sum())) + blend((t[back] - 8.5) / 2.0)[:, None] * (
        START - on_circle(np.zeros(back.sum())))
    return p


def sheave_centre(sx: int, sy: int) -> np.ndarray:
    return np.array([POST * sx, POST * sy, OUTLET_Z])


def winch_point(sx: int, sy: int) -> np.ndarray:
    """Below the sheave's outer side: the rope comes down the post's outside, vertically."""
    out = np.array([sx, sy, 0.0]) / math.sqrt(2.0)
    return sheave_centre(sx, sy) + SHEAVE * out - np.array([0.0, 0.0, WINCH_DROP])


def sheave_axis(sx: int, sy: int) -> np.ndarray:
    """Horizontal, across the post's diagonal plane (the plane of the rope as drawn)."""
    return np.array([-sy, sx, 0.0]) / math.sqrt(2.0)


def wrap(g: np.ndarray, c: np.ndarray, centre: np.ndarray, axis: np.ndarray) -> tuple[float, list[np.ndarray]]:
    """The shortest rope from g over the cylinder (centre, axis, SHEAVE) to c, threaded over it
    (round the cylinder's far side from the straight line g c): its length and the points where
    it touches the cylinder, every 10 degrees or less. Seen along the axis it is tangent, arc and
    tangent; the offset along the axis is spread evenly over it (the development of the tangent
    planes and the cylinder is one plane)."""
    along = lambda v: axis * (axis @ v)  # noqa: E731
    a, b = g - centre - along(g - centre), c - centre - along(c - centre)
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    ah = a / na
    w = b - ah * (ah @ b)
    wh = -w / np.linalg.norm(w)  # across the axis, away from c's side: round the far side
    phi = math.atan2(b @ wh, b @ ah) % (2 * math.pi)
    t0, t1 = math.acos(SHEAVE / na), phi - math.acos(SHEAVE / nb)
    if t1 <= t0:
        raise ValueError("the rope does not touch the sheave")
    ta, tb = math.sqrt(na * na - SHEAVE * SHEAVE), math.sqrt(nb * nb - SHEAVE * SHEAVE)
    across = ta + SHEAVE * (t1 - t0) + tb
    offset_g, offset_c = axis @ (g - centre), axis @ (c - centre)
    n = max(2, math.ceil(math.degrees(t1 - t0) / 10.0))
    arc = []
    for t in np.linspace(t0, t1, n + 1):
        share = (ta + SHEAVE * (t - t0)) / across
        arc.append(centre + SHEAVE * (math.cos(t) * ah + math.sin(t) * wh) + axis * (offset_g + share * (offset_c - offset_g)))
    return math.hypot(across, offset_c - offset_g), arc


def rope_length(sx: int, sy: int, p: np.ndarray) -> float:
    corner = p + np.array([CORNER * sx, CORNER * sy, LIFT])
    return wrap(winch_point(sx, sy), corner, sheave_centre(sx, sy), sheave_axis(sx, sy))[0]


def fmt(v) -> str:
    return "[" + ", ".join(f"{x:.9f}" for x in v) + "]"


def scene(t_end: float, dt: float, tables: dict[str, str]) -> str:
    lines = [
        "# A cable robot on four winches (written by scripts/make_cable_robot.py: geometry, paths and the",
        "# winches' tables come from there). A 20 kg platform (a rigid body) hangs from four 4 mm steel",
        "# wire ropes (ANCF cables). Each rope runs from the platform's corner up and over an outlet",
        "# sheave on a corner post (a fixed frictionless contact cylinder across the post's diagonal",
        "# plane), straight down the post through its winch (a",
        "# [[guide]] driven by a [[slider_drive]]) and on into the store below, where its tail hangs",
        "# free: the rope is all there, nothing is cut or rescaled. The equilibrium start hangs the",
        "# platform with the winches held; then the winches reel rope in and out by their tables (the",
        "# rigid ropes' inverse kinematics) so that the platform's centre rises 0.3 m, goes once round",
        "# a horizontal circle of 0.4 m and comes back. The energy balance closes with the winches' work.",
        "#",
        "#   scripts/slidebeam run runs/multibody/cable_robot_winches.toml",
        "#   scripts/slidebeam plot out/cable_robot_winches --what paths,reactions",
        "#   scripts/slidebeam render out/cable_robot_winches --animation out/cable_robot_winches/robot.gif",
        "",
        "[scene]",
        'name = "cable_robot_winches"',
        'description = "a platform on four ropes over outlet sheaves, moved round a circle by four winches"',
        "",
        "[analysis]",
        'type = "dynamic"',
        'integrator = "energy-momentum"',
        'start = "equilibrium"',
        f"t_end = {t_end}",
        f"dt = {dt}",
        "# the energy-decaying variant: the ropes' axial waves, which the contact with the sheaves and",
        "# the winches excite and energy-momentum keeps, fade (its dissipation is in the balance);",
        "# the conserving scheme takes 1.4x the Newton iterations and 4x the Jacobians here",
        "em_dissipation = 0.1",
        "",
        "[[body]]",
        'name = "platform"',
        f"mass = {MASS}",
        "inertia = [0.617, 0.617, 1.2]  # kg m^2: a 0.6 x 0.6 x 0.1 m plate",
        f"position = {fmt(START)}",
    ]
    for name, (sx, sy) in CORNERS.items():
        centre, g = sheave_centre(sx, sy), winch_point(sx, sy)
        corner = START + np.array([CORNER * sx, CORNER * sy, LIFT])
        _, arc = wrap(g, corner, centre, sheave_axis(sx, sy))
        tail = g - np.array([0.0, 0.0, TAIL])
        points = [tail, g] + arc + [corner]
        drawn = sum(np.linalg.norm(q - p) for p, q in zip(points, points[1:]))
        spans = math.ceil(drawn / ELEMENT)
        unstretched = drawn - TENSION * (drawn - TAIL - WINCH_DROP / 2) / EA  # the tail hardly pulls
        lines += [
            "",
            "[[beam]]",
            f'name = "rope_{name}"',
            'formulation = "ancf"',
            "polyline = [",
            ",\n".join(f"  {fmt(p)}" for p in points),
            "]",
            f"unstretched_length = {unstretched:.9f}",
            f"spans = {spans}",
            f"section = {{ EA = {EA:.1e}, EI = {EI}, rhoA = {RHO_A} }}   # a 4 mm steel wire rope",
            "",
            "[[joint]]",
            'type = "spherical"',
            f'beams = ["rope_{name}", "platform"]',
            f'at = ["end", {fmt(corner)}]',
            "",
            "[[contact]]",
            'type = "cylinder"',
            f'beam = "rope_{name}"',
            f"point = {fmt(centre)}",
            f"axis = {fmt(sheave_axis(sx, sy))}",
            f"radius = {SHEAVE}              # the sheave's groove and the rope's 2 mm",
            "stiffness = 1.0e6",
            "",
            "[[guide]]",
            f'name = "winch_{name}"',
            f'rope = "rope_{name}"',
            f"point = {fmt(g)}",
            'static = "held"              # the winch holds its rope while the platform settles',
            "",
            "[[slider_drive]]",
            f'guide = "winch_{name}"',
            "distance = 1.0                # s = s0 + f(t): the table is the travel (m), negative pays rope out",
            f'time_function = {{ type = "spline", file = "{tables[name]}" }}',
        ]
    lines += [
        "",
        "[gravity]",
        "g = [0.0, 0.0, -9.81]",
        "",
        "[output]",
        "every = 20",
        "samples_per_span = 2           # the ropes' 576 elements: 8 samples each would write 2.7 MB a record",
        'track = [{ body = "platform" }]',
        "",
        "[petsc]",
        "# modified Newton: the step Jacobian and its LU kept across iterations and steps, several times",
        '# faster on ropes than full Newton (docs/performance.md, "Cables")',
        "sb_jacobian_reuse = true",
        "",
    ]
    return "\n".join(lines)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=ROOT / "runs" / "multibody" / "cable_robot_winches.toml")
    p.add_argument("--t-end", type=float, default=12.0)
    p.add_argument("--dt", type=float, default=0.005)
    args = p.parse_args()
    t = np.arange(0.0, 12.0 + 1e-9, 0.05)
    centres = path(t)
    tables = {}
    folder = args.out.parent / args.out.stem
    folder.mkdir(parents=True, exist_ok=True)
    for name, (sx, sy) in CORNERS.items():
        lengths = np.array([rope_length(sx, sy, c) for c in centres])
        # s is the rope's arc length at the winch from its tail: reeling in (a shorter rope up to
        # the platform) makes it grow
        travel = lengths[0] - lengths
        csv = folder / f"winch_{name}.csv"
        csv.write_text(f"# winch {name}: travel of s (m) against time (s), scripts/make_cable_robot.py\n"
                       + "".join(f"{a:.2f},{b:.9f}\n" for a, b in zip(t, travel)))
        tables[name] = f"{folder.name}/{csv.name}"
    args.out.write_text(scene(args.t_end, args.dt, tables))
    print(f"wrote {args.out} and {folder}/winch_*.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main())
