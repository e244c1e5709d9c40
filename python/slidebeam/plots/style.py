# SPDX-License-Identifier: MIT
"""Figures without pyplot's global state: a Figure on the Agg canvas, saved by suffix."""
from __future__ import annotations

from pathlib import Path
from typing import Any

FORMATS = ("png", "pdf")
LINE_STYLES = ("-", "--", "-.", ":")


def new_figure(rows: int = 1, cols: int = 1, **kwargs: Any):
    """A Figure (Agg) and its axes, as ``plt.subplots`` returns them."""
    from matplotlib.figure import Figure

    figsize = kwargs.pop("figsize", (12, 8))
    fig = Figure(figsize=figsize)
    return fig, fig.subplots(rows, cols, squeeze=kwargs.pop("squeeze", True), **kwargs)


def blank_figure(figsize: tuple[float, float] = (12, 8)):
    """A Figure (Agg) without axes, for layouts of its own (gridspec)."""
    from matplotlib.figure import Figure

    return Figure(figsize=figsize)


def save(fig, path: Path, dpi: int = 110) -> Path:
    """Write ``fig`` to ``path`` (PNG or PDF by its suffix), creating the folder."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path


def finish(axes) -> None:
    """A light grid on every axis."""
    import numpy as np

    for a in np.atleast_1d(np.asarray(axes, dtype=object)).flat:
        a.grid(True, alpha=0.3)
