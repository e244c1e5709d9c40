# SPDX-License-Identifier: MIT
"""What an engineer asks of a run first: where the tracked points and the point masses go, the
tension along every beam, the reactions of supports and joints, the sliders' travel and speed, what
effects report (a contact's force and length in contact), and how hard the solver worked. Each ``*_figure`` takes opened run folders and returns a Figure; runs
given together are drawn over each other, one line style per run."""
from __future__ import annotations

import numpy as np

from ..output.rundata import Run
from .style import LINE_STYLES, blank_figure, finish, new_figure

MAX_PANELS = 12  # reactions and beams shown at most (the largest); the title says how many more


def _style(k: int) -> str:
    return LINE_STYLES[k % len(LINE_STYLES)]


def _run_label(runs: list[Run], k: int) -> str:
    labels = [r.label for r in runs]
    return labels[k] if labels.count(labels[k]) == 1 else f"{labels[k]} ({runs[k].folder.name})"


def _time_label(run: Run) -> str:
    return "t [s]" if run.dynamic else "load factor"


def _ok(run: Run) -> np.ndarray:
    return run.history["converged"] > 0


def _panels(count: int):
    """(figure, axes) of `count` panels over one time axis: one column up to two, else two."""
    cols = 1 if count <= 2 else 2
    rows = -(-count // cols)
    return new_figure(rows, cols, figsize=(7 * cols, 2.8 * rows + 0.6), squeeze=False, sharex=True)


def _finish_panels(fig, axes, runs: list[Run], shown: int, total: int, title: str):
    """Time labels, the unused panels hidden, and a title saying what was left out (`title`: what
    the shown ones are, e.g. "the 12 largest reactions")."""
    for a in axes[-1]:
        a.set_xlabel(_time_label(runs[0]))
    for a in list(axes.flat)[shown:]:
        a.set_visible(False)
    if total > shown:
        fig.suptitle(f"{title} ({total - shown} more not shown)")
    finish(axes)
    fig.tight_layout()
    return fig


# -- paths ---------------------------------------------------------------------------------------
def tracked_points(run: Run) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """name -> (times, positions (n, 3)): the history's tracked points (``<beam>@<s>``) and the
    point masses of the masses series."""
    out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    h, ok = run.history, _ok(run)
    for col in run.columns(".x"):
        name = col[:-2]
        if "@" in name and "[" not in name and f"{name}.y" in h and f"{name}.z" in h:
            out[name] = (h["t"][ok], np.column_stack([h[f"{name}.{c}"][ok] for c in "xyz"]))
    if run.masses is not None and len(run.masses.times):
        m = run.masses
        positions = np.stack([m.positions(r) for r in range(len(m.times))])
        for i, name in enumerate(m.names):
            out[f"mass {name}"] = (m.times, positions[:, i])
    return out


def paths_figure(runs: list[Run]):
    """Left: the points' x, y and z over time; right: their paths in the plane of the two
    coordinates that vary most (equal scales, start o, end x)."""
    fig = blank_figure((13, 8))
    grid = fig.add_gridspec(3, 2, width_ratios=(1.3, 1.0))
    comp = [fig.add_subplot(grid[i, 0]) for i in range(3)]
    plane = fig.add_subplot(grid[:, 1])
    points = [tracked_points(run) for run in runs]
    spread = np.zeros(3)
    for pts in points:
        for _, xyz in pts.values():
            spread = np.maximum(spread, np.ptp(xyz, axis=0) if len(xyz) else 0.0)
    i, j = sorted(np.argsort(spread)[-2:])
    colour = 0
    for k, (run, pts) in enumerate(zip(runs, points)):
        for name, (t, xyz) in pts.items():
            label = name if len(runs) == 1 else f"{name}, {_run_label(runs, k)}"
            c = f"C{colour % 10}"
            colour += 1
            for a, axis in zip(comp, range(3)):
                a.plot(t, xyz[:, axis], _style(k), color=c, label=label)
            plane.plot(xyz[:, i], xyz[:, j], _style(k), color=c, label=label)
            plane.plot(xyz[0, i], xyz[0, j], "o", color=c)
            plane.plot(xyz[-1, i], xyz[-1, j], "x", color=c)
    for a, axis in zip(comp, "xyz"):
        a.set_ylabel(f"{axis} [m]")
    comp[-1].set_xlabel(_time_label(runs[0]))
    comp[0].set_title("tracked points and point masses")
    plane.set_xlabel(f"{'xyz'[i]} [m]")
    plane.set_ylabel(f"{'xyz'[j]} [m]")
    plane.set_aspect("equal", adjustable="datalim")
    plane.set_title(f"paths in the {'xyz'[i]}-{'xyz'[j]} plane (o start, x end)")
    plane.legend(fontsize=8)
    finish([*comp, plane])
    fig.tight_layout()
    return fig


# -- tension -------------------------------------------------------------------------------------
def tension_map(run: Run) -> tuple[np.ndarray, dict[str, tuple[np.ndarray, np.ndarray]]]:
    """Times and, per beam name, (arc length, tension (times, points)) from the beams series."""
    b = run.beams
    assert b is not None
    tension = b.field_over_time("tension")
    ids, s = b.constants["beam_id"], b.constants["s"]
    return b.times, {name: (s[ids == k], tension[:, ids == k]) for k, name in enumerate(b.names)}


def tension_figure(runs: list[Run]):
    """Per beam (the ones with the largest peak tension first, at most MAX_PANELS over all runs)
    a colour map of the tension over arc length and time; a diverging map where it changes sign."""
    maps = []
    for k, run in enumerate(runs):
        t, beams = tension_map(run)
        for name, (s, T) in beams.items():
            title = name if len(runs) == 1 else f"{name}, {_run_label(runs, k)}"
            maps.append((float(np.abs(T).max()) if T.size else 0.0, title, t, s, T, run))
    maps.sort(key=lambda m: -m[0])
    shown, hidden = maps[:MAX_PANELS], len(maps) - MAX_PANELS
    cols = 1 if len(shown) <= 3 else 2
    rows = -(-len(shown) // cols)
    fig, axes = new_figure(rows, cols, figsize=(7 * cols, 2.8 * rows + 0.6), squeeze=False)
    for a, (_, title, t, s, T, run) in zip(axes.flat, shown):
        lo, hi = float(T.min()), float(T.max())
        if lo < 0.0 < hi and -lo > 0.01 * hi:  # compression worth seeing: white at zero
            bound = max(-lo, hi)
            image = a.pcolormesh(t, s, T.T, shading="nearest", cmap="RdBu_r", vmin=-bound, vmax=bound)
        else:
            image = a.pcolormesh(t, s, T.T, shading="nearest", cmap="viridis")
        fig.colorbar(image, ax=a, label="tension [N]")
        peak = np.unravel_index(np.argmax(T), T.shape)
        a.set_title(f"{title}: largest {T.max():.4g} N at t = {t[peak[0]]:.3g}, s = {s[peak[1]]:.3g} m",
                    fontsize=9)
        a.set_xlabel(_time_label(run))
        a.set_ylabel("s [m]")
    for a in list(axes.flat)[len(shown):]:
        a.set_visible(False)
    if hidden > 0:
        fig.suptitle(f"the {len(shown)} beams with the largest tension ({hidden} more not shown)")
    fig.tight_layout()
    return fig


# -- reactions -----------------------------------------------------------------------------------
def reactions(run: Run) -> dict[str, dict[str, np.ndarray]]:
    """Effect or joint -> {"force": (n, 3)[, "moment": (n, 3)]} over the converged records."""
    h, ok = run.history, _ok(run)
    out: dict[str, dict[str, np.ndarray]] = {}
    for col in run.columns(".fx"):
        name = col[:-3]
        out[name] = {"force": np.column_stack([h[f"{name}.f{c}"][ok] for c in "xyz"])}
        if f"{name}.mx" in h:
            out[name]["moment"] = np.column_stack([h[f"{name}.m{c}"][ok] for c in "xyz"])
    for col in run.columns(".reaction.x"):
        name = col[: -len(".reaction.x")]
        out[f"sliding joint {name}"] = {"force": np.column_stack([h[f"{name}.reaction.{c}"][ok] for c in "xyz"])}
    return out


def reactions_figure(runs: list[Run]):
    """One panel per support and joint (the largest first): the force's components and its
    magnitude, moments dashed on a second axis where the support holds one."""
    panels: dict[str, list[tuple[int, np.ndarray, dict[str, np.ndarray]]]] = {}
    for k, run in enumerate(runs):
        t = run.history["t"][_ok(run)]
        for name, r in reactions(run).items():
            panels.setdefault(name, []).append((k, t, r))
    order = sorted(panels, key=lambda n: -max(float(np.abs(r["force"]).max(initial=0.0)) for _, _, r in panels[n]))
    shown = order[:MAX_PANELS]
    fig, axes = _panels(len(shown))
    for a, name in zip(axes.flat, shown):
        moment_axis = None
        for k, t, r in panels[name]:
            suffix = "" if len(runs) == 1 else f", {_run_label(runs, k)}"
            F = r["force"]
            for c, axis in enumerate("xyz"):
                a.plot(t, F[:, c], _style(k), color=f"C{c}", label=f"F{axis}{suffix}")
            a.plot(t, np.linalg.norm(F, axis=1), _style(k), color="k", lw=1.6, label=f"|F|{suffix}")
            if "moment" in r:
                moment_axis = moment_axis or a.twinx()
                for c, axis in enumerate("xyz"):
                    moment_axis.plot(t, r["moment"][:, c], ":", color=f"C{c + 3}", label=f"M{axis}{suffix}")
        a.set_title(name, fontsize=9)
        a.set_ylabel("force [N]")
        a.legend(fontsize=7, loc="upper left", ncol=2)
        if moment_axis is not None:
            moment_axis.set_ylabel("moment [N m]")
            moment_axis.legend(fontsize=7, loc="upper right")
    return _finish_panels(fig, axes, runs, len(shown), len(order), f"the {len(shown)} largest reactions")


# -- sliders -------------------------------------------------------------------------------------
def sliders_figure(runs: list[Run]):
    """Every sliding joint's position s on its carrier and its speed ds/dt over time, and every
    guide's s on its rope (the rope running through it)."""
    fig, (pos, speed) = new_figure(2, 1, figsize=(11, 7), sharex=True)
    colour = 0
    for k, run in enumerate(runs):
        h, ok = run.history, _ok(run)
        for col in run.columns(".ds_dt"):
            name = col[: -len(".ds_dt")]
            label = name if len(runs) == 1 else f"{name}, {_run_label(runs, k)}"
            c = f"C{colour % 10}"
            colour += 1
            pos.plot(h["t"][ok], h[f"{name}.s"][ok], _style(k), color=c, label=label)
            speed.plot(h["t"][ok], h[col][ok], _style(k), color=c, label=label)
    pos.set_ylabel("s on the carrier (rope) [m]")
    speed.set_ylabel("ds/dt [m/s]")
    speed.set_xlabel(_time_label(runs[0]))
    pos.set_title("sliding joints and guides" if any(run.columns(".point.x") for run in runs) else "sliding joints")
    pos.legend(fontsize=8)
    finish([pos, speed])
    fig.tight_layout()
    return fig


# -- effects' outputs ----------------------------------------------------------------------------
def outputs(run: Run) -> dict[str, dict[str, np.ndarray]]:
    """Effect -> {name: values over the converged records} of the values effects report
    (summary.json's ``outputs`` names them; history.csv has them as <effect>.<name>); a vector's
    <name>.x/.y/.z as one (n, 3) array under <name>."""
    h, ok = run.history, _ok(run)
    out: dict[str, dict[str, np.ndarray]] = {}
    for label, names in run.summary.get("outputs", {}).items():
        if "ds_dt" in names:  # a sliding joint's: the sliders and reactions figures draw them
            continue
        values: dict[str, np.ndarray] = {}
        for name in names:
            if f"{label}.{name}" not in h:
                continue
            base, _, axis = name.rpartition(".")
            if axis in ("x", "y", "z") and all(f"{label}.{base}.{c}" in h for c in "xyz"):
                if base not in values:
                    values[base] = np.column_stack([h[f"{label}.{base}.{c}"][ok] for c in "xyz"])
            else:
                values[name] = h[f"{label}.{name}"][ok]
        if values:
            out[label] = values
    return out


_UNITS = {"force": "N", "length": "m"}  # of the names effects report (others: as named)


def _axis_label(name: str) -> str:
    return f"{name} [{_UNITS[name]}]" if name in _UNITS else name


def outputs_figure(runs: list[Run]):
    """One panel per effect that reports values: vectors as their components and magnitude,
    numbers dashed on a second axis (a contact: the shape's force on the beam, and the length
    in contact)."""
    panels: dict[str, list[tuple[int, np.ndarray, dict[str, np.ndarray]]]] = {}
    for k, run in enumerate(runs):
        t = run.history["t"][_ok(run)]
        for label, values in outputs(run).items():
            panels.setdefault(label, []).append((k, t, values))
    shown = list(panels)[:MAX_PANELS]
    fig, axes = _panels(len(shown))
    for a, label in zip(axes.flat, shown):
        second = None
        for k, t, values in panels[label]:
            suffix = "" if len(runs) == 1 else f", {_run_label(runs, k)}"
            for name, v in values.items():
                if v.ndim == 2:
                    for c, axis in enumerate("xyz"):
                        a.plot(t, v[:, c], _style(k), color=f"C{c}", label=f"{name}.{axis}{suffix}")
                    a.plot(t, np.linalg.norm(v, axis=1), _style(k), color="k", lw=1.6, label=f"|{name}|{suffix}")
                    a.set_ylabel(_axis_label(name))
                else:
                    second = second or a.twinx()
                    second.plot(t, v, ":", color="C3", lw=1.6, label=f"{name}{suffix}")
                    second.set_ylabel(_axis_label(name))
        a.set_title(label, fontsize=9)
        a.legend(fontsize=7, loc="upper left", ncol=2)
        if second is not None:
            second.legend(fontsize=7, loc="upper right")
    return _finish_panels(fig, axes, runs, len(shown), len(panels), f"the first {len(shown)} effects")


# -- solver --------------------------------------------------------------------------------------
def solver_figure(runs: list[Run]):
    """Newton iterations per recorded step, the step size, rejected steps (failed attempts,
    cumulative) and the final residual norm of each step."""
    fig, axes = new_figure(2, 2, figsize=(12, 7), sharex=True)
    (its, dt), (rej, res) = axes
    for k, run in enumerate(runs):
        h, label, style = run.history, _run_label(runs, k), _style(k)
        stepped = h["step"] > 0 if "step" in h else np.ones(len(h["t"]), bool)  # not the initial state
        t, ok = h["t"][stepped], _ok(run)[stepped]
        iterations = h["newton_iterations"][stepped]
        its.plot(t, iterations, style, color=f"C{k}", drawstyle="steps-post", label=label)
        if not ok.all():
            its.plot(t[~ok], iterations[~ok], "rx", label=f"not converged ({label})")
        if "dt" in h:
            dt.semilogy(t, h["dt"][stepped], style, color=f"C{k}", drawstyle="steps-post", label=label)
        if "rejected_steps" in h:
            rej.plot(t, np.cumsum(h["rejected_steps"][stepped]), style, color=f"C{k}", drawstyle="steps-post",
                     label=label)
        res.semilogy(t, np.maximum(h["residual_norm"][stepped], 1e-300), style, color=f"C{k}", label=label)
    from matplotlib.ticker import MaxNLocator

    for a in (its, rej):
        a.yaxis.set_major_locator(MaxNLocator(integer=True))
    its.set_title("Newton iterations per recorded step")
    dt.set_title("step size [s]")
    rej.set_title("rejected steps (retried smaller), cumulative")
    res.set_title("residual norm at the end of the step")
    for a in axes[1]:
        a.set_xlabel(_time_label(runs[0]))
    its.legend(fontsize=8)
    finish(axes)
    fig.tight_layout()
    return fig
