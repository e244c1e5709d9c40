#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Friction that sticks, against closed forms: prints the figures of docs/verification.md,
"Friction on sliding joints", and draws docs/friction_arc.png (the block on the circular rail:
angle against the closed form's turning points, ds/dt, energies).

  - the block of runs/effects/friction_block.toml (30 degree rail): held (mu = 0.7), at the
    limit (mu = tan 30 deg, from the equilibrium start) and sliding (mu = 0.3) against
    s'' = -g (sin a - mu cos a), and the dissipation against mu N |ds|;
  - the rail tilted from 20 to 25 degrees by a driven support (mu = 0.4): the slide's
    acceleration once the rail is still;
  - runs/effects/friction_arc.toml: turning points and rest angle against the closed form, at
    dt = 2 ms and 1 ms, Newton iterations per step;
  - runs/effects/friction_zip_line.toml: the trolley's release, stick and slide (and
    docs/friction_zip_line.png).

    scripts/friction_table.py            # about half a minute
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))
sys.path.insert(0, str(ROOT / "tests" / "python"))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--figure", default=str(ROOT / "docs" / "friction_arc.png"), help="PNG of the circular rail")
    parser.add_argument("--zip-figure", default=str(ROOT / "docs" / "friction_zip_line.png"),
                        help="PNG of the friction zip line")
    args = parser.parse_args()
    import numpy as np

    from test_condensation import petsc_options
    from test_friction import ALPHA, G, arc_rail, arc_turning_points, block, s_history, tilting_rail

    def its(records) -> str:
        n = [r.newton_iterations for r in records[1:]]
        return f"{np.mean(n):.2f} mean, {max(n)} at most"

    def balance(records) -> float:
        scale = max(max(r.kinetic_energy for r in records), abs(records[-1].work), records[-1].dissipated, 1e-300)
        return max(r.energy_balance_error for r in records) / scale

    for mu, label, start in ((0.7, "held, mu = 0.7", None), (math.tan(ALPHA), "at the limit, mu = tan 30 deg", "equilibrium")):
        t, s, rec = s_history(block(ROOT, mu, t_end=1.0, start=start))
        print(f"block {label}: max |s - s0| = {np.abs(s - s[0]).max():.1e} m over {t[-1]:g} s, D = {rec[-1].dissipated:.1e} J, "
              f"Newton {its(rec)}")
    t, s, rec = s_history(block(ROOT, 0.3))
    exact = -G * (math.sin(ALPHA) - 0.3 * math.cos(ALPHA))
    late = t >= 0.2
    c = np.polyfit(t[late] - 0.6, s[late], 2)
    m = 1.0 + 0.1 * 0.1
    D = 0.3 * m * G * math.cos(ALPHA) * abs(s[-1] - s[0])
    print(f"block sliding, mu = 0.3: s'' = {2 * c[0]:.13f} against {exact:.13f} (error {(2 * c[0] - exact) / G:.1e} g), "
          f"D = {rec[-1].dissipated:.9f} J against mu m g cos a |ds| = {D:.9f} J, balance {balance(rec):.1e} of max K, "
          f"Newton {its(rec)}")
    t, s, rec = s_history(tilting_rail(20.0, 5.0, 0.4, 0.8))
    exact = -G * (math.sin(math.radians(25.0)) - 0.4 * math.cos(math.radians(25.0)))
    late = t >= 0.4
    c = np.polyfit(t[late] - 0.6, s[late], 2)
    first = t[np.nonzero(np.diff(s))[0][0] + 1]
    print(f"rail tilted 20 -> 25 deg over 0.1-0.3 s, mu = 0.4: first slip at t = {first:.3f} s; s'' = {2 * c[0]:.13f} against "
          f"{exact:.13f} (error {(2 * c[0] - exact) / G:.1e} g); W = {rec[-1].work:.4f} J, D = {rec[-1].dissipated:.4f} J, "
          f"balance {balance(rec):.1e}; Newton {its(rec)}")
    points = arc_turning_points(math.radians(-40.0), 0.1, G)
    print("circular rail, closed form (deg): " + ", ".join(f"{math.degrees(p):.6f}" for p in points))
    arc = {}
    for dt, options in ((2e-3, {}), (1e-3, {}), (2e-3, {"sb_floor_stop": "true"})):
        with petsc_options(**options):
            t, s, rec = s_history(arc_rail(0.1, 3.3, dt=dt))
        theta = math.radians(-45.0) + s
        turns = [theta.max(), theta[theta.argmax():].min(), theta[-1]]
        moving = np.nonzero(np.diff(s))[0]
        print(f"  dt = {dt * 1e3:g} ms{' -sb_floor_stop' if options else ''}: " + ", ".join(f"{math.degrees(v):.6f}" for v in turns) +
              f" (rest error {turns[-1] - points[-1]:.1e} rad); at rest from t = {t[moving[-1] + 1]:.3f} s; "
              f"Newton {its(rec)}; balance {balance(rec):.1e}")
        arc.setdefault(dt, (t, theta, rec))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t, theta, rec = arc[2e-3]
    fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    ax[0].plot(t, np.degrees(theta), label="slidebeam")
    for p in points:
        ax[0].axhline(math.degrees(p), color="0.6", lw=0.6, ls="--")
    ax[0].set_ylabel("angle from the bottom (deg)")
    ax[0].legend(["slidebeam", "closed form's turning points and rest"], loc="upper right", fontsize=8)
    ax[1].plot(t[1:], np.diff(theta) / np.diff(t))
    ax[1].set_ylabel("d(angle)/dt (rad/s)")
    ax[2].plot(t, [r.kinetic_energy for r in rec], label="kinetic")
    ax[2].plot(t, [r.dissipated for r in rec], label="dissipated by friction")
    ax[2].set_ylabel("J")
    ax[2].set_xlabel("t (s)")
    ax[2].legend(fontsize=8)
    fig.suptitle("runs/effects/friction_arc.toml: a block with mu = 0.1 on a circular rail")
    fig.tight_layout()
    fig.savefig(args.figure, dpi=90)
    print(f"wrote {args.figure}")
    plt.close(fig)

    import slidebeam

    zip_scene = slidebeam.load_scene(ROOT / "runs" / "effects" / "friction_zip_line.toml", ["output.every=1"])
    t, s, rec = s_history(zip_scene)
    rate = np.array([r.joints[0].ds_dt for r in rec])
    early = t <= 0.05
    release = next(k for k in range(1, len(t)) if rate[k] == 0.0)
    # the longest stretch of records with ds/dt = 0 (the trolley held by friction)
    best, start = (0, 0), None
    for k, v in enumerate(rate):
        if v == 0.0 and start is None:
            start = k
        if (v != 0.0 or k == len(rate) - 1) and start is not None:
            best = max(best, (k - start, start))
            start = None
    held_from, held_to = t[best[1]], t[best[1] + best[0]]
    print(f"zip line: at release s moves {s[release] - s[0]:.3f} m in {t[release]:.3f} s (ds/dt up to "
          f"{rate[early].max():.2f} m/s), friction takes {rec[release].dissipated:.2f} J; held (ds/dt = 0) from "
          f"{held_from:.3f} s to {held_to:.3f} s; after {t[-1]:g} s D = {rec[-1].dissipated:.1f} J, "
          f"K = {rec[-1].kinetic_energy:.1f} J, balance {balance(rec):.1e}; Newton {its(rec)}")
    fig, ax = plt.subplots(4, 1, figsize=(7, 8), sharex=True)
    ax[0].plot(t, s)
    ax[0].set_ylabel("s (m)")
    ax[1].plot(t, rate)
    ax[1].set_ylabel("ds/dt (m/s)")
    ax[2].plot(t, [r.kinetic_energy for r in rec], label="kinetic")
    ax[2].plot(t, [r.dissipated for r in rec], label="dissipated by friction")
    ax[2].set_ylabel("J")
    ax[2].legend(fontsize=8)
    ax[3].semilogy(t[1:], [max(r.energy_balance_error, 1e-16) for r in rec[1:]])
    ax[3].set_ylabel("|H - H0 - W + D| (J)")
    ax[3].set_xlabel("t (s)")
    fig.suptitle("runs/effects/friction_zip_line.toml: an 80 kg trolley with mu = 0.05")
    fig.tight_layout()
    fig.savefig(args.zip_figure, dpi=90)
    print(f"wrote {args.zip_figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
