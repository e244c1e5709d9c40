#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""An Atwood machine with a massive rope over a row of point guides, against its closed form.

Masses m1 = 1.2 kg and m2 = 1.0 kg hang from the ends of a rope (0.5 kg/m, EA = 1e6 N) whose top
turns over N fixed [[guide]]s: two 0.1 m apart at the same height (90 degrees each), or N on a
half circle of radius 0.1 m (180 / (N - 1) degrees between them, half that at the first and last).
The first guide holds the rope in the equilibrium start (static = "held"), the others let it run;
then it runs free. With a the length of the heavier strand (the first guide's s), l_w the rope
between the first and last guide, M = m1 + m2 + lambda L and k^2 = 2 lambda g / M:

    a(t) = a_e + (a0 - a_e) cosh(k t),   a_e = (L - l_w) / 2 - (m1 - m2) / (2 lambda).

Prints a(1 s) against it, the energy drift, steps, Newton iterations and wall time for each row
(docs/verification.md, "Guides"). Several minutes a row.

    PYTHONPATH=python /usr/bin/python3 scripts/atwood_guides.py [--rows 2:84:1e-2,17:230:1e-4]
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))
import slidebeam  # noqa: E402

M1, M2, LAMBDA, G, R = 1.2, 1.0, 0.5, 9.81, 0.1


def scene(n: int, spans: int, ei: float) -> tuple[str, float]:
    """The scene's text and the rope's length L."""
    if n == 2:
        top = [(-0.05, 0.0, 0.0), (0.05, 0.0, 0.0)]
    else:
        top = [(R * math.cos(t), 0.0, R * math.sin(t)) for t in (math.pi - j * math.pi / (n - 1) for j in range(n))]
    points = [(top[0][0], 0.0, -1.0)] + top + [(top[-1][0], 0.0, -1.0)]
    length = sum(math.dist(a, b) for a, b in zip(points, points[1:]))
    guides = "\n".join(f'[[guide]]\nname = "g{j}"\nrope = "rope"\npoint = [{p[0]:.12f}, 0.0, {p[2]:.12f}]\n'
                       f'static = "{"held" if j == 0 else "free"}"\n' for j, p in enumerate(top))
    poly = ", ".join(f"[{p[0]:.12f}, 0.0, {p[2]:.12f}]" for p in points)
    return f"""[scene]
name = "atwood"
[analysis]
type = "dynamic"
t_end = 1.0
dt = 0.002
start = "equilibrium"
[[beam]]
name = "rope"
polyline = [{poly}]
d2 = [0.0, 1.0, 0.0]
unstretched_length = {length:.12f}
spans = {spans}
section = {{ EA = 1.0e6, kGA = 4.0e5, GJ = {ei}, EI2 = {ei}, EI3 = {ei}, rhoA = {LAMBDA}, rhoI2 = 1e-9, rhoI3 = 1e-9 }}
[[point_mass]]
beam = "rope"
at = "start"
mass = {M1}
[[point_mass]]
beam = "rope"
at = "end"
mass = {M2}
{guides}
[gravity]
g = [0.0, 0.0, -{G}]
[output]
every = 10
xdmf = false
[petsc]
sb_jacobian_reuse = true
""", length


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rows", default="2:84:1e-2,17:230:1e-4", help="guides:spans:EI, comma-separated")
    args = ap.parse_args()
    print("| guides | deflection each | spans | EI, N m^2 | a(1 s) | closed form | error | energy drift / K | steps (cut) | Newton | wall, s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for row in args.rows.split(","):
        n, spans, ei = int(row.split(":")[0]), int(row.split(":")[1]), float(row.split(":")[2])
        text, length = scene(n, spans, ei)
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "atwood.toml"
            path.write_text(text)
            sim = slidebeam.Simulation(slidebeam.load_scene(path))
            started = time.perf_counter()
            run = sim.run_dynamic()
            wall = time.perf_counter() - started
        groups = sim.output_groups()
        values = [[float(v) for v in r.outputs] for r in run.records]
        names = [f"{g}.{n_}" for g, ns in groups.items() for n_ in ns]
        a_col, b_col = names.index("rope_at_g0.s"), names.index(f"rope_at_g{n - 1}.s")
        a0, lw = values[0][a_col], values[0][b_col] - values[0][a_col]
        mass = M1 + M2 + LAMBDA * length
        k = math.sqrt(2 * LAMBDA * G / mass)
        ae = (length - lw) / 2 - (M1 - M2) / (2 * LAMBDA)
        t1 = run.records[-1].t
        exact = ae + (a0 - ae) * math.cosh(k * t1)
        a1 = values[-1][a_col]
        K = max(r.kinetic_energy for r in run.records)
        drift = max(abs(r.total_energy - run.records[0].total_energy) for r in run.records) / K
        turn = 90.0 if n == 2 else 180.0 / (n - 1)
        status = "" if run.complete else f" (stopped at t = {t1:.3g}: {run.message})"
        print(f"| {n} | {turn:.3g} deg | {spans} | {ei:g} | {a1:.6f} | {exact:.6f} | {a1 - exact:.2e}{status} | "
              f"{drift:.1e} | {run.steps} ({run.rejected_steps}) | {run.newton_iterations} | {wall:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
