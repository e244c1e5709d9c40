#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Error-controlled steps against fixed ones: the error at t_end and the work of each.

For a scene: a reference run at a fine fixed step (its own error printed, from a run at twice
that step), fixed steps, then `[analysis] adapt = { rtol }` over several tolerances. The error is
the controller's norm at t_end: max over points and sliding coordinates of |x - x_ref| / L (L the
longest beam) and over directions of |d - d_ref|, to compare with rtol. Wall times are single
runs (this script compares work, steps and Newton iterations; bench_pendulum.py times steps).

    PYTHONPATH=python /usr/bin/python3 scripts/bench_adapt.py runs/soft_pendulum.toml \\
        --reference-dt 2.5e-5 --dts 1e-2,3e-3,1e-3,3e-4 --rtols 1e-3,1e-4,1e-5,1e-6
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))
import slidebeam  # noqa: E402
from slidebeam.scene.parse import load_scene  # noqa: E402


def run(path: str, sets: list[str]):
    sim = slidebeam.Simulation(load_scene(path, sets + ["output.every=1000000000", "output.xdmf=false"]))
    started = time.perf_counter()
    out = sim.run_dynamic()
    return sim, out, time.perf_counter() - started


def run_fixed(path: str, dt: float):
    """The scene at the fixed step dt (whatever its own [analysis] adapt says)."""
    return run(path, [f"analysis.dt={dt}", "analysis.adapt=false"])


def split(sim) -> tuple[list[int], list[int]]:
    """Unknowns of points and sliding coordinates, and of directions."""
    points, directions = [], []
    for b in range(len(sim.scene.beams)):
        first = sim.first_control_point(b)
        for c in range(sim.control_points(b).shape[0]):
            base, nq = sim.control_point_unknowns(first + c)
            points += range(base, base + 3)
            directions += range(base + 3, base + nq)
    points += [sim.sliding_coordinate_index(j) for j in range(len(sim.scene.sliding_joints))]
    return points, directions


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("scene")
    p.add_argument("--reference-dt", type=float, required=True)
    p.add_argument("--dts", default="1e-2,3e-3,1e-3,3e-4")
    p.add_argument("--rtols", default="1e-3,1e-4,1e-5")
    a = p.parse_args()
    ref_sim, ref, _ = run_fixed(a.scene, a.reference_dt)
    assert ref.complete, ref.message
    x_ref = ref_sim.x.getArray().copy()
    points, directions = split(ref_sim)
    length = max(b.geometry.length for b in ref_sim.scene.beams)

    def error(sim) -> float:
        d = np.abs(sim.x.getArray() - x_ref)
        return max(d[points].max() / length, d[directions].max() if directions else 0.0)

    check, out, _ = run_fixed(a.scene, 2 * a.reference_dt)
    print(f"{a.scene}: reference dt = {a.reference_dt:g}; the run at twice it differs by {error(check):.2e}")
    print(f"| run | error at t_end | error / rtol | steps | rejected | Newton iterations | wall [s] |")
    print("|---|---|---|---|---|---|---|")
    for dt in (float(v) for v in a.dts.split(",")):
        sim, out, wall = run_fixed(a.scene, dt)
        e = f"{error(sim):.2e}" if out.complete else "failed"
        print(f"| dt = {dt:g} | {e} | | {out.steps} | {out.rejected_steps} | {out.newton_iterations} | {wall:.2f} |")
    for rtol in (float(v) for v in a.rtols.split(",")):
        sim, out, wall = run(a.scene, [f"analysis.adapt={{rtol={rtol}}}", "analysis.dt_min=1e-12"])
        if not out.complete:
            print(f"| adapt rtol = {rtol:g} | failed: {out.message[:80]} | | {out.steps} | {out.rejected_steps} "
                  f"| {out.newton_iterations} | {wall:.2f} |")
            continue
        e = error(sim)
        print(f"| adapt rtol = {rtol:g} | {e:.2e} | {e / rtol:.2f} | {out.steps} | {out.rejected_steps} "
              f"| {out.newton_iterations} | {wall:.2f} |")


if __name__ == "__main__":
    main()
