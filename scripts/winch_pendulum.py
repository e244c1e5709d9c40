#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A pendulum on a rope through a point guide, of fixed length and paid out by a winch, against
the small-angle pendulum.

A 10 kg mass hangs 2 m below a fixed [[guide]] on an ANCF rope (EA = 1e8 N, EI = 1e-3 N m^2,
1e-3 kg/m: nearly a massless string) whose other end, 3 m above the guide, is a spherical
support. The rope starts hanging straight with an angular velocity of 0.05 rad/s about the guide.
Fixed length: the support stays; the period against 2 pi sqrt(l/g) (1 + theta0^2/16), over
several spans. Winch: the support moves down 2 m by a smooth ramp over 10 s, paying the rope out
through the guide (l = 2 m -> 4 m); the angle against the small-angle equation
(l^2 theta')' + g l theta = 0 (for l = l0 + v t its solution is
theta = l^-1/2 [A J1(2 sqrt(g l)/v) + B Y1(2 sqrt(g l)/v)]; here l follows the ramp, so the
reference integrates the equation, RK4 at 1e-4 s), its two constants fitted to the run's first
0.5 s. Prints a table (docs/verification.md, "Guides").

    PYTHONPATH=python /usr/bin/python3 scripts/winch_pendulum.py [--spans 25,50,100]
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))
import slidebeam  # noqa: E402

L0, DROP, T_END, G = 2.0, 2.0, 10.0, 9.81


def scene(spans: int, drop: float, t_end: float) -> str:
    return f"""[scene]
name = "winch_pendulum"
[analysis]
type = "dynamic"
t_end = {t_end}
dt = 0.005
[[beam]]
name = "rope"
start = [0.0, 0.0, 3.0]
end = [0.0, 0.0, -{L0}]
spans = {spans}
formulation = "ancf"
section = {{ EA = 1.0e8, EI = 1.0e-3, rhoA = 1.0e-3 }}
angular_velocity = [0.0, 0.05, 0.0]
rotation_center = [0.0, 0.0, 0.0]
[[support]]
type = "spherical"
beam = "rope"
at = "start"
motion = {{ displacement = [0.0, 0.0, {-drop}], time_function = {{ type = "smooth_ramp", t0 = 0.0, t1 = {T_END} }} }}
[[guide]]
name = "sheave"
rope = "rope"
point = [0.0, 0.0, 0.0]
[[point_mass]]
beam = "rope"
at = "end"
mass = 10.0
[gravity]
g = [0.0, 0.0, -{G}]
[output]
every = 1
xdmf = false
track = [{{ beam = "rope", at = "end" }}]
"""


def angle(spans: int, drop: float, t_end: float):
    """The run's times, the angle of the mass about the guide, the energy balance's largest error
    relative to the largest kinetic energy, and the wall time."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "pendulum.toml"
        path.write_text(scene(spans, drop, t_end))
        with warnings.catch_warnings():  # the angular velocity about the guide is projected on the support
            warnings.simplefilter("ignore")
            sim = slidebeam.Simulation(slidebeam.load_scene(path))
        started = time.perf_counter()
        run = sim.run_dynamic()
        wall = time.perf_counter() - started
    t = np.array([r.t for r in run.records])
    end = np.array([r.tracked[0] for r in run.records])
    K = max(r.kinetic_energy for r in run.records)
    balance = max(abs(r.energy_balance_error) for r in run.records) / K
    return t, np.arctan2(end[:, 0], -end[:, 2]), balance, wall


def length(t: float) -> tuple[float, float]:
    """l and dl/dt below the guide while the winch pays out (the smooth ramp)."""
    u = min(max(t / T_END, 0.0), 1.0)
    return L0 + DROP * u ** 3 * (10 - 15 * u + 6 * u * u), DROP * 30 * u * u * (1 - u) ** 2 / T_END


def small_angle(theta0: float, rate0: float, times: np.ndarray, h: float = 1e-4) -> np.ndarray:
    def f(t: float, y: np.ndarray) -> np.ndarray:
        l, dl = length(t)
        return np.array([y[1], -(2 * dl * y[1] + G * y[0]) / l])
    out, y, t = [], np.array([theta0, rate0]), 0.0
    for target in times:
        while t < target - 1e-12:
            dt = min(h, target - t)
            k1 = f(t, y)
            k2 = f(t + dt / 2, y + dt / 2 * k1)
            k3 = f(t + dt / 2, y + dt / 2 * k2)
            k4 = f(t + dt, y + dt * k3)
            y, t = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4), t + dt
        out.append(y[0])
    return np.array(out)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spans", default="25,50,100", help="the rope's elements, comma-separated")
    args = ap.parse_args()
    spans = [int(v) for v in args.spans.split(",")]
    print("Fixed length, 2 m: the period over 6 s")
    print("| elements | span h, m | period, s | 2 pi sqrt(l/g) (1 + theta0^2/16) | error | pivot below the guide / h | balance / K | wall, s |")
    print("|---|---|---|---|---|---|---|---|")
    for n in spans:
        t, th, balance, wall = angle(n, 1e-12, 6.0)
        i = np.where((th[:-1] > 0) & (th[1:] <= 0))[0]
        crossings = t[i] - th[i] * (t[i + 1] - t[i]) / (th[i + 1] - th[i])
        period = float(np.diff(crossings).mean())
        exact = 2 * math.pi * math.sqrt(L0 / G) * (1 + np.abs(th).max() ** 2 / 16)
        h = 5.0 / n
        pivot = L0 * (1 - (period / exact) ** 2) / h  # the length that would give this period
        print(f"| {n} | {h:.3g} | {period:.6f} | {exact:.6f} | {period / exact - 1:.2e} | {pivot:.3f} | {balance:.1e} | {wall:.0f} |",
              flush=True)
    print("\nWinch: paid out 2 m over 10 s")
    print("| elements | theta(10 s) | small-angle equation | error / amplitude | largest over the run | balance / K | wall, s |")
    print("|---|---|---|---|---|---|---|")
    for n in spans[:1]:
        t, th, balance, wall = angle(n, DROP, T_END)
        b1, b2 = small_angle(1.0, 0.0, t), small_angle(0.0, 1.0, t)
        first = t <= 0.5
        c, *_ = np.linalg.lstsq(np.vstack([b1[first], b2[first]]).T, th[first], rcond=None)
        ref = c[0] * b1 + c[1] * b2
        amp = np.abs(th).max()
        print(f"| {n} | {th[-1]:.6f} | {ref[-1]:.6f} | {(th[-1] - ref[-1]) / amp:.2e} | {np.abs(th - ref).max() / amp:.2e} | "
              f"{balance:.1e} | {wall:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
