#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The equilibrium start alone, against the size of the structure: bundles of 400-span carrier
cables with sliding hangers (scripts/make_cables.py, start = "equilibrium", one time step after
it), 7.5e3 to 1.0e5 unknowns, serially and on 2 ranks. For each: summary.json's
static_start.wall_time_s (median of --repeat runs), microseconds per unknown, continuation steps,
(and how many failed and were retried with half the pseudo-step), Newton iterations (failed
attempts included), iterations per continuation step, and continuation steps that needed the
pivoting LU of the whole saddle-point system.
Prints a Markdown table. Time it only on an otherwise idle machine (2 ranks need 2 idle cores).

    scripts/bench_start.py                          # 1, 2, 4 and 10 carriers, 1 and 2 ranks, 3 runs
    scripts/bench_start.py --carriers 1 4 --ranks 1 --repeat 1
    scripts/bench_start.py --hangers-each 4 --ranks 1      # the same load on every carrier
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
SPANS = 400  # per carrier
HANGERS = 4  # hangers per carrier, times the number of carriers: the load grows with the bundle


def scene(carriers: int, hangers: int, work: Path) -> Path:
    path = work / f"bundle_{carriers}x{hangers}.toml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--carriers", str(carriers),
                    "--spans", str(SPANS), "--hangers", str(hangers), "--start", "equilibrium",
                    "--t-end", "0.001", "--dt", "0.001", "--out", str(path)], check=True, capture_output=True)
    return path


def start(path: Path, ranks: int, work: Path) -> dict:
    """summary.json's static_start and unknowns of one run."""
    out = work / "out"
    cmd = [str(ROOT / "scripts" / "slidebeam"), "run", str(path), "--out", str(out), "-q", "--set", "output.xdmf=false"]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks), *cmd]
    env = {**os.environ, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
    res = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if res.returncode != 0:
        raise RuntimeError(f"{path.name} on {ranks} rank(s): {(res.stderr.strip().splitlines() or ['?'])[-1]}")
    summary = json.loads((out / "summary.json").read_text())
    return {**summary["static_start"], "unknowns": summary["unknowns"]}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--carriers", type=int, nargs="+", default=[1, 2, 4, 10])
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--hangers-each", type=int, default=0,
                   help="hangers on every carrier, whatever their number (default: 4 x the number of carriers)")
    a = p.parse_args()
    print(f"| carriers, hangers on each | unknowns | ranks | start, s (median of {a.repeat}) | us per unknown "
          "| continuation steps (cut) | Newton iterations | per step | steps on the full system | 2 ranks / 1 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for c in a.carriers:
            hangers = a.hangers_each or HANGERS * c
            path = scene(c, hangers, work)
            serial = None
            for n in a.ranks:
                runs = [start(path, n, work) for _ in range(a.repeat)]
                t = statistics.median(r["wall_time_s"] for r in runs)
                r = runs[0]
                if n == 1:
                    serial = t
                ratio = f"{t / serial:.2f}" if serial and n > 1 else ""
                steps, its = r["continuation_steps"], r["newton_iterations"]
                print(f"| {c}, {hangers} | {r['unknowns']} | {n} | {t:.3g} "
                      f"| {1e6 * t / r['unknowns']:.0f} | {steps} ({r['cut_steps']}) | {its} | {its / max(steps, 1):.1f} "
                      f"| {r['full_system_steps']} | {ratio} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
