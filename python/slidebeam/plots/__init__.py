# SPDX-License-Identifier: MIT
"""Plots of run folders (matplotlib, no display needed), as ``slidebeam plot`` draws them.

Kinds (``KINDS``): ``energy`` (energy, energy balance, momenta), ``paths`` (tracked points and
point masses), ``tension`` (along every beam over time), ``reactions`` (supports and joints),
``sliders`` (sliding joints' s and speed), ``outputs`` (what effects report: a contact's force and
length in contact) and ``solver`` (Newton iterations, step size, rejected steps, residuals). ``available`` says which a run has data for; ``plot`` draws them to files::

    from slidebeam import plots
    plots.plot(["out/ropeway"], what=["tension", "reactions"], out="figures/")   # figures/tension.png, ...
    fig = plots.figure("paths", ["out/ropeway"])                                  # a matplotlib Figure
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from ..output.rundata import Run, RunFolderError, open_run
from . import engineering
from .energy import energy_figure
from .style import FORMATS, save

KINDS = ("energy", "paths", "tension", "reactions", "sliders", "outputs", "solver")

_HAS: dict[str, Callable[[Run], bool]] = {
    "energy": lambda r: r.dynamic,
    "paths": lambda r: bool(engineering.tracked_points(r)),
    "tension": lambda r: r.beams is not None and "tension" in r.beams.fields and len(r.beams.times) > 1,
    "reactions": lambda r: bool(r.columns(".fx") or r.columns(".reaction.x")),
    "sliders": lambda r: bool(r.columns(".ds_dt")),
    "outputs": lambda r: bool(engineering.outputs(r)),
    "solver": lambda r: "newton_iterations" in r.history,
}
_WHY_NOT = {
    "energy": "a static run has no energy history",
    "paths": "the run tracks no point ([output] track) and has no point masses in its XDMF",
    "tension": "the run wrote no beams.xdmf with more than one record ([output] xdmf)",
    "reactions": "the scene has no supports or joints with reactions",
    "sliders": "the scene has no sliding joints",
    "outputs": "no effect of the scene reports values (contact, buoyancy do)",
    "solver": "history.csv has no newton_iterations column",
}


def available(run: Run) -> list[str]:
    """The kinds of plot ``run`` has data for, in ``KINDS`` order."""
    return [k for k in KINDS if _HAS[k](run)]


def parse_kinds(text: str) -> list[str]:
    """``"tension,reactions"`` -> the kinds; ``all`` -> every kind. Unknown names: ValueError."""
    kinds = [k.strip() for k in text.split(",") if k.strip()]
    if kinds == ["all"]:
        return list(KINDS)
    unknown = [k for k in kinds if k not in KINDS]
    if unknown or not kinds:
        raise ValueError(f"unknown plot {', '.join(repr(k) for k in unknown) or repr(text)}: "
                         f"expected a comma-separated list of {', '.join(KINDS)} (or all)")
    return kinds


def figure(kind: str, runs: Sequence[str | Path | Run], drift: bool = False):
    """The Figure of one kind for one or more runs (folders or opened runs)."""
    opened = [r if isinstance(r, Run) else open_run(r) for r in runs]
    missing = [r.folder for r in opened if not _HAS[kind](r)]
    if missing:
        raise RunFolderError(f"no {kind} plot for {', '.join(map(str, missing))}: {_WHY_NOT[kind]}")
    if kind == "energy":
        return energy_figure(opened, drift=drift)
    return getattr(engineering, f"{kind}_figure")(opened)


def plot(runs: Sequence[str | Path], what: Sequence[str] | None = None, out: str | Path | None = None,
         fmt: str = "png", drift: bool = False) -> list[Path]:
    """Draw the kinds ``what`` (default: every kind the runs have) and return the files written.

    ``out``: a folder (one ``<kind>.<fmt>`` each; default ``<first run>/plots``), a ``.png`` file
    (one kind: ``energy`` unless ``what`` names another) or a ``.pdf`` file (one page per kind)."""
    if fmt not in FORMATS:
        raise ValueError(f"unknown format {fmt!r}: expected one of {', '.join(FORMATS)}")
    opened = [open_run(r) for r in runs]
    try:
        target = Path(out) if out is not None else opened[0].folder / "plots"
        if what:
            kinds = list(what)
        elif target.suffix == ".png":
            kinds = ["energy"]
        else:
            kinds = [k for k in KINDS if all(_HAS[k](r) for r in opened)]
        if not kinds:
            raise RunFolderError("these runs have no plot in common")
        if target.suffix == ".pdf":
            return [_pdf(kinds, opened, target, drift)]
        if target.suffix:
            if target.suffix != ".png":
                raise ValueError(f"--out {target}: expected a folder, a .png or a .pdf file")
            if len(kinds) != 1:
                raise ValueError(f"--out {target} holds one plot, but {len(kinds)} were asked for "
                                 f"({', '.join(kinds)}): choose one with --what, or give a folder or a .pdf")
            return [save(figure(kinds[0], opened, drift), target)]
        return [save(figure(k, opened, drift), target / f"{k}.{fmt}") for k in kinds]
    finally:
        for r in opened:
            r.close()


def _pdf(kinds: list[str], runs: list[Run], path: Path, drift: bool) -> Path:
    from matplotlib.backends.backend_pdf import PdfPages

    path.parent.mkdir(parents=True, exist_ok=True)
    with PdfPages(path) as pdf:
        for k in kinds:
            pdf.savefig(figure(k, runs, drift))
    return path


def plot_energy_momentum(run_dirs: Sequence[str | Path], out_png: str | Path, drift: bool = False) -> Path:
    """The energy plot of ``run_dirs`` as one PNG (``slidebeam plot RUN... --what energy``)."""
    return save(figure("energy", run_dirs, drift), Path(out_png))


__all__ = ["KINDS", "available", "figure", "parse_kinds", "plot", "plot_energy_momentum"]
