#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The cable benchmark: time steps of the cable scenes users run, with the Newton variant chosen
by cost (the default) against full Newton (-sb_jacobian_reuse false) and modified Newton
(-sb_jacobian_reuse). Per scene and variant: ms per step (summary.json stepping_time_s / steps,
median of --repeat runs), Newton iterations, Jacobians and rejected steps per step, and the share
of the Jacobian assembly in the run. For the swing (runs/cables/cable_swing.toml) also its
accuracy: the first sideways frequency from the tracked midpoint's zero crossings against the
exact linear value 1.579505 rad/s, and the support tension of the static start against the elastic
catenary (Irvine) of the same cable. Time it only on an otherwise idle machine.

    scripts/bench_cables.py                      # every scene, 3 runs each
    scripts/bench_cables.py --repeat 1 --quick   # the swing shortened to 10.5 s

A side-by-side with MoorDyn on the same cable is not in this script yet (docs/performance.md,
"Cables", says what is open).
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import statistics
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SWING = "runs/cables/cable_swing.toml"
SCENES = [(SWING, []), ("runs/cables/zip_line.toml", []), ("runs/cables/hanging_rope.toml", ["analysis.t_end=0.2"]),
          ("runs/effects/ropeway.toml", ["analysis.t_end=0.4"]), ("runs/effects/moving_anchor.toml", []),
          ("runs/cables/ropeway.toml", ["analysis.t_end=0.2"])]
VARIANTS = [("chosen by cost", ["-sb_newton_by_cost"]), ("full Newton", ["-sb_jacobian_reuse", "false"]),
            ("modified Newton", ["-sb_jacobian_reuse"])]
EXACT_OMEGA = 1.579505  # rad/s, the swing's first out-of-plane mode (linear theory)


def run(scene: str, sets: list[str], petsc: list[str], out: Path) -> dict:
    cmd = [str(ROOT / "scripts" / "slidebeam"), "run", str(ROOT / scene), "--out", str(out), "-q",
           "--set", "output.xdmf=false", *[a for s in sets for a in ("--set", s)], "--", *petsc]
    subprocess.run(cmd, check=True, capture_output=True, text=True)
    return json.loads((out / "summary.json").read_text())


def assembly_share(summary: dict) -> float:
    """Share of the run in assembly: the cost table's effect rows, residuals and Jacobians together."""
    return sum(c["share"] for c in summary.get("cost", []) if c["phase"].startswith("assembly"))


def swing_frequency(history: Path) -> float:
    """omega of the tracked midpoint's sideways (y) motion after the support stopped (t > 1 s):
    the least-squares fit of a + b sin(omega t) + c cos(omega t) plus a sine and cosine at the
    strongest higher mode of the spectrum (the third symmetric mode, at 3x the frequency, rides
    on the first: zero crossings were off by 1e-3), omega refined on a grid about the peak."""
    import numpy as np

    rows = list(csv.DictReader(history.open()))
    t = np.array([float(r["t"]) for r in rows])
    y = np.array([float(r["cable@50.3.y"]) for r in rows])
    keep = t > 1.0
    t, y = t[keep], y[keep]
    if len(t) < 16:
        return float("nan")
    spectrum = np.abs(np.fft.rfft((y - y.mean()) * np.hanning(len(y))))
    omegas = 2 * math.pi * np.fft.rfftfreq(len(y), t[1] - t[0])
    peak = omegas[1 + int(np.argmax(spectrum[1:]))]
    above = omegas > 2 * peak  # the strongest higher mode, fitted alongside
    other = omegas[above][int(np.argmax(spectrum[above]))]

    def misfit(w: float) -> float:
        A = np.column_stack([np.ones_like(t), np.sin(w * t), np.cos(w * t), np.sin(other * t), np.cos(other * t)])
        c, *_ = np.linalg.lstsq(A, y, rcond=None)
        return float(np.linalg.norm(A @ c - y))

    lo, hi = 0.9 * peak, 1.1 * peak
    for _ in range(4):  # grids of 201 points, each 20x finer about the best
        grid = np.linspace(lo, hi, 201)
        best = grid[int(np.argmin([misfit(w) for w in grid]))]
        half = 5 * (hi - lo) / 200
        lo, hi = best - half, best + half
    return float(best)


def catenary_tension(L0: float = 100.6, span: float = 100.0, w: float = 9.81, EA: float = 1.0e7) -> float:
    """Support tension of a level elastic catenary (Irvine): H from
    span = H L0 / EA + H / w (asinh(V / H) - asinh((V - W) / H)), V = W / 2, by bisection."""
    W = w * L0
    V = W / 2

    def gap(H: float) -> float:
        return H * L0 / EA + H / w * (math.asinh(V / H) - math.asinh((V - W) / H)) - span

    lo, hi = 1.0, 1.0e6
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if gap(lo) * gap(mid) <= 0:
            hi = mid
        else:
            lo = mid
    H = 0.5 * (lo + hi)
    return math.hypot(H, V)


def start_tension(history: Path) -> float:
    row = next(csv.DictReader(history.open()))
    return math.sqrt(sum(float(row[f"spherical[cable@start].f{c}"]) ** 2 for c in "xyz"))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeat", type=int, default=3, help="runs per scene and variant (the median is shown)")
    p.add_argument("--quick", action="store_true", help="the swing over 10.5 s instead of 60.5 s")
    p.add_argument("scenes", nargs="*", help="scene files (default: the cable scenes)")
    args = p.parse_args()
    scenes = [(s, []) for s in args.scenes] if args.scenes else SCENES
    print("| scene | unknowns | Newton | ms / step | iterations / step | Jacobians / step | rejected / step "
          "| assembly share | vs full Newton |")
    print("|---|---|---|---|---|---|---|---|---|")
    swing_checked = False
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for scene, sets in scenes:
            if scene == SWING and args.quick:
                sets = [*sets, "analysis.t_end=10.5"]
            full_ms = None
            rows = []
            for name, petsc in VARIANTS:
                ms, its, jac, rej, share = [], [], [], [], []
                for k in range(args.repeat):
                    out = work / f"out_{k}"
                    s = run(scene, sets, petsc, out)
                    n = max(1, s["steps"])
                    ms.append(1e3 * s["stepping_time_s"] / n)
                    its.append(s["newton_iterations"] / n)
                    jac.append(s["jacobian_evaluations"] / n)
                    rej.append(s["rejected_steps"] / n)
                    share.append(assembly_share(s))
                    if scene == SWING and not swing_checked:
                        omega = swing_frequency(out / "history.csv")
                        T, T_exact = start_tension(out / "history.csv"), catenary_tension()
                        swing_checked = True
                        accuracy = (f"swing: omega = {omega:.7f} rad/s (exact linear {EXACT_OMEGA}: relative error "
                                    f"{abs(omega / EXACT_OMEGA - 1):.1e}); support tension {T:.4f} N (elastic "
                                    f"catenary {T_exact:.4f} N: relative error {abs(T / T_exact - 1):.1e})")
                med = statistics.median(ms)
                if name == "full Newton":
                    full_ms = med
                rows.append((name, med, statistics.median(its), statistics.median(jac), statistics.median(rej),
                             statistics.median(share)))
                unknowns = s["unknowns"]
            for name, med, it, jc, rj, sh in rows:
                ratio = f"{full_ms / med:.2f}x faster" if full_ms else "–"
                label = Path(scene).stem + (f" ({', '.join(sets)})" if sets else "")
                print(f"| {label} | {unknowns} | {name} | {med:.3f} | {it:.2f} | {jc:.3f} | {rj:.3f} | {sh:.0%} "
                      f"| {ratio} |", flush=True)
    if swing_checked:
        print()
        print(accuracy)


if __name__ == "__main__":
    main()
