#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""What the output costs: runs with a record every step, the share of the wall time in the
output phase (the cost table's `output` row: XDMF records, checkpoint, history.csv and the final
files), medians of repeated runs.

    scripts/bench_output.py                          # this tree
    scripts/bench_output.py --before /path/to/other/checkout --repeat 5

Scenes: the seed benchmark 1+4 (1000 steps) and a ~1e5-unknown cable scene written by
scripts/make_cables.py (--carriers 10 --spans 400 --hangers 40, started from the reference
drawing, a few steps). --before runs another checkout's slidebeam the same way (its
python/slidebeam must hold a built _core), for a before/after table. Timings depend on the
machine's load: compare shares taken in one invocation.
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
PYTHON = "/usr/bin/python3"  # Debian's petsc4py imports only there


def _cables(folder: Path) -> Path:
    scene = folder / "cables_1e5.toml"
    subprocess.run([PYTHON, str(ROOT / "scripts" / "make_cables.py"), "--carriers", "10", "--spans", "400",
                    "--hangers", "40", "--start", "reference", "--out", str(scene)], check=True, capture_output=True)
    return scene


def _run(tree: Path, scene: Path, sets: list[str], out: Path) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree / "python")}
    cmd = [PYTHON, "-m", "slidebeam", "run", str(scene), "--out", str(out), "-q"]
    for s in sets:
        cmd += ["--set", s]
    res = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{res.stderr}")
    summary = json.loads((out / "summary.json").read_text())
    output = next(r for r in summary["cost"] if r["phase"] == "output")
    records = sum(1 for _ in (out / "history.csv").open()) - 1
    return {"wall": summary["wall_time_s"], "output": output["time_s"], "records": records}


def _median_row(runs: list[dict]) -> dict:
    return {"wall": statistics.median(r["wall"] for r in runs),
            "output": statistics.median(r["output"] for r in runs),
            "share": statistics.median(r["output"] / r["wall"] for r in runs),
            "per_record_ms": statistics.median(1e3 * r["output"] / r["records"] for r in runs),
            "records": runs[0]["records"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", type=Path, help="another checkout to measure the same way (e.g. before a change)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per scene and tree (default 3; medians)")
    ap.add_argument("--cable-steps", type=int, default=5, help="time steps of the cable scene (default 5)")
    args = ap.parse_args()
    trees = ([("before", args.before.resolve())] if args.before else []) + [("this tree", ROOT)]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        cables = _cables(folder)
        scenes = [
            ("seed 1+4, 1000 steps", ROOT / "runs" / "seed" / "free_fall_1+4.toml", ["output.every=1"]),
            (f"cables 10x400x40, {args.cable_steps} steps", cables,
             ["output.every=1", f"analysis.t_end={args.cable_steps * 1e-3!r}"]),
        ]
        print(f"{'scene':<28} {'code':<10} {'records':>7} {'wall [s]':>9} {'output [s]':>10} {'share':>6} "
              f"{'ms/record':>9}")
        for label, scene, sets in scenes:
            for name, tree in trees:
                runs = [_run(tree, scene, sets, folder / f"out{k}") for k in range(args.repeat)]
                m = _median_row(runs)
                print(f"{label:<28} {name:<10} {m['records']:>7d} {m['wall']:>9.3f} {m['output']:>10.3f} "
                      f"{100 * m['share']:>5.1f}% {m['per_record_ms']:>9.2f}", flush=True)


if __name__ == "__main__":
    main()
