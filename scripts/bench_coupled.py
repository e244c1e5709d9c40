#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Coupled ranks: scenes whose split of control points over ranks cuts through a beam or its joints,
solved on 1 rank and on 2 ranks with each parallel linear solve: GMRES on block Jacobi
(-sb_schwarz_exact false), the exact coupling correction (the default) and MUMPS on the whole
system. Prints a Markdown table: wall time of the time steps (median of --repeat
runs), KSP iterations per solve (max / mean), rejected steps and what the run ended with. Time
it only on an otherwise idle machine.

    scripts/bench_coupled.py                 # the default scenes, 3 runs each (about 5 minutes)
    scripts/bench_coupled.py --repeat 5
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOLVERS = {
    "GMRES": ["-sb_schwarz_exact", "false"],
    # the correction whatever the interface (the default takes GMRES beyond 1024 coupled rows)
    "exact (default)": ["-sb_schwarz_exact_max_interface", "100000"],
    # threshold pivoting 0.5: with MUMPS's default the saddle-point systems of these scenes break down
    "MUMPS": ["-sb_ts_pc_type", "lu", "-sb_ts_pc_factor_mat_solver_type", "mumps", "-sb_ts_mat_mumps_cntl_1", "0.5",
              "-sb_ts_mat_mumps_icntl_14", "200"],
}


def scenes(work: Path) -> list[tuple[str, Path, list[str]]]:
    def cables(name: str, *args: str) -> Path:
        out = work / f"{name}.toml"
        subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), *args, "--start", "reference",
                        "--out", str(out)], check=True, capture_output=True)
        return out

    rope = cables("rope", "--carriers", "1", "--spans", "2000", "--hangers", "1")
    hung = cables("hung", "--carriers", "1", "--spans", "400", "--hangers", "40")
    net = cables("net", "--net", "10", "--spans", "4")
    fine_net = cables("fine_net", "--net", "10", "--spans", "16")
    return [
        ("slider_skips_spans (rail cut once), dt = 1e-2, 0.3 s", ROOT / "runs" / "hard" / "slider_skips_spans.toml",
         ["analysis.t_end=0.3"]),
        ("the same at dt = 0.1 (10x)", ROOT / "runs" / "hard" / "slider_skips_spans.toml",
         ["analysis.t_end=0.3", "analysis.dt=0.1"]),
        ("2000-span rope, 1 hanger (cut once), dt = 1e-3, 10 steps", rope, ["analysis.t_end=0.01", "analysis.dt=1e-3"]),
        ("the same rope, dt = 1e-2, 10 steps", rope, ["analysis.t_end=0.1", "analysis.dt=1e-2"]),
        ("400-span rope, 40 hangers (cut once), dt = 1e-3, 10 steps", hung,
         ["analysis.t_end=0.01", "analysis.dt=1e-3"]),
        ("10 x 10 net, 4 spans per stretch (cut across), dt = 1e-3, 20 steps", net,
         ["analysis.t_end=0.02", "analysis.dt=1e-3"]),
        ("10 x 10 net, 16 spans per stretch, dt = 1e-3, 20 steps", fine_net,
         ["analysis.t_end=0.02", "analysis.dt=1e-3"]),
    ]


def worker(scene: str, sets: list[str]) -> None:
    """Under mpirun: run the scene, print the figures as JSON (rank 0)."""
    import time

    from mpi4py import MPI

    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(scene, sets), MPI.COMM_WORLD)
    its: list[int] = []

    def monitor(_ksp, it, _rnorm):
        if it == 0:
            its.append(0)
        its[-1] = it

    sim.snes.getKSP().setMonitor(monitor)
    start = time.perf_counter()
    out = sim.run_dynamic()
    wall = time.perf_counter() - start
    if MPI.COMM_WORLD.rank == 0:
        print(json.dumps({"wall": wall, "unknowns": sim.x.getSize(), "complete": out.complete,
                          "rejected": out.rejected_steps, "max_its": max(its, default=0),
                          "mean_its": sum(its) / max(1, len(its)), "pc": sim.snes.getKSP().getPC().getType()}))


def run(scene: Path, sets: list[str], ranks: int, petsc: list[str]) -> dict:
    cmd = [sys.executable, __file__, "--worker", str(scene), *sets, "--", *petsc, "-sb_serial_below", "0"]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks), *cmd]
    env = {**os.environ, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "PYTHONPATH": str(ROOT / "python")}
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, env=env)
    return json.loads(next(line for line in out.stdout.splitlines() if line.startswith("{")))


def main() -> None:
    if "--worker" in sys.argv:
        i = sys.argv.index("--worker")
        rest = sys.argv[i + 1:]
        petsc = rest[rest.index("--") + 1:] if "--" in rest else []
        args = rest[:rest.index("--")] if "--" in rest else rest
        import petsc4py

        petsc4py.init(petsc)
        worker(args[0], args[1:])
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print("| scene | unknowns | 1 rank, s | 2 ranks: " + " | ".join(f"{s}, s (its max / mean)" for s in SOLVERS) + " |")
    print("|---|---|---|" + "---|" * len(SOLVERS))
    with tempfile.TemporaryDirectory() as tmp:
        for name, scene, sets in scenes(Path(tmp)):
            cells = []
            serial = [run(scene, sets, 1, []) for _ in range(args.repeat)]
            one = statistics.median(r["wall"] for r in serial)
            for petsc in SOLVERS.values():
                rs = [run(scene, sets, 2, petsc) for _ in range(args.repeat)]
                t = statistics.median(r["wall"] for r in rs)
                r = rs[0]
                note = "" if r["complete"] else ", incomplete"
                note += f", {r['rejected']} rejected" if r["rejected"] else ""
                note += ", then MUMPS (a step failed)" if r["pc"] == "lu" and petsc != SOLVERS["MUMPS"] else ""
                cells.append(f"{t:.2f} ({t / one:.2f}x; {r['max_its']} / {r['mean_its']:.1f}{note})")
            print(f"| {name} | {serial[0]['unknowns']} | {one:.2f} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
