#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Redraw the user guide's plots and pictures (docs/figures/) from shipped scenes:
``runs/effects/ropeway.toml`` (every kind of plot, pictures from two views), a 7 x 7 rockfall
net from ``scripts/make_cables.py`` (a picture of a 12 978-unknown structure), and the multibody
scenes ``runs/multibody/crane.toml``, ``cable_robot.toml``, ``ropeway.toml``, ``rockfall_net.toml`` and
``winch.toml``, ``block_and_tackle.toml``, ``ropeway_towers.toml``, ``track_ropes.toml``,
``cable_robot_winches.toml``, ``crane_winch.toml`` (pictures). About five minutes.

    scripts/doc_figures.py [--out docs/figures] [--work out/doc_figures]
"""
from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "python"))

from slidebeam import plots  # noqa: E402
from slidebeam.plots import render  # noqa: E402


def run(*args: str) -> None:
    subprocess.run([str(ROOT / "scripts" / "slidebeam"), *args], check=True)


def multibody_pictures(out: Path, work: Path) -> list[Path]:
    """The crane slewed (t = 6 s), the cable robot half way (t = 2.5 s), the ropeway's cabin
    under way (t = 6 s), the boulder deepest in the rockfall net (t = 0.1 s), the winch's rope
    wound half a turn (t = 4.5 s, seen along the drum's axis), the block and tackle after its
    pull (t = 4 s, seen along the sheaves' axes), the ropeway over two towers (t = 5 s, from the
    front), the trolley on the bridge rail between two track ropes (t = 5.4 s, from the front), the
    cable robot on winches a quarter of the way round its circle (t = 4 s), the crane after
    hoisting by its winch (t = 8 s, from the front)."""
    written = []
    for scene, t in (("crane", 6.0), ("cable_robot", 2.5), ("ropeway", 6.0), ("rockfall_net", 0.1), ("winch", 4.5),
                     ("block_and_tackle", 4.0), ("ropeway_towers", 5.0), ("track_ropes", 5.4),
                     ("cable_robot_winches", 4.0), ("crane_winch", 8.0)):
        run("run", str(ROOT / "runs" / "multibody" / f"{scene}.toml"), "--out", str(work / scene), "-q",
            "--set", f"analysis.t_end={t}")
        written += render.pictures(work / scene, times=[t], out=out / f"render_{scene}.png", size=(1100, 650),
                                   view="front" if scene in ("winch", "block_and_tackle", "ropeway_towers", "track_ropes",
                                                             "crane_winch")
                                   else "iso")
    return written


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=ROOT / "docs" / "figures", help="where the figures go")
    p.add_argument("--work", type=Path, default=ROOT / "out" / "doc_figures", help="where the runs go")
    args = p.parse_args()
    ropeway, net = args.work / "ropeway", args.work / "net7"
    run("run", str(ROOT / "runs" / "effects" / "ropeway.toml"), "--out", str(ropeway), "-q")
    net_scene = args.work / "net7.toml"
    net_scene.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--net", "7", "--spans", "4",
                    "--t-end", "0.5", "--dt", "0.01", "--out", str(net_scene)], check=True)
    run("run", str(net_scene), "--out", str(net), "-q")
    written = []
    for kind in plots.KINDS:
        written += plots.plot([ropeway], what=[kind], out=args.out / f"plot_{kind}.png")
    written += render.pictures(ropeway, times=[3.0], out=args.out / "render_ropeway_iso.png", size=(1100, 600))
    written += render.pictures(net, out=args.out / "render_net.png", size=(1100, 650))
    written += multibody_pictures(args.out, args.work)
    for f in written:
        print(f"wrote {f.relative_to(ROOT) if f.is_relative_to(ROOT) else f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
