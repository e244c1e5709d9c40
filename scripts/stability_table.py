#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Every hard scene of runs/hard/ with every integrator (issue 8): did it finish, energy drift
max |H - H(0)| / max T, largest constraint residual, rejected steps, Newton iterations, wall time,
and how it ended. Writes docs/stability/table.md and prints it.

    scripts/stability_table.py                  # all scenes x all integrators, 2 at a time (~10 min)
    scripts/stability_table.py -j 1 --scenes slender cable_whip
"""
from __future__ import annotations

import argparse
import math
import sys
import tomllib
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from slidebeam.app.study import Variant, _run_one, load_run  # noqa: E402

INTEGRATORS = {
    "energy-momentum": {},
    "EM, dissipative (xi = 0.1)": {"analysis.em_dissipation": "0.1"},
    "midpoint": {"analysis.integrator": "midpoint"},
    "newmark": {"analysis.integrator": "newmark"},
    "hht (alpha = -0.1)": {"analysis.integrator": "hht"},
}


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("-j", "--jobs", type=int, default=2, help="runs at once (default 2)")
    p.add_argument("--scenes", nargs="*", help="scene names in runs/hard/ (default: all)")
    p.add_argument("--out", type=Path, default=ROOT / "docs" / "stability", help="output folder")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds a run may take (default 300)")
    args = p.parse_args()
    scenes = sorted((ROOT / "runs" / "hard").glob("*.toml"))
    if args.scenes:
        scenes = [s for s in scenes if s.stem in args.scenes]
    runs_dir = args.out / "runs"
    runs_dir.mkdir(parents=True, exist_ok=True)
    plan = [(scene, name, sets) for scene in scenes for name, sets in INTEGRATORS.items()]

    def work(item):
        scene, name, sets = item
        variant = Variant(0, {**sets, "output.xdmf": "false"})
        folder = runs_dir / f"{scene.stem}__{name.split(' ')[0].strip(',')}{'_xi' if 'xi' in name else ''}"
        code, message = _run_one(scene, variant, {}, folder, [], args.timeout)
        return scene, name, code, load_run(variant, folder, code, message)

    rows = []
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for scene, name, code, run in pool.map(work, plan):
            s = run.summary
            ended = ("finished" if s.get("complete") and code == 0 else
                     "stopped: slider at carrier end" if code == 0 and s else
                     f"not finished: {run.message}" if code == -1 else
                     "stopped: " + (run.message.split("error: ")[-1].split(";")[0] if run.message else f"exit {code}"))
            row = (scene.stem, name, ended, run.drift(), s.get("max_constraint_residual", math.nan),
                   s.get("rejected_steps", 0), s.get("newton_iterations", 0), s.get("wall_time_s", math.nan),
                   s.get("t_reached", math.nan))
            rows.append(row)
            print(f"{scene.stem:20s} {name:28s} {ended[:60]:60s} drift {row[3]:.1e}", flush=True)
    statements = {sc.stem: tomllib.loads(sc.read_text())["scene"]["description"] for sc in scenes}
    lines = ["| scene | integrator | run | energy balance error max\\|H−H0−W+D\\|/max T | max constraint residual | rejected steps "
             "| Newton iterations | wall [s] | t reached |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]:.1e} | {r[4]:.1e} | {r[5]} | {r[6]} | {r[7]:.1f} | {r[8]:.3g} |")
    text = "What makes each scene hard:\n\n" + "\n".join(f"- `{k}`: {v}" for k, v in statements.items())
    text += "\n\n" + "\n".join(lines) + "\n"
    (args.out / "table.md").write_text(text)
    print(f"wrote {args.out / 'table.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
