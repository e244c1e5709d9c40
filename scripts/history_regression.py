#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Every shipped scene's history against a reference taken before a change: the check that a
refactoring of the run loop, the solvers or the effects changed no result.

    scripts/history_regression.py record REF            # on the commit before the change
    scripts/history_regression.py compare REF NEW       # runs the scenes again into NEW, compares
    scripts/history_regression.py record REF --steps 200 --ranks 2

Each scene under runs/ (every .toml with a [scene] table) runs through the CLI into
DIR/<scene path>/ (history.csv, summary.json). --steps N shortens dynamic runs to N steps of
their dt (the default runs them whole: some take minutes); static runs are taken whole.
compare runs them the same way (the same --steps and --ranks) and checks every numeric column of
history.csv, row by row, against the reference: |new - ref| <= rtol max(|ref column|) (rtol
1e-12 by default; a column that is 0 throughout must stay 0 to the same rtol of the largest
|value| of the run). Prints a table and exits 1 if any scene differs, if a run ends differently
(complete, message) or has another number of records. Columns a new run adds (an effect's new
outputs) are listed, not compared; a column the reference has and the new run lacks differs.

A change that is exact only to roundoff (a sum taken in another order) is compared with a looser
tolerance and a floor: --rtol 1e-8 --floor 1e-3 judges each column against the larger of its own
largest |value| and 1e-3 of the run's largest, so that columns at roundoff level (residual norms,
energy balance errors, the momenta of a structure at rest) do not count as differences of order 1.
The floor also leaves out the columns that describe the solves rather than the results (Newton
iterations and residual norms: a solve at the tolerance may end an iteration sooner). Runs whose
step cuts are sensitive to roundoff (hard scenes at large steps, long chaotic runs) still differ
then, in their records or their late values.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# columns that are not results (timing)
_NOT_RESULTS = {"wall_time_s"}
# columns that describe the solves: compared only without a floor (exact comparisons)
_SOLVES = {"newton_iterations", "residual_norm", "constraint_residual"}


def scenes() -> list[Path]:
    out = []
    for path in sorted((ROOT / "runs").rglob("*.toml")):
        with path.open("rb") as f:
            if "scene" in tomllib.load(f):
                out.append(path)
    return out


def run(scene: Path, out: Path, steps: int | None, ranks: int) -> float:
    args = [str(ROOT / "scripts" / "slidebeam"), "run", str(scene), "--out", str(out), "-q"]
    with scene.open("rb") as f:
        analysis = tomllib.load(f).get("analysis", {})
    if steps and analysis.get("type", "dynamic") == "dynamic" and "dt" in analysis:
        t_end = min(float(analysis["t_end"]), steps * float(analysis["dt"]))
        args += ["--set", f"analysis.t_end={t_end!r}"]
    if ranks > 1:
        args = ["mpirun", "-n", str(ranks)] + args
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    started = time.perf_counter()
    subprocess.run(args, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - started


def read_history(folder: Path) -> tuple[list[str], list[list[float]]]:
    with (folder / "history.csv").open() as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    header, values = rows[0], []
    for row in rows[1:]:
        values.append([_number(v) for v in row])
    return header, values


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan  # a text column (reason): compared as text below


def compare(ref: Path, new: Path, rtol: float, floor: float = 0.0) -> tuple[bool, str]:
    """(same, what differs) of two runs' folders."""
    if not (ref / "history.csv").exists() or not (new / "history.csv").exists():
        return (ref / "history.csv").exists() == (new / "history.csv").exists(), "no history in one of them"
    s_ref = json.loads((ref / "summary.json").read_text())
    s_new = json.loads((new / "summary.json").read_text())
    for key in ("complete", "message"):
        if s_ref.get(key) != s_new.get(key):
            return False, f"{key}: {s_ref.get(key)!r} -> {s_new.get(key)!r}"
    h_ref, v_ref = read_history(ref)
    h_new, v_new = read_history(new)
    missing = [name for name in h_ref if name not in h_new]
    if missing:
        return False, f"columns gone: {', '.join(missing[:3])}{' ...' if len(missing) > 3 else ''}"
    added = len(h_new) - len(h_ref)  # new outputs: the reference's columns are compared, by name
    at = [h_new.index(name) for name in h_ref]
    v_new = [[row[i] for i in at] for row in v_new]
    if len(v_ref) != len(v_new):
        return False, f"{len(v_ref)} -> {len(v_new)} records"
    largest = max((abs(v) for row in v_ref for v in row if math.isfinite(v)), default=0.0)
    least_scale = floor * largest
    worst, where = 0.0, ""
    for c, name in enumerate(h_ref):
        if name in _NOT_RESULTS or (floor > 0.0 and name in _SOLVES):
            continue
        column = [row[c] for row in v_ref]
        scale = max(max((abs(v) for v in column if math.isfinite(v)), default=0.0), least_scale) or largest or 1.0
        for r, (a, b) in enumerate(zip(column, (row[c] for row in v_new))):
            if math.isnan(a) and math.isnan(b):
                continue
            d = abs(a - b) / scale
            if not d <= worst:
                worst, where = d, f"{name} row {r}"
    what = f"largest difference {worst:.1e} ({where})" if where else "identical"
    return worst <= rtol, what + (f" (+{added} new columns)" if added else "")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("action", choices=("record", "compare"))
    parser.add_argument("ref", type=Path, help="the reference folder")
    parser.add_argument("new", type=Path, nargs="?", help="compare: the folder of the new runs")
    parser.add_argument("--steps", type=int, default=None, help="shorten dynamic runs to this many steps")
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--rtol", type=float, default=1e-12)
    parser.add_argument("--floor", type=float, default=0.0,
                        help="judge each column against at least this fraction of the run's largest |value|")
    parser.add_argument("--only", default="", help="only scenes whose path contains this text")
    args = parser.parse_args()
    if args.action == "compare" and args.new is None:
        parser.error("compare needs the reference folder and a folder for the new runs")
    target = args.ref if args.action == "record" else args.new
    failures = 0
    for scene in scenes():
        rel = scene.relative_to(ROOT / "runs").with_suffix("")
        if args.only not in str(rel):
            continue
        seconds = run(scene, target / rel, args.steps, args.ranks)
        if args.action == "record":
            print(f"{str(rel):40s} {seconds:7.1f} s", flush=True)
            continue
        same, what = compare(args.ref / rel, target / rel, args.rtol, args.floor)
        failures += 0 if same else 1
        print(f"{str(rel):40s} {seconds:7.1f} s  {'same' if same else 'DIFFERS'}: {what}", flush=True)
    if args.action == "compare":
        print(f"{failures} scene(s) differ" if failures else "every scene's history is the same")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
