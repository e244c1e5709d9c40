#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Peak memory of runs against their size: the measurements behind python/slidebeam/run/resources.py.

Runs short variants of a few scenes (static and dynamic, director beams and ANCF cables, with
XDMF output) at growing numbers of spans, each in its own process(es), and prints per run the
unknowns, the peak resident set summed over the ranks (getrusage's ru_maxrss at exit) and, from
the difference to the same scene with 1 span, the bytes per unknown; then the estimate of
resources.py for the same run.

    scripts/measure_memory.py [--spans 1000,10000,100000] [--ranks 1]
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
SCENES = {  # scene, extra --set for a short run
    "static director": ("runs/rollup.toml", ["analysis.steps=1", "load.0.value=[0,0,0.6]"]),  # 1 % of the moment
    "static ancf": ("runs/ancf_cantilever.toml", ["analysis.steps=1"]),
    "dynamic director": ("runs/pendulum16.toml", ["analysis.t_end=2e-3"]),
    "dynamic ancf": ("runs/pendulum16_ancf.toml", ["analysis.t_end=2e-3"]),
}
WRAPPER = """
import resource, sys
from mpi4py import MPI
from slidebeam.app.cli import main
sys.argv[0] = "slidebeam"
code = main(sys.argv[1:])
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
peaks = MPI.COMM_WORLD.gather(peak)
if MPI.COMM_WORLD.Get_rank() == 0:
    print("PEAK", sum(peaks), code, file=sys.stderr)
"""


def measure(scene: str, sets: list[str], spans: int, ranks: int, out: Path) -> tuple[int, int]:
    """(unknowns, peak bytes summed over ranks) of one run."""
    cmd = [sys.executable, "-c", WRAPPER, "run", str(ROOT / scene), "--out", str(out), "-q",
           "--set", f"beam.0.spans={spans}", *(a for s in sets for a in ("--set", s))]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks), *cmd]
    env = {**os.environ, "PYTHONPATH": str(ROOT / "python")}
    res = subprocess.run(cmd, capture_output=True, text=True, env=env)
    line = [ln for ln in res.stderr.splitlines() if ln.startswith("PEAK")]
    if not line:
        sys.exit(f"{' '.join(cmd)}: {res.stderr}")
    _, peak, code = line[-1].split()
    summary = json.loads((out / "summary.json").read_text())
    return int(summary["unknowns"]), int(peak)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--spans", default="1000,10000,100000")
    p.add_argument("--ranks", type=int, default=1)
    p.add_argument("--only", help="one of: " + ", ".join(SCENES))
    args = p.parse_args()
    sys.path.insert(0, str(ROOT / "python"))
    from slidebeam.scene import load_scene

    try:
        from slidebeam.run.resources import estimate
    except ImportError:  # before resources.py existed
        estimate = None

    print(f"{'case':18s} {'spans':>8s} {'unknowns':>9s} {'peak MB':>9s} {'B/unknown':>10s} {'estimate MB':>12s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, (scene, sets) in SCENES.items():
            if args.only and name != args.only:
                continue
            n0, base = measure(scene, sets, 1, args.ranks, Path(tmp) / "base")
            print(f"{name:18s} {1:8d} {n0:9d} {base / 1e6:9.1f} {'':>10s}", flush=True)
            for spans in (int(s) for s in args.spans.split(",")):
                n, peak = measure(scene, sets, spans, args.ranks, Path(tmp) / str(spans))
                est = (estimate(load_scene(ROOT / scene, [f"beam.0.spans={spans}", *sets]), args.ranks).total
                       if estimate else float("nan"))
                print(f"{name:18s} {spans:8d} {n:9d} {peak / 1e6:9.1f} {(peak - base) / (n - n0):10.0f} "
                      f"{est / 1e6:12.1f}", flush=True)


if __name__ == "__main__":
    main()
