#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Scaling benchmark on generated cable scenes (scripts/make_cables.py): time per step against
the number of unknowns on one rank, strong scaling (one scene on 1, 2, ... ranks) and weak
scaling (unknowns per rank fixed), with the share of each phase from PETSc's log events
(assembly by effect, linear solve, output, rest). Prints Markdown tables.

    scripts/bench_scaling.py                      # sizes 1e3 .. 1e5, ranks 1 and 2
    scripts/bench_scaling.py --max-unknowns 3e4 --ranks 1 2 --steps 10
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SIZES = [(1, 32, 4), (2, 64, 8), (4, 128, 16), (8, 256, 32), (10, 400, 40)]  # carriers, spans, hangers


def unknowns(c: int, s: int, h: int) -> int:
    return 18 * (c * (s + 2) + c * h * 4) + 4 * c * h


def run(c: int, s: int, h: int, steps: int, ranks: int, work: Path, petsc: list[str] | None = None) -> dict:
    scene = work / f"cables_{c}_{s}_{h}.toml"
    subprocess.run([str(ROOT / "scripts" / "make_cables.py"), "--carriers", str(c), "--spans", str(s),
                    "--hangers", str(h), "--t-end", str(steps * 1e-3), "--out", str(scene)],
                   check=True, capture_output=True)
    out = work / f"run_{c}_{s}_{h}_np{ranks}"
    cmd = [str(ROOT / "scripts" / "slidebeam"), "run", str(scene), "--out", str(out), "-q",
           "--set", "output.xdmf=false", "--set", f"output.every={steps}", "--set", "analysis.start=reference",
           *(["--", *petsc] if petsc else [])]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks), *cmd]
    env = {**os.environ, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
    res = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if res.returncode != 0:
        return {"error": (res.stderr.strip().splitlines() or ["?"])[-1]}
    summary = json.loads((out / "summary.json").read_text())
    phases = {r["phase"]: r["time_s"] for r in summary["cost"]}
    step_time = summary["stepping_time_s"]
    assembly = sum(t for p, t in phases.items() if p.startswith("assembly"))
    contact = sum(t for p, t in phases.items() if "sliding_joint" in p)
    # the median step: the first one also records the Jacobian's pattern and factors symbolically
    return {"unknowns": summary["unknowns"], "steps": summary["steps"], "per_step": summary["step_time_s"]["median"],
            "first_step": summary["step_time_s"]["first"], "search_setup": summary["contact_search_setup_s"],
            "newton": summary["newton_iterations"] / summary["steps"], "assembly": assembly / step_time,
            "contact": contact / step_time, "solve": phases["linear solve (incl. factorisation)"] / step_time,
            "output": phases["output"] / summary["wall_time_s"]}


MUMPS = ["-pc_factor_mat_solver_type", "mumps"]  # the direct solve on every rank count


def row(r: dict, extra: str = "") -> str:
    if "error" in r:
        return f"| {extra} failed: {r['error']} |"
    return (f"| {extra}{r['unknowns']} | {1e3 * r['per_step']:.1f} | {1e6 * r['per_step'] / r['unknowns']:.1f} "
            f"| {1e3 * r['first_step']:.0f} | {1e3 * r['search_setup']:.2f} | {r['newton']:.1f} "
            f"| {100 * r['assembly']:.0f} % | {100 * r['contact']:.1f} % | {100 * r['solve']:.0f} % "
            f"| {100 * r['output']:.1f} % |")


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--max-unknowns", type=float, default=1.2e5)
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--steps", type=int, default=10)
    a = p.parse_args()
    sizes = [s for s in SIZES if unknowns(*s) <= a.max_unknowns]
    head = ("| {} | ms per step (median) | us per step per unknown | first step, ms (pattern, symbolic LU) "
            "| slider search set-up, ms | Newton its per step | assembly | of which contact (sliding joints) "
            "| linear solve | output (of wall) |\n|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        print("One rank, growing scene (direct LU in the model's elimination order):\n")
        print(head.format("unknowns"))
        for s in sizes:
            print(row(run(*s, a.steps, 1, work)), flush=True)
        big = sizes[-1]
        print(f"\nStrong scaling ({unknowns(*big)} unknowns; default: PETSc LU in the model's order on one rank, "
              f"GMRES + Schwarz on the model's subdomains on more; MUMPS: direct LU on all ranks):\n")
        print(head.format("ranks, solver: unknowns"))
        for n in a.ranks:
            print(row(run(*big, a.steps, n, work), f"{n}, default: "), flush=True)
            print(row(run(*big, a.steps, n, work, MUMPS), f"{n}, MUMPS: "), flush=True)
        print("\nWeak scaling (carriers = 2 x ranks, 128 spans, 16 hangers each):\n")
        print(head.format("ranks: unknowns"))
        for n in a.ranks:
            print(row(run(2 * n, 128, 16, a.steps, n, work), f"{n}: "), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
