# SPDX-License-Identifier: MIT
"""Work-precision studies: run a grid of variants of a scene, measure each run's error against a
reference run and its cost, and write a CSV, a Markdown table and log-log diagrams of error
against wall time with the observed convergence orders.

Errors, over the times both runs reached (the reference interpolated linearly in time):

- ``tip``: largest distance between the run's first tracked point and the reference's;
- ``s``: largest difference of the first sliding joint's coordinate (scenes with joints);
- ``energy``: largest |H(t) - H_ref(t)|, divided by the reference's largest kinetic energy.

Each run also reports its own energy drift: the energy balance's largest error
max |H - H0 - W + D| / max T (with no work and no dissipation, max |H(t) - H(0)| / max T). Costs come from the run's
summary.json: wall time without the output phase, steps, Newton iterations and linear solves.
All dynamic runs record at the same times (every max(dt) of the study), so errors are taken
where both runs have a state.

Curves: a varied key whose values are all numbers is a refinement axis. The one with the most
values is the x of the orders; the curves are the combinations of the other varied keys.

Tolerance-driven runs (``adapt = [rtol, ...]`` in the study file, ``--adapt rtol,...``): besides
the grid, every combination of the other varied keys runs with ``[analysis] adapt = { rtol }``
instead of the varied ``analysis.dt``; they make curves of their own (``..., adaptive``), whose
order is the slope of the error against rtol (1: the error follows the tolerance). Their records
are every step, and their errors are taken at the reference's record times.
"""
from __future__ import annotations

import csv
import io
import itertools
import json
import math
import os
import subprocess
import sys
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..run.options_check import warnings_of_runs

# Each run is `python -m slidebeam run ...` under this interpreter, importing this same package
# (the source tree's python/ or an installed copy: docs/install.md).
PACKAGE_PARENT = Path(__file__).resolve().parents[2]


class StudyError(ValueError):
    """A study that cannot be set up (bad --vary, unknown study file keys, ...): bad input."""


@dataclass
class Variant:
    index: int
    sets: dict[str, str]  # key -> value text, as for --set
    extra: dict[str, str] = field(default_factory=dict)  # set by the study (record interval), not a label

    @property
    def label(self) -> str:
        parts: list[str] = []
        for k, v in self.sets.items():  # keys varied together show once
            part = f"{k.split('.')[-1]}={v}"
            if part not in parts:
                parts.append(part)
        return ", ".join(parts) or "base"

    @property
    def folder(self) -> str:
        safe = "".join(c if c.isalnum() or c in "-.=" else "_" for c in self.label.replace(", ", "__"))
        return f"{self.index:03d}_{safe}"


@dataclass
class RunData:
    variant: Variant
    folder: Path
    ok: bool
    message: str
    t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tip: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    s: np.ndarray | None = None
    H: np.ndarray = field(default_factory=lambda: np.zeros(0))
    T: np.ndarray = field(default_factory=lambda: np.zeros(0))
    summary: dict[str, Any] = field(default_factory=dict)
    balance: np.ndarray | None = None  # |H - H0 - W + D| per row (histories that have it)

    @property
    def complete(self) -> bool:
        return bool(self.summary.get("complete"))

    @property
    def work(self) -> float:
        return float(self.summary.get("steps", 0)) * float(self.summary.get("unknowns", 0))

    def cost(self) -> dict[str, float]:
        """Wall time without the output phase (what the numerics cost), steps, iterations, solves."""
        phases = {r["event"]: r for r in self.summary.get("cost", [])}
        wall = self.summary.get("wall_time_s", math.nan)
        output = phases.get("SBOutput", {}).get("time_s", 0.0)
        return {"wall_time_s": wall - output, "steps": self.summary.get("steps", 0),
                "newton_iterations": self.summary.get("newton_iterations", 0),
                "linear_solves": phases.get("KSPSolve+PCSetUp", {}).get("calls", 0)}

    def drift(self) -> float:
        """The energy balance's largest error |H - H0 - W + D| (with no work done and nothing
        dissipated: |H - H0|), relative to the largest kinetic energy."""
        if len(self.H) == 0 or self.T.max(initial=0.0) <= 0:
            return math.nan
        if self.balance is not None and len(self.balance):
            return float(self.balance.max() / self.T.max())
        return float(np.abs(self.H - self.H[0]).max() / self.T.max())


# -- set-up ----------------------------------------------------------------------------------

def parse_vary(text: str) -> tuple[list[str], list[str]]:
    """'key=v1,v2' or 'key1&key2=v1,v2' (keys varied together) -> (keys, values)."""
    keys_text, sep, values_text = text.partition("=")
    keys = [k.strip() for k in keys_text.split("&") if k.strip()]
    values = [v.strip() for v in values_text.split(",") if v.strip()]
    if not sep or not keys or not values:
        raise StudyError(f"--vary must look like key=v1,v2,... (got '{text}')")
    return keys, values


def parse_assignments(items: list[str], what: str) -> dict[str, str]:
    out = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise StudyError(f"{what} must look like key=value (got '{item}')")
        out[key.strip()] = value.strip()
    return out


def grid(varies: list[tuple[list[str], list[str]]]) -> list[Variant]:
    """The cartesian product of the varied values (keys varied together share a value)."""
    variants = []
    for i, combo in enumerate(itertools.product(*[values for _, values in varies])):
        sets: dict[str, str] = {}
        for (keys, _), value in zip(varies, combo):
            for k in keys:
                sets[k] = value
        variants.append(Variant(i, sets))
    return variants


def _toml_text(value: Any) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value)


def read_study_file(path: Path) -> dict[str, Any]:
    """A study file: a [study] table with scene (relative to the file), vary, and optionally
    reference, set and jobs."""
    try:
        data = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as err:
        raise StudyError(f"cannot read study file {path}: {err}") from err
    study = data.get("study")
    if not isinstance(study, dict):
        raise StudyError(f"{path}: a study file needs a [study] table")
    allowed = {"scene", "vary", "reference", "set", "jobs", "description", "curve_by", "adapt"}
    unknown = set(study) - allowed
    if unknown:
        raise StudyError(f"{path}: unknown key(s) in [study]: {', '.join(sorted(unknown))} "
                         f"(allowed: {', '.join(sorted(allowed))})")
    if "scene" not in study or "vary" not in study:
        raise StudyError(f"{path}: [study] needs 'scene' and 'vary'")
    varies = []
    for key, values in study["vary"].items():
        if not isinstance(values, list) or not values:
            raise StudyError(f"{path}: vary.{key} must be a non-empty list")
        varies.append((key.split("&"), [_toml_text(v) for v in values]))
    return {
        "scene": (path.parent / study["scene"]).resolve(),
        "varies": varies,
        "reference": {k: _toml_text(v) for k, v in study.get("reference", {}).items()},
        "sets": {k: _toml_text(v) for k, v in study.get("set", {}).items()},
        "jobs": int(study.get("jobs", 1)),
        "curve_by": list(study.get("curve_by", [])),
        "adapt": parse_tolerances(study.get("adapt", []), f"{path}: adapt"),
    }


def parse_tolerances(values: Any, what: str) -> list[float]:
    """rtols of the tolerance-driven runs: a list of numbers in (0, 1), or 'r1,r2' text."""
    items = values.split(",") if isinstance(values, str) else values
    if not isinstance(items, list):
        raise StudyError(f"{what} must be a list of tolerances, got {values!r}")
    out = []
    for v in items:
        try:
            r = float(v)
        except (TypeError, ValueError):
            raise StudyError(f"{what} must be numbers in (0, 1), got {v!r}") from None
        if not 0 < r < 1:
            raise StudyError(f"{what} must be numbers in (0, 1), got {v!r}")
        out.append(r)
    return out


ADAPT_KEY = "analysis.adapt"


def adaptive_variants(varies: list[tuple[list[str], list[str]]], rtols: list[float], first: int) -> list[Variant]:
    """Every combination of the varied keys other than analysis.dt, at each tolerance."""
    others = [(keys, values) for keys, values in varies if "analysis.dt" not in keys]
    out = []
    for rtol in rtols:
        for v in grid(others):
            out.append(Variant(first + len(out), {**v.sets, ADAPT_KEY: f"{{rtol={rtol:g}}}"},
                               {"output.every": "1"}))
    return out


# -- running ---------------------------------------------------------------------------------

def _run_one(scene: Path, variant: Variant, base_sets: dict[str, str], out: Path,
             petsc_args: list[str], timeout: float | None = None) -> tuple[int, str]:
    # no XDMF series: a study compares histories, and 50 runs of series are hundreds of MB
    cmd = [sys.executable, "-m", "slidebeam", "run", str(scene), "--out", str(out), "-q", "--set", "output.xdmf=false"]
    for k, v in {**base_sets, **variant.extra, **variant.sets}.items():
        cmd += ["--set", f"{k}={v}"]
    if petsc_args:
        cmd += ["--", *petsc_args]
    try:
        path = os.environ.get("PYTHONPATH")
        env = {**os.environ, "PYTHONPATH": str(PACKAGE_PARENT) + (os.pathsep + path if path else "")}
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return -1, f"still running after {timeout:.0f} s (stopped by the caller)"
    return res.returncode, (res.stderr.strip().splitlines() or [""])[-1]


def load_run(variant: Variant, folder: Path, code: int, message: str) -> RunData:
    summary_path, history_path = folder / "summary.json", folder / "history.csv"
    if not summary_path.is_file() or not history_path.is_file():
        return RunData(variant, folder, False, message or f"exit code {code}, no results")
    summary = json.loads(summary_path.read_text())
    rows = [r for r in csv.DictReader(history_path.open()) if r.get("converged", "1") == "1"]
    cols = list(rows[0]) if rows else []
    tip_cols = [c for c in cols if "@" in c and c.endswith(".x")]
    s_cols = [c for c in cols if c.endswith(".s") and "_on_" in c]

    def column(name: str) -> np.ndarray:
        return np.array([float(r[name]) for r in rows])

    tip = (np.column_stack([column(tip_cols[0][:-1] + c) for c in "xyz"]) if tip_cols
           else np.zeros((len(rows), 3)))
    return RunData(variant, folder, code in (0, 1), message if code else "completed", column("t"), tip,
                   column(s_cols[0]) if s_cols else None, column("total_energy"), column("kinetic_energy"), summary,
                   column("energy_balance_error") if "energy_balance_error" in cols else None)


def errors(run: RunData, ref: RunData) -> dict[str, float]:
    """Largest differences from the reference over the times both reached."""
    if len(run.t) == 0 or len(ref.t) == 0:
        return {"tip": math.nan, "s": math.nan, "energy": math.nan}
    scale = ref.T.max() if ref.T.max(initial=0.0) > 0 else 1.0
    if len(run.t) > len(ref.t):  # a run recorded more densely (adaptive steps): at the reference's times
        run, ref = ref, run
    keep = run.t <= ref.t[-1] * (1 + 1e-12)
    t = run.t[keep]

    def interp(values: np.ndarray) -> np.ndarray:
        return np.interp(t, ref.t, values)

    ref_tip = np.column_stack([interp(ref.tip[:, k]) for k in range(3)])
    out = {"tip": float(np.linalg.norm(run.tip[keep] - ref_tip, axis=1).max())}
    out["s"] = float(np.abs(run.s[keep] - interp(ref.s)).max()) if run.s is not None and ref.s is not None else math.nan
    out["energy"] = float(np.abs(run.H[keep] - interp(ref.H)).max() / scale)
    return out


def _numeric(values: list[str]) -> bool:
    try:
        [float(v) for v in values]
        return True
    except ValueError:
        return False


def curves(varies: list[tuple[list[str], list[str]]]) -> tuple[str | None, list[str]]:
    """(refinement key or None, keys that tell curves apart)."""
    numeric = [(len(values), "&".join(keys)) for keys, values in varies if _numeric(values)]
    x_key = max(numeric)[1] if numeric else None
    others = ["&".join(keys) for keys, _ in varies if "&".join(keys) != x_key]
    return x_key, others


ROUNDOFF = 1e-11  # errors below this (relative energy at solver tolerance) have no order


def observed_order(x: list[float], err: list[float]) -> float:
    """|slope| of log(err) against log(x), least squares over the finite, positive errors; nan
    with fewer than two such errors or when all are at roundoff (a conserved energy)."""
    pts = [(math.log(a), math.log(e)) for a, e in zip(x, err) if e > 0 and math.isfinite(e) and a > 0]
    if len(pts) < 2 or max(math.exp(p[1]) for p in pts) < ROUNDOFF:
        return math.nan
    xs, ys = np.array(pts).T
    return float(abs(np.polyfit(xs, ys, 1)[0]))


# -- the study -------------------------------------------------------------------------------

def common_record_interval(scene: Path, variants: list[Variant], base_sets: dict[str, str]) -> None:
    """Give every dynamic run the same record times, so that errors are taken where both runs
    have a state (no interpolation error): records every max(dt) of the study, that is
    output.every = max(dt) / dt for each run (when that is a whole number)."""
    from ..scene.parse import load_scene

    base = load_scene(scene, [f"{k}={v}" for k, v in base_sets.items()])
    if base.analysis.type != "dynamic" or base.analysis.dt is None:
        return
    fixed = [v for v in variants if ADAPT_KEY not in v.sets]
    dts = [float(v.sets.get("analysis.dt", base.analysis.dt)) for v in fixed]
    interval = max(dts)
    for v, dt in zip(fixed, dts):
        ratio = interval / dt
        if "output.every" not in v.sets and abs(ratio - round(ratio)) < 1e-9 * ratio:
            v.extra = {"output.every": str(round(ratio))}


def run_study(scene: Path, varies: list[tuple[list[str], list[str]]], out: Path,
              reference: dict[str, str] | None = None, base_sets: dict[str, str] | None = None,
              jobs: int = 1, petsc_args: list[str] | None = None, progress=print,
              curve_by: list[str] | None = None, adapt: list[float] | None = None) -> dict[str, Any]:
    """Run the grid (and the reference), write study.csv, study.md and the diagrams into out.
    curve_by: keys whose values make the diagram's curves (default: every varied key but the
    refinement key); each curve then joins all its runs in order of cost. adapt: tolerances of
    the tolerance-driven runs (see the module comment)."""
    base_sets = base_sets or {}
    variants = grid(varies)
    variants += adaptive_variants(varies, adapt or [], len(variants))
    out.mkdir(parents=True, exist_ok=True)
    runs_dir = out / "runs"
    runs_dir.mkdir(exist_ok=True)
    todo = list(variants)
    ref_variant = Variant(len(variants), dict(reference)) if reference else None
    if ref_variant is not None:
        todo.append(ref_variant)
    common_record_interval(scene, todo, base_sets)
    results: dict[int, RunData] = {}
    started = time.perf_counter()

    def work(v: Variant) -> RunData:
        folder = runs_dir / (v.folder if v is not ref_variant else "reference")
        code, message = _run_one(scene, v, base_sets, folder, petsc_args or [])
        return load_run(v, folder, code, message)

    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        for n, data in enumerate(pool.map(work, todo), 1):
            results[data.variant.index] = data
            progress(f"[{n:3d}/{len(todo)}] {('reference: ' if data.variant is ref_variant else '') + data.variant.label}: "
                     f"{data.summary.get('wall_time_s', math.nan):.2f} s, {data.message}")
    for line in warnings_of_runs(r.summary for r in results.values()):  # typos in PETSc options, once
        print(line, file=sys.stderr, flush=True)
    runs = [results[v.index] for v in variants]
    if ref_variant is not None:
        ref = results[ref_variant.index]
    else:
        candidates = [r for r in runs if r.complete]
        if not candidates:
            raise StudyError("no run of the grid completed: no reference (give --reference)")
        ref = max(candidates, key=lambda r: r.work)
    if not ref.complete:
        raise StudyError(f"the reference run ({ref.variant.label}) did not complete: {ref.message}")
    x_key, curve_keys = curves(varies)
    rows = []
    for r in runs:
        err = errors(r, ref) if r is not ref else {"tip": 0.0, "s": 0.0 if r.s is not None else math.nan, "energy": 0.0}
        if not r.complete:  # errors of a run that stopped early are not comparable
            err = {k: math.nan for k in err}
        rows.append({"run": r.variant.folder, **r.variant.sets, "complete": r.complete, "is_reference": r is ref,
                     **{f"error_{k}": v for k, v in err.items()}, "energy_drift": r.drift(), **r.cost(),
                     "message": r.message})
    has_s = any(r.s is not None for r in runs)
    quantities = ["tip"] + (["s"] if has_s else []) + ["energy"]
    orders = _orders(rows, varies, x_key, curve_keys, quantities)
    _write_csv(out / "study.csv", rows)
    (out / "study.md").write_text(_markdown(rows, varies, quantities, orders, ref, x_key))
    plot_keys = curve_by if curve_by else curve_keys
    pareto = bool(curve_by) and set(curve_by) != set(curve_keys)
    pngs = _plots(out, rows, plot_keys, quantities, orders, pareto, x_key)
    progress(f"study of {len(runs)} runs in {time.perf_counter() - started:.1f} s: reference {ref.variant.label}; "
             f"wrote {out / 'study.csv'}, {out / 'study.md'}, " + ", ".join(p.name for p in pngs))
    return {"rows": rows, "orders": orders, "reference": ref.variant.label, "x_key": x_key, "pngs": pngs}


def _curve_label(row: dict, curve_keys: list[str]) -> str:
    label = ", ".join(f"{k.split('&')[0].split('.')[-1]}={row[k.split('&')[0]]}" for k in curve_keys
                      if k.split('&')[0] in row) or "all"
    return label + ", adaptive" if ADAPT_KEY in row else label


def _rtol(row: dict) -> float:
    return float(row[ADAPT_KEY].strip("{}").partition("=")[2])


def _orders(rows, varies, x_key, curve_keys, quantities) -> dict[str, dict[str, float]]:
    """Observed order per curve and quantity, along the refinement key."""
    out: dict[str, dict[str, float]] = {}
    if x_key is None:
        return out
    first_x = x_key.split("&")[0]
    groups: dict[str, list[dict]] = {}
    for row in rows:
        groups.setdefault(_curve_label(row, curve_keys), []).append(row)
    for label, members in groups.items():
        members = [m for m in members if not m["is_reference"]]
        x = [_rtol(m) if ADAPT_KEY in m else float(m[first_x]) for m in members]
        out[label] = {q: observed_order(x, [m[f"error_{q}"] for m in members]) for q in quantities}
    return out


def _write_csv(path: Path, rows: list[dict]) -> None:
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=keys)
    w.writeheader()
    for r in rows:
        w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in r.items()})
    path.write_text(buf.getvalue())


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return "—" if math.isnan(v) else f"{v:.3g}"
    return str(v)


def _markdown(rows, varies, quantities, orders, ref, x_key) -> str:
    keys = [k for keys, _ in varies for k in keys[:1]] + ([ADAPT_KEY] if any(ADAPT_KEY in r for r in rows) else [])
    head = keys + [f"error {q}" for q in quantities] + ["energy drift", "wall [s]*", "steps", "Newton its",
                                                       "linear solves", "run"]
    lines = [f"Reference: {ref.variant.label}" + (" (finest run of the grid)" if ref.variant.index < len(rows) else ""),
             "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        cells = [str(r.get(k, "")) for k in keys] + [_fmt(r[f"error_{q}"]) for q in quantities]
        cells += [_fmt(r["energy_drift"]), _fmt(float(r["wall_time_s"])), str(r["steps"]), str(r["newton_iterations"]),
                  str(r["linear_solves"]), ("reference" if r["is_reference"] else r["message"])]
        lines.append("| " + " | ".join(cells) + " |")
    if orders:
        lines += ["", f"Observed orders along {x_key} (least-squares slope of log error; adaptive curves: "
                      "along rtol):", "",
                  "| curve | " + " | ".join(quantities) + " |", "|---|" + "---|" * len(quantities)]
        for label, qs in orders.items():
            lines.append(f"| {label} | " + " | ".join(_fmt(qs[q]) for q in quantities) + " |")
    lines += ["", "\\* wall time without the output phase (XDMF, CSV, checkpoints), from the run's PETSc log events."]
    return "\n".join(lines) + "\n"


def _plots(out: Path, rows, curve_keys, quantities, orders, pareto: bool = False, x_key: str | None = None) -> list[Path]:
    """One PNG per quantity. A curve joins its runs in order of cost; with pareto (curves that
    mix several varied keys) every run is a dot and the line is the curve's Pareto front: the
    runs no cheaper run beats in error."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = {"tip": "tip position error [m]", "s": "sliding coordinate error [m]",
             "energy": "energy error / max kinetic energy"}
    pngs = []
    for q in quantities:
        fig, ax = plt.subplots(figsize=(6.5, 4.8))
        groups: dict[str, list[dict]] = {}
        for row in rows:
            if not row["is_reference"]:
                groups.setdefault(_curve_label(row, curve_keys), []).append(row)
        for label, members in groups.items():
            pts = sorted((float(m["wall_time_s"]), m[f"error_{q}"]) for m in members
                         if math.isfinite(m[f"error_{q}"]) and m[f"error_{q}"] > 0)
            if not pts:
                continue
            if pareto:  # the range of the orders of the finer curves this one gathers
                parts = label.split(", ")
                found = [qs[q] for g, qs in orders.items() if all(p in g.split(", ") for p in parts)
                         and math.isfinite(qs[q])]
                axis = (x_key or "").split("&")[0].split(".")[-1]
                text = label + (f" (orders in {axis} {min(found):.2f}-{max(found):.2f})" if found else "")
            else:
                order = orders.get(label, {}).get(q, math.nan)
                text = label + (f" (order {order:.2f})" if math.isfinite(order) else "")
            if pareto:
                front, best = [], math.inf
                for p in pts:
                    if p[1] < best:
                        front.append(p)
                        best = p[1]
                line, = ax.loglog(*zip(*front), "-", label=text + ", Pareto front")
                ax.loglog(*zip(*pts), "o", color=line.get_color(), alpha=0.45, markersize=4)
            else:
                ax.loglog(*zip(*pts), "o-", label=text)
        ax.set_xlabel("wall time without output [s]")
        ax.set_ylabel(names[q])
        ax.set_title(f"work-precision: {q}")
        ax.grid(alpha=0.3, which="both")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
        fig.tight_layout()
        path = out / f"study_{q}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        pngs.append(path)
    return pngs


def main_study(args, petsc_args: list[str]) -> int:
    """`slidebeam study`: exit 0 when the study ran (runs may fail; the table says so), 2 on bad input."""
    path = Path(args.scene)
    varies = [parse_vary(v) for v in args.vary]
    reference = parse_assignments(args.reference, "--reference")
    sets = parse_assignments(args.set, "--set")
    jobs = args.jobs
    scene = path
    adapt = parse_tolerances(args.adapt, "--adapt") if args.adapt else []
    curve_by: list[str] | None = None
    if path.is_file() and "[study]" in path.read_text():
        spec = read_study_file(path)
        scene, varies = spec["scene"], spec["varies"] + varies
        reference = {**spec["reference"], **reference}
        sets = {**spec["sets"], **sets}
        jobs = args.jobs if args.jobs_given else spec["jobs"]
        curve_by = spec["curve_by"] or None
        adapt = spec["adapt"] + adapt
    if not scene.is_file():
        raise StudyError(f"scene {scene} does not exist")
    if not varies:
        raise StudyError("nothing to vary: give --vary key=v1,v2,... (or a study file)")
    out = Path(args.out) if args.out else Path("out") / f"study_{path.stem}"
    say = (lambda s: None) if args.quiet else (lambda s: print(s, flush=True))
    run_study(scene, varies, out, reference or None, sets, jobs, petsc_args, say, curve_by, adapt)
    return 0
