#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""What one step Jacobian and one step residual of a scene cost: the scene's first steps are
taken, the next one prepared, and its Jacobian and residual assembled again and again at a trial
end state (x + h v). Prints the fastest of --repeat batches (timing noise only adds), in ms and us,
serially. Time it only on an otherwise idle machine.

    scripts/bench_jacobian.py runs/cables/cable_swing.toml
    scripts/bench_jacobian.py runs/cables/cable_swing.toml --set beam.0.quadrature=full
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python"))

from mpi4py import MPI  # noqa: E402

import slidebeam  # noqa: E402


def fastest(work, calls: int, repeat: int) -> float:
    """Seconds per call of the fastest of `repeat` batches of `calls` calls."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(calls):
            work()
        best = min(best, (time.perf_counter() - t0) / calls)
    return best


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", help="a dynamic scene (TOML)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override a scene value")
    parser.add_argument("--steps", type=int, default=3, help="steps taken before the timed one (default 3)")
    parser.add_argument("--repeat", type=int, default=9, help="batches; the fastest counts (default 9)")
    args = parser.parse_args()
    scene = slidebeam.load_scene(args.scene, args.set)
    sim = slidebeam.Simulation(scene, MPI.COMM_SELF)
    integ = sim.integrator
    h = scene.analysis.dt
    for _ in range(args.steps):
        integ.step(h)
    integ.prepare_step(h)
    x1 = integ.x.copy()
    x1.axpy(h, integ.v)
    J, F = sim.jacobian, x1.duplicate()
    t_jacobian = fastest(lambda: integ.step_jacobian(x1, J), 100, args.repeat)
    t_residual = fastest(lambda: integ.step_residual(x1, F), 1000, args.repeat)
    print(f"{Path(args.scene).stem}: {x1.getSize()} unknowns, step Jacobian {1e3 * t_jacobian:.3f} ms, "
          f"step residual {1e6 * t_residual:.1f} us")
    return 0


if __name__ == "__main__":
    sys.exit(main())
