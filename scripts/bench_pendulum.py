#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Speed benchmark (issue 3): the flexible pendulum of runs/pendulum16.toml and
runs/pendulum64.toml (director beam), and of runs/pendulum16_ancf.toml and
runs/pendulum64_ancf.toml (the same rod as an ANCF cable), 1 s of motion. Prints, per run, the
wall time of the time stepping alone (no output), Newton iterations, Jacobian evaluations and the
energy drift max |H(t) - H(0)| / max T.

    scripts/bench_pendulum.py                     # EM at dt = 1e-3, both meshes, plus dt = 1e-2
    scripts/bench_pendulum.py --formulation ancf  # one formulation only (director, ancf)
    scripts/bench_pendulum.py --all-integrators   # also midpoint, Newmark, HHT
    scripts/bench_pendulum.py -- -log_view        # PETSc options after --
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))


def main() -> int:
    argv = sys.argv[1:]
    petsc_args: list[str] = []
    if "--" in argv:
        i = argv.index("--")
        argv, petsc_args = argv[:i], argv[i + 1:]
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--all-integrators", action="store_true", help="also midpoint, Newmark and HHT")
    p.add_argument("--repeat", type=int, default=3, help="best of N timings (default 3)")
    p.add_argument("--formulation", choices=("director", "ancf", "both"), default="both",
                   help="beam formulation(s) to run (default both)")
    args = p.parse_args(argv)

    import petsc4py

    petsc4py.init([sys.argv[0], *petsc_args])
    import signal

    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `| head` ends quietly, not via PETSc's handler
    from slidebeam import Simulation, load_scene

    integrators = ["energy-momentum"] + (["midpoint", "newmark", "hht"] if args.all_integrators else [])
    formulations = ["director", "ancf"] if args.formulation == "both" else [args.formulation]
    cases = [(f, n, i, 1e-3) for f in formulations for n in (16, 64) for i in integrators]
    cases += [(f, n, "energy-momentum", 1e-2) for f in formulations for n in (16, 64)]
    print(f"{'beam':>8} {'spans':>5} {'integrator':>16} {'dt':>7} {'steps':>5} {'wall [s]':>9} {'us/step':>8} "
          f"{'newton':>6} {'jac':>5} {'energy drift':>12}  status")
    for formulation, spans, integrator, dt in cases:
        best, stats = float("inf"), None
        suffix = "_ancf" if formulation == "ancf" else ""
        for _ in range(args.repeat):
            scene = load_scene(ROOT / "runs" / f"pendulum{spans}{suffix}.toml",
                               [f'analysis.integrator="{integrator}"', f"analysis.dt={dt}"])
            sim = Simulation(scene)
            integ = sim.integrator
            n_steps = round(scene.analysis.t_end / dt)
            energies, newton, wall, status = [], 0, 0.0, "ok"
            e = sim.energies()
            energies.append((integ.kinetic_energy(), e["strain"] + e["potential"]))
            jac0 = integ.jacobian_evaluations
            for k in range(n_steps):
                t0 = time.perf_counter()
                r = integ.step(dt)
                wall += time.perf_counter() - t0
                if not r.converged:
                    status = f"failed at t = {integ.time:.4g}: {r.reason_name}"
                    break
                newton += r.iterations
                if (k + 1) % 10 == 0 or k + 1 == n_steps:  # outside the timer
                    e = sim.energies()
                    energies.append((integ.kinetic_energy(), e["strain"] + e["potential"]))
            T = [a for a, _ in energies]
            H = [a + b for a, b in energies]
            drift = max(abs(h - H[0]) for h in H) / max(max(T), 1e-300)
            if wall < best:
                best, stats = wall, (n_steps, newton, integ.jacobian_evaluations - jac0, drift, status)
        n_steps, newton, jacs, drift, status = stats
        print(f"{formulation:>8} {spans:5d} {integrator:>16} {dt:7.0e} {n_steps:5d} {best:9.3f} {1e6 * best / n_steps:8.1f} "
              f"{newton:6d} {jacs:5d} {drift:12.2e}  {status}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
