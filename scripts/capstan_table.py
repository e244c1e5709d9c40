#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The capstan relation on [[contact]] friction: a rope wrapped theta = pi/2, pi and 2 pi around a
fixed drum (a helix of 0.1 m pitch for the full turn), one leg held, the other pulled by a force
that grows from the equilibrium start's 100 N. The held leg keeps its tension T1 while friction
holds (the slip zone spreads from the pulled side, the sticking part's springs give a little);
once the pull F reaches exp(mu theta cos b) T1 (b the helix angle: the wrap's curvature is
cos^2 b / R) the whole wrap slips and T1 follows F at that ratio. Measured as the median of F / T1
over the steps after T1 has risen 5 % above its start, for mu = 0.3 and 0.5
(docs/verification.md, "Friction on contact").

    scripts/capstan_table.py [--quick] [--undamped]
    scripts/capstan_table.py --figure docs/capstan.png
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))

import slidebeam  # noqa: E402

R = 0.5        # the drum's (centre line's) radius, m
LEG = 1.0      # the straight legs, m
T0 = 100.0     # both legs' tension at the start, N
PITCH = 0.1    # the helix's advance along the axis per turn, m (a full turn only)


def helix_angle(theta: float) -> float:
    return float(np.arctan(PITCH / (2 * np.pi * R))) if theta > np.pi else 0.0


def capstan_ratio(mu: float, theta: float) -> float:
    return float(np.exp(mu * theta * np.cos(helix_angle(theta))))


def scene(mu: float, theta: float, ramp: float, top: float, spans: int, dt: float,
          damped: bool = True) -> slidebeam.Scene:
    """The rope over the drum, the pull growing linearly from T0 to top T0 over ramp seconds. The
    bed's stiffness and the rope's EA scale with the largest tension (sunk and stretched by about
    as much at every ratio); its damping gives the bed's bounce zeta = 0.16."""
    pitch = PITCH if theta > np.pi else 0.0
    phis = np.linspace(np.pi / 2 + theta / 2, np.pi / 2 - theta / 2, max(9, int(24 * theta / np.pi) + 1))
    arc = [np.array([R * np.cos(p), pitch * (phis[0] - p) / (2 * np.pi), R * np.sin(p)]) for p in phis]

    def along(p: float) -> np.ndarray:  # the unit tangent in the direction of travel (decreasing phi)
        d = np.array([R * np.sin(p), pitch / (2 * np.pi), -R * np.cos(p)])
        return d / np.linalg.norm(d)

    start = arc[0] - LEG * along(phis[0])
    pull = along(phis[-1])
    end = arc[-1] + LEG * pull
    scale = top / 3.0
    k, rhoA = 1e6 * scale, 0.1
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "start": "equilibrium", "dt": dt,
                     "t_end": ramp},
        "beam": [{"name": "rope", "polyline": [list(map(float, p)) for p in [start, *arc, end]], "spans": spans,
                  "section": {"EA": 1e4 * scale, "kGA": 5e3 * scale, "GJ": 1e-3, "EI2": 1e-3, "EI3": 1e-3,
                              "rhoA": rhoA, "rhoI2": 1e-7, "rhoI3": 1e-7}}],
        "support": [{"type": "spherical", "beam": "rope", "at": "start"}],
        "load": [{"type": "force", "beam": "rope", "at": "end", "value": list(map(float, T0 * pull)),
                  "time_function": {"type": "table", "times": [0.0, ramp], "values": [1.0, top]}}],
        "damping": [{"beam": "rope", "retardation_time": 2e-3}],
        "contact": [{"type": "cylinder", "beam": "rope", "point": [0.0, 0.0, 0.0], "axis": [0.0, 1.0, 0.0],
                     "radius": R, "stiffness": k, "mu": mu,
                     "damping": 2 * 0.16 * np.sqrt(k * rhoA) if damped else 0.0}],
        "output": {"every": 1},
    })


def measure(mu: float, theta: float, quick: bool, damped: bool) -> dict[str, float]:
    limit = capstan_ratio(mu, theta)
    top, ramp = 1.3 * limit, 2.0 if quick else 4.0
    spans = int((2 * LEG + theta * R) / 0.06)
    started = time.perf_counter()
    sim = slidebeam.Simulation(scene(mu, theta, ramp, top, spans, 4e-3 if quick else 2e-3, damped))
    records = sim.run_dynamic().records
    wall = time.perf_counter() - started
    t = np.array([r.t for r in records])
    T1 = np.array([np.linalg.norm(r.reactions[0].force) for r in records])
    F = T0 * (1.0 + (top - 1.0) * t / ramp)
    # while the whole wrap slips: the held leg's tension rising, from 5 % above its start on (before
    # that the last sticking points' springs still give)
    slip = T1 >= 1.05 * T1[0]
    below = F < 0.95 * limit * T1[0]
    scale = max(max(r.kinetic_energy, abs(r.work), r.dissipated) for r in records)
    return {"limit": limit, "ratio": float(np.median(F[slip] / T1[slip])) if slip.any() else float("nan"),
            "held": float(np.abs(T1[below] / T1[0] - 1.0).max()),
            "balance": max(r.energy_balance_error for r in records) / scale,
            "newton": float(np.mean([r.newton_iterations for r in records[1:]])), "wall": wall}


def figure(path: Path) -> None:
    """runs/cables/capstan.toml over its 4 s: the pull F and the held leg's tension T1, their ratio
    against exp(mu pi), and the lengths of the wrap that stick and slip."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    root = Path(__file__).resolve().parents[1]
    scene = slidebeam.load_scene(root / "runs" / "cables" / "capstan.toml", ["output.every=1"])
    sim = slidebeam.Simulation(scene)
    records = sim.run_dynamic().records
    labels = sim.output_labels()
    t = np.array([r.t for r in records])
    T1 = np.array([np.linalg.norm(r.reactions[0].force) for r in records])
    F = T0 * (1.0 + 2.0 * t / 4.0)
    stick = np.array([r.outputs[labels.index("cylinder_friction[rope].sticking")] for r in records])
    slip = np.array([r.outputs[labels.index("cylinder_friction[rope].slipping")] for r in records])
    limit = np.exp(0.3 * np.pi)
    fig, ax = plt.subplots(3, 1, figsize=(7, 7.5), sharex=True)
    ax[0].plot(t, F, label="pull F")
    ax[0].plot(t, T1, label="held leg T1")
    ax[0].set_ylabel("tension, N")
    ax[0].legend()
    ax[1].plot(t, F / T1, label="F / T1")
    ax[1].axhline(limit, color="k", ls="--", lw=0.8, label=f"exp(mu pi) = {limit:.4f}")
    ax[1].set_ylabel("ratio")
    ax[1].legend()
    ax[2].plot(t, stick, label="sticking")
    ax[2].plot(t, slip, label="slipping")
    ax[2].set_ylabel("length of rope, m")
    ax[2].set_xlabel("t, s")
    ax[2].legend()
    fig.suptitle("a rope half a turn over a capstan, mu = 0.3 (runs/cables/capstan.toml)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    print(f"wrote {path}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="2 s ramps at dt = 4 ms (4 s at 2 ms otherwise)")
    parser.add_argument("--undamped", action="store_true", help="the bed without its damping (it rings)")
    parser.add_argument("--figure", type=Path, help="draw runs/cables/capstan.toml's run into this PNG instead")
    args = parser.parse_args()
    if args.figure:
        figure(args.figure)
        return 0
    print("| wrap | mu | exp(mu theta cos b) | F / T1 while it slips | error | T1 while F < 0.95 limit T1 | "
          "balance / largest energy | Newton per step | wall, s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for theta, name in ((np.pi / 2, "pi/2"), (np.pi, "pi"), (2 * np.pi, "2 pi")):
        for mu in (0.3, 0.5):
            m = measure(mu, theta, args.quick, not args.undamped)
            print(f"| {name} | {mu} | {m['limit']:.5f} | {m['ratio']:.5f} | {m['ratio'] / m['limit'] - 1:+.1e} | "
                  f"within {m['held']:.1e} | {m['balance']:.1e} | {m['newton']:.2f} | {m['wall']:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
