#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Shipped and generated scenes on 1 and 2 ranks: the run's wall time (summary.json's
wall_time_s, median of --repeat runs; the equilibrium start included where the scene has one)
serially, on 2 ranks with the default -sb_serial_below (small models owned by rank 0 alone) and on
2 ranks distributed (-sb_serial_below 0). Prints a Markdown table with the ratios to the serial
time. Time it only on an otherwise idle machine.

    scripts/bench_ranks.py                 # the default shipped scenes, 3 runs each
    scripts/bench_ranks.py --generated     # make_cables.py ropeways and nets, 2.6e3 to 7.3e4 unknowns

With --generated the table has the static start's own time too (summary.json's
static_start.wall_time_s) and a third column: 2 ranks with the static start on rank 0 alone
(-sb_equilibrium_on_rank_0) instead of on both.
    scripts/bench_ranks.py --repeat 5 runs/cables/zip_line.toml
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENES = [("runs/seed/free_fall_1+4.toml", []), ("runs/hard/two_sliders.toml", []),
          ("runs/cables/zip_line.toml", []), ("runs/effects/ropeway.toml", ["analysis.t_end=0.4"]),
          ("runs/pendulum64.toml", []), ("runs/rollup.toml", []), ("runs/rollup.toml", ["beam.0.spans=256"]),
          ("runs/cables/ropeway.toml", ["analysis.t_end=0.4"]),
          ("runs/hard/slider_skips_spans.toml", ["analysis.t_end=0.3"])]
# make_cables.py arguments (equilibrium start, 50 steps of 1e-3): ropeways (carriers, spans,
# hangers) and cable nets (K x K ropes, spans between crossings)
GENERATED = [("cables_1x100x10", ["--carriers", "1", "--spans", "100", "--hangers", "10"]),
             ("cables_3x64x8", ["--carriers", "3", "--spans", "64", "--hangers", "8"]),
             ("cables_1x400x40", ["--carriers", "1", "--spans", "400", "--hangers", "40"]),
             ("cables_5x200x20", ["--carriers", "5", "--spans", "200", "--hangers", "20"]),
             ("net_10x10x4", ["--net", "10", "--spans", "4"]),
             ("net_10x10x16", ["--net", "10", "--spans", "16"])]


def generate(work: Path) -> list[tuple[str, list[str]]]:
    """The GENERATED scenes, written into work."""
    import sys

    out = []
    for name, args in GENERATED:
        path = work / f"{name}.toml"
        subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), *args, "--start", "equilibrium",
                        "--t-end", "0.05", "--out", str(path)], check=True, capture_output=True)
        out.append((str(path), []))
    return out


def run(scene: str, sets: list[str], ranks: int, petsc: list[str], work: Path) -> tuple[float, int, float]:
    """The run's wall time, its unknowns and its static start's wall time (0 without one)."""
    out = work / "out"
    cmd = [str(ROOT / "scripts" / "slidebeam"), "run", str(ROOT / scene), "--out", str(out), "-q",
           "--set", "output.xdmf=false", *[a for s in sets for a in ("--set", s)], *(["--", *petsc] if petsc else [])]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks), *cmd]
    env = {**os.environ, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
    subprocess.run(cmd, check=True, capture_output=True, env=env)
    summary = json.loads((out / "summary.json").read_text())
    start = summary.get("static_start") or {}
    return float(summary["wall_time_s"]), int(summary["unknowns"]), float(start.get("wall_time_s", 0.0))


def generated_table(scenes: list[tuple[str, list[str]]], repeat: int, work: Path) -> None:
    """Whole run and static start, 1 rank against 2 (start on both, and on rank 0 alone)."""
    print("| scene | unknowns | 1 rank: run, s (start, s) | 2 ranks: run, s (ratio) | start, s (ratio) "
          "| 2 ranks, start on rank 0: run, s (ratio) |")
    print("|---|---|---|---|---|---|")
    for scene, sets in scenes:
        med = {}
        unknowns = 0
        for label, ranks, petsc in (("1", 1, []), ("2", 2, []), ("2r0", 2, ["-sb_equilibrium_on_rank_0", "true"])):
            samples = [run(scene, sets, ranks, petsc, work) for _ in range(repeat)]
            unknowns = samples[0][1]
            med[label] = (statistics.median(t for t, _, _ in samples), statistics.median(s for _, _, s in samples))
        (one, one_start), (two, two_start), (r0, _) = med["1"], med["2"], med["2r0"]
        print(f"| {Path(scene).stem} | {unknowns} | {one:.3g} ({one_start:.3g}) | {two:.3g} ({two / one:.2f}) | "
              f"{two_start:.3g} ({two_start / one_start:.2f}) | {r0:.3g} ({r0 / one:.2f}) |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="*", help="scene files (default: a set of shipped scenes)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--generated", action="store_true", help="generated cable scenes (make_cables.py)")
    args = ap.parse_args()
    if args.generated:
        with tempfile.TemporaryDirectory() as tmp:
            generated_table(generate(Path(tmp)), args.repeat, Path(tmp))
        return
    print("| scene | unknowns | 1 rank, s | 2 ranks (default), s | ratio | 2 ranks distributed, s | ratio |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        scenes = [(s, []) for s in args.scenes] or SCENES
        for scene, sets in scenes:
            times = {}
            unknowns = 0
            for label, ranks, petsc in (("1", 1, []), ("2", 2, []), ("2d", 2, ["-sb_serial_below", "0"])):
                samples = []
                for _ in range(args.repeat):
                    t, unknowns, _ = run(scene, sets, ranks, petsc, work)
                    samples.append(t)
                times[label] = statistics.median(samples)
            one = times["1"]
            name = Path(scene).name + (f" ({', '.join(sets)})" if sets else "")
            print(f"| {name} | {unknowns} | {one:.3g} | {times['2']:.3g} | {times['2'] / one:.2f} | "
                  f"{times['2d']:.3g} | {times['2d'] / one:.2f} |", flush=True)


if __name__ == "__main__":
    main()
