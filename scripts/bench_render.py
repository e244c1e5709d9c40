#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Time ``slidebeam render`` on run folders: the set-up (reading the series, the camera and the
colour scale over the run) and the seconds per frame of a PNG picture and of a GIF animation
(medians over the frames). Prints one row per run.

    scripts/slidebeam run runs/effects/ropeway.toml --out out/ropeway
    scripts/make_cables.py --net 7 --spans 4 --t-end 0.5 --out /tmp/net7.toml      # 12 978 unknowns
    scripts/slidebeam run /tmp/net7.toml --out out/net7 --set output.every=1
    scripts/bench_render.py out/ropeway out/net7 [--frames 20]
"""
from __future__ import annotations

import argparse
import io
import json
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "python"))

from slidebeam.plots.render import Renderer  # noqa: E402
from slidebeam.output.rundata import open_run  # noqa: E402


def bench(folder: Path, frames: int) -> dict[str, float]:
    from matplotlib.animation import PillowWriter

    start = time.perf_counter()
    run = open_run(folder)
    assert run.beams is not None
    count = len(run.beams.times)
    records = sorted({int(round(r)) for r in [i * (count - 1) / max(frames - 1, 1) for i in range(frames)]})
    renderer = Renderer(run, "iso", "tension", (1280, 720))
    setup = time.perf_counter() - start
    png = []
    for r in records:
        t0 = time.perf_counter()
        renderer.draw(r)
        renderer.fig.savefig(io.BytesIO(), format="png")
        png.append(time.perf_counter() - t0)
    writer = PillowWriter(fps=20)
    gif = []
    out = folder / "bench_render.gif"
    with writer.saving(renderer.fig, str(out), dpi=renderer.fig.dpi):
        for r in records:
            t0 = time.perf_counter()
            renderer.draw(r)
            writer.grab_frame()
            gif.append(time.perf_counter() - t0)
    out.unlink()  # (PillowWriter encodes the GIF when it finishes: not in the frame times)
    summary = json.loads((folder / "summary.json").read_text()) if (folder / "summary.json").is_file() else {}
    run.close()
    return {"unknowns": summary.get("unknowns", float("nan")), "points": len(run.beams.points),
            "cells": len(run.beams.cells), "records": count, "setup": setup,
            "png": statistics.median(png), "gif": statistics.median(gif), "frames": len(records)}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", type=Path, help="run folders with beams.xdmf")
    p.add_argument("--frames", type=int, default=20, help="frames timed per run (default 20)")
    args = p.parse_args()
    print("| run | unknowns | beam points, cells | records | set-up, s | PNG frame, s | GIF frame, s |")
    print("|---|---|---|---|---|---|---|")
    for folder in args.runs:
        r = bench(folder, args.frames)
        print(f"| {folder.name} | {r['unknowns']} | {r['points']}, {r['cells']} | {r['records']} | "
              f"{r['setup']:.2f} | {r['png']:.3f} | {r['gif']:.3f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
