# SPDX-License-Identifier: MIT
"""Energy and momentum over time for one or more run folders (history.csv of dynamic runs)."""
from __future__ import annotations

import numpy as np

from ..output.rundata import Run, RunFolderError
from .style import LINE_STYLES, finish, new_figure


def _label(run: Run) -> str:
    s = run.summary
    if not s:
        return run.folder.name
    text = s.get("integrator") or s.get("scene", run.folder.name)
    return text if s.get("complete", True) else f"{text} (stopped at t = {s.get('t_reached', float('nan')):.3g})"


def energy_figure(runs: list[Run], drift: bool = False):
    """Four panels: total energy, the energy balance's error |H - H0 - W + D| relative to the
    largest energy of the run (histories without it: the energy change per record), linear
    momentum and angular momentum (all components; drift: their relative change from the start
    on a log scale), one line style per run. Runs with the same label (integrator) are told
    apart by their folder's name."""
    fig, ax = new_figure(2, 2, figsize=(12, 8), sharex=True)
    typical = []
    labels = [_label(run) for run in runs]
    for k, run in enumerate(runs):
        h = run.history
        if "total_energy" not in h:
            raise RunFolderError(f"{run.folder}: history.csv has no total_energy column (not a dynamic run)")
        t, H = h["t"], h["total_energy"]
        ok = h["converged"] > 0
        t, H = t[ok], H[ok]
        label = labels[k] if labels.count(labels[k]) == 1 else f"{labels[k]} ({run.folder.name})"
        color = f"C{k}"
        ax[0, 0].plot(t, H, color=color, label=label)
        first_half = H[: max(2, len(H) // 2)]
        typical.append((first_half.min(), first_half.max()))
        scale = max(np.abs(h["kinetic_energy"][ok]).max(), np.abs(H).max(), 1e-300)
        if "energy_balance_error" in h:  # |H - H0 - W + D|: closes under energy-momentum with work and damping
            ax[0, 1].semilogy(t, np.maximum(h["energy_balance_error"][ok] / scale, 1e-17), color=color, label=label)
        else:
            ax[0, 1].semilogy(t[1:], np.maximum(np.abs(np.diff(H)) / scale, 1e-17), color=color, label=label)
        if drift:
            for a, name in ((ax[1, 0], "linear_momentum"), (ax[1, 1], "angular_momentum")):
                m = np.stack([h[f"{name}.{c}"][ok] for c in "xyz"], axis=1)
                rel = np.linalg.norm(m - m[0], axis=1) / max(np.linalg.norm(m[0]), 1e-300)
                # (runs that keep a momentum equally well would hide each other in one style)
                a.semilogy(t[1:], np.maximum(rel[1:], 1e-17), LINE_STYLES[k % len(LINE_STYLES)], color=color, label=label)
            continue
        for c, style in zip("xyz", ("-", "--", ":")):
            ax[1, 0].plot(t, h[f"linear_momentum.{c}"][ok], style, color=color, label=f"{label} L{c}")
            ax[1, 1].plot(t, h[f"angular_momentum.{c}"][ok], style, color=color, label=f"{label} J{c}")
    if typical:  # a run that blew up must not flatten the others
        lo, hi = min(a for a, _ in typical), max(b for _, b in typical)
        pad = 0.25 * (hi - lo) + 1e-12 * max(abs(lo), abs(hi), 1.0)
        ax[0, 0].set_ylim(lo - pad, hi + pad)
    ax[0, 0].set_title("total energy T + U + V")
    ax[0, 1].set_title("energy balance |H - H0 - W + D| / max energy")
    if drift:
        ax[1, 0].set_title("linear momentum |L(t) - L(0)| / |L(0)|")
        ax[1, 1].set_title("angular momentum |J(t) - J(0)| / |J(0)| (about the origin)")
    else:
        ax[1, 0].set_title("linear momentum")
        ax[1, 1].set_title("angular momentum (about the origin)")
    finish(ax)
    for a in ax[1]:
        a.set_xlabel("t")
    ax[0, 0].legend(fontsize=8)
    ax[1, 1].legend(fontsize=7, ncol=1 if drift else 2)
    fig.tight_layout()
    return fig
