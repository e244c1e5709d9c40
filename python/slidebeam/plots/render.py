# SPDX-License-Identifier: MIT
"""Pictures and animations of a run's deformed structure without a display (matplotlib's Agg
canvas): beams as lines coloured by a field, point masses as squares (rigid bodies too, with their
axes as red, green and blue segments), sliders and guides as circles, from a
camera fixed by the structure's extent over the whole run, so frames and pictures at several
times line up.

Why matplotlib and not VTK/ParaView: Debian's ParaView renders only on an X display (offscreen it
needs ``xvfb-run``), while matplotlib is already a dependency and draws a 10^4-unknown net in a
fraction of a second per frame (docs/user-guide.md, "Pictures and animations"). Beams are drawn
as lines of a fixed width on screen rather than tubes at their true section: a rope's diameter is
a thousandth of the structure's size and would not show.

From Python::

    from slidebeam.plots import render
    render.pictures("out/ropeway", times=[0.0, 3.0], out="ropeway.png", view="front")
    render.animation("out/ropeway", out="ropeway.gif")
"""
from __future__ import annotations

import argparse
import shutil
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..output.rundata import Run, RunFolderError, open_run

VIEWS = {"iso": (25.0, -60.0), "front": (0.0, -90.0), "side": (0.0, 0.0), "top": (90.0, -90.0)}
FIELDS = ("tension", "velocity", "displacement", "s", "none")
MAX_FRAMES = 600  # an animation's frames by default at most (evenly over the run)
BEAM_COLOUR = "#1f77b4"  # beams without a field
MASS_COLOUR = "#222222"
SLIDER_COLOUR = "#d62728"
AXIS_COLOURS = ("#d62728", "#2ca02c", "#1f77b4")  # a body's d1, d2, d3 (red, green, blue)


def parse_view(text: str) -> tuple[float, float]:
    """``iso``/``front``/``side``/``top`` or ``ELEVATION,AZIMUTH`` (degrees)."""
    if text in VIEWS:
        return VIEWS[text]
    try:
        elevation, azimuth = (float(v) for v in text.split(","))
    except ValueError:
        raise ValueError(f"--view {text!r}: expected one of {', '.join(VIEWS)} or ELEVATION,AZIMUTH in degrees") from None
    return elevation, azimuth


def parse_size(text: str) -> tuple[int, int]:
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"--size {text!r}: expected WIDTHxHEIGHT in pixels, e.g. 1280x720") from None
    if not (64 <= width <= 8192 and 64 <= height <= 8192):
        raise ValueError(f"--size {text!r}: width and height must be 64 to 8192 pixels")
    return width, height


@dataclass
class Frame:
    """What one picture shows: the time, every beam cell's end points and colour value, and the
    point masses' and sliders' positions."""

    t: float
    segments: np.ndarray  # (cells, 2, 3)
    values: np.ndarray | None  # (cells,) or None (one colour)
    masses: np.ndarray  # (n, 3)
    sliders: np.ndarray  # (n, 3)
    axes: np.ndarray  # (3, bodies, 2, 3): each body's d1, d2, d3 as a segment from its centre


class Renderer:
    """One figure for a run, redrawn per record: the camera and the colour scale are fixed over
    the whole run (``records`` limits what is read to set them)."""

    def __init__(self, run: Run, view: str = "iso", field: str = "tension", size: tuple[int, int] = (1280, 720),
                 records: Sequence[int] | None = None) -> None:
        if run.beams is None:
            raise RunFolderError(f"{run.folder} has no beams.xdmf (the run wrote no XDMF: [output] xdmf)")
        if field not in FIELDS:
            raise ValueError(f"--field {field!r}: expected one of {', '.join(FIELDS)}")
        if field != "none" and field not in (*run.beams.fields, "s"):
            raise ValueError(f"--field {field!r}: {run.beams.path.name} has no such field")
        self.run, self.field = run, field
        self.elevation, self.azimuth = parse_view(view)
        beams = run.beams
        self.records = list(range(len(beams.times))) if records is None else list(records)
        if not self.records:
            raise RunFolderError(f"{beams.path} has no records")
        self.cells = beams.cells
        self._build(size)

    # -- data ----------------------------------------------------------------------------------
    def _values(self, record: int) -> np.ndarray | None:
        b = self.run.beams
        assert b is not None
        if self.field == "none":
            return None
        if self.field == "s":
            point = b.constants["s"]
        else:
            point = b.field(self.field, record)
            point = np.linalg.norm(point, axis=1) if point.ndim == 2 else point
        return 0.5 * (point[self.cells[:, 0]] + point[self.cells[:, 1]])

    def frame(self, record: int) -> Frame:
        b = self.run.beams
        assert b is not None
        x = b.positions(record)
        t = float(b.times[record])
        # bodies are drawn at their centres of mass, as point masses are, with their axes
        centres = self._at(self.run.bodies, t)
        masses = np.concatenate([self._at(self.run.masses, t), centres])
        sliders = np.concatenate([self._at(self.run.sliders, t), self._at(self.run.guides, t)])  # guides alike
        return Frame(t, x[self.cells], self._values(record), masses, sliders, self._body_axes(t, centres))

    def _body_axes(self, t: float, centres: np.ndarray) -> np.ndarray:
        axes = np.zeros((3, len(centres), 2, 3))
        if not len(centres):
            return axes
        bodies = self.run.bodies
        assert bodies is not None
        record = int(np.argmin(np.abs(bodies.times - t)))
        for k in range(3):
            axes[k, :, 0] = centres
            axes[k, :, 1] = centres + self.axis_length * bodies.field(f"d{k + 1}", record)
        return axes

    @staticmethod
    def _at(series, t: float) -> np.ndarray:
        if series is None or not len(series.times):
            return np.empty((0, 3))
        return series.positions(int(np.argmin(np.abs(series.times - t))))

    def _sampled_records(self) -> list[int]:
        """The records the camera and the colour scale are set from: all, or 200 evenly over the run."""
        if len(self.records) <= 200:
            return self.records
        return [self.records[i] for i in np.linspace(0, len(self.records) - 1, 200).astype(int)]

    def _extent(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounding box of every beam point over the sampled records."""
        b = self.run.beams
        assert b is not None
        lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
        for r in self._sampled_records():
            x = b.positions(r)
            lo, hi = np.minimum(lo, x.min(axis=0)), np.maximum(hi, x.max(axis=0))
        return lo, hi

    def _colour_range(self) -> tuple[float, float]:
        values = [self._values(r) for r in self._sampled_records()]
        lo = min(float(v.min()) for v in values if v is not None)
        hi = max(float(v.max()) for v in values if v is not None)
        return (lo, hi) if hi > lo else (lo - 0.5 * abs(lo) - 1e-12, hi + 0.5 * abs(hi) + 1e-12)

    # -- drawing -------------------------------------------------------------------------------
    def _build(self, size: tuple[int, int]) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.colors import Normalize
        from matplotlib.figure import Figure
        from mpl_toolkits.mplot3d.art3d import Line3DCollection

        dpi = 100
        self.fig = Figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi)
        FigureCanvasAgg(self.fig)
        coloured = self.field != "none"
        ax = self.fig.add_axes((0.0, 0.0, 0.88 if coloured else 1.0, 0.95), projection="3d", computed_zorder=False)
        self.ax = ax
        lo, hi = self._extent()
        centre, span = 0.5 * (lo + hi), hi - lo
        side = max(float(span.max()), 1e-9)
        span = np.maximum(span, 0.15 * side)  # a flat structure keeps a visible depth
        half = 0.5 * span * 1.04
        self.axis_length = 0.06 * side  # a body's axes as drawn
        ax.set_xlim(centre[0] - half[0], centre[0] + half[0])
        ax.set_ylim(centre[1] - half[1], centre[1] + half[1])
        ax.set_zlim(centre[2] - half[2], centre[2] + half[2])
        # equal scales on every axis; a box taller than wide overhangs the axes in the oblique views
        ax.set_box_aspect(tuple(span), zoom=1.1 if span[2] <= max(span[0], span[1]) else 0.8)
        ax.view_init(elev=self.elevation, azim=self.azimuth)
        from matplotlib.ticker import MaxNLocator

        for axis, name in zip((ax.xaxis, ax.yaxis, ax.zaxis), "xyz"):
            axis.set_major_locator(MaxNLocator(6 if axis is ax.xaxis else 4))
            axis.set_label_text(f"{name} [m]")
            axis.labelpad = 12
        for pane in (ax.xaxis, ax.yaxis, ax.zaxis):
            pane.set_pane_color((1.0, 1.0, 1.0, 0.0))
        along_view = {(0.0, -90.0): ax.yaxis, (0.0, 0.0): ax.xaxis, (90.0, -90.0): ax.zaxis}
        if (self.elevation, self.azimuth) in along_view:  # seen end-on: its ticks would pile up
            hidden = along_view[(self.elevation, self.azimuth)]
            hidden.set_ticks([])
            hidden.set_label_text("")
        first = self.frame(self.records[0])
        self.segments = first.segments  # as drawn (the collection keeps only their projection)
        self.lines = Line3DCollection(first.segments, linewidths=max(1.5, size[0] / 550), capstyle="round")
        if first.values is not None:
            self.lines.set_cmap("viridis")
            self.lines.set_norm(Normalize(*self._colour_range()))
            self.lines.set_array(first.values)
            unit = {"tension": "N", "velocity": "m/s", "displacement": "m", "s": "m"}[self.field]
            self.fig.colorbar(self.lines, cax=self.fig.add_axes((0.88, 0.2, 0.015, 0.6)), label=f"{self.field} [{unit}]")
        else:
            self.lines.set_color(BEAM_COLOUR)
        ax.add_collection3d(self.lines)
        self.masses = ax.scatter(*first.masses.T, marker="s", s=40, color=MASS_COLOUR, depthshade=False, zorder=3)
        self.sliders = ax.scatter(*first.sliders.T, marker="o", s=30, color=SLIDER_COLOUR, depthshade=False,
                                  zorder=4)
        self.axes = [Line3DCollection(first.axes[k], colors=colour, linewidths=2.0, zorder=4)
                     for k, colour in enumerate(AXIS_COLOURS)]
        for collection in self.axes:
            ax.add_collection3d(collection)
        for artist in (self.lines, self.masses, self.sliders, *self.axes):
            # the axes clip to their 2-D box, which the zoomed 3-D box overhangs in the axis-aligned
            # views; the limits hold every record, so nothing would be drawn outside the 3-D box
            artist.set_clip_on(False)
        self.title = ax.set_title("")

    def draw(self, record: int) -> None:
        f = self.frame(record)
        self.segments = f.segments
        self.lines.set_segments(f.segments)
        if f.values is not None:
            self.lines.set_array(f.values)
        self.masses._offsets3d = tuple(f.masses.T)
        self.sliders._offsets3d = tuple(f.sliders.T)
        for collection, segments in zip(self.axes, f.axes):
            collection.set_segments(segments)
        self.title.set_text(f"{self.run.label}   t = {f.t:.4g} s")

    def projected_box(self) -> tuple[float, float, float, float]:
        """Pixel box (x0, y0, x1, y1; origin bottom left) of the beams' points as drawn now:
        for tests that check a picture shows the structure where it is."""
        from mpl_toolkits.mplot3d import proj3d

        self.fig.canvas.draw()  # the projection is set up at draw time
        xyz = self.segments.reshape(-1, 3)
        x, y, _ = proj3d.proj_transform(xyz[:, 0], xyz[:, 1], xyz[:, 2], self.ax.get_proj())
        px = self.ax.transData.transform(np.column_stack([x, y]))
        return float(px[:, 0].min()), float(px[:, 1].min()), float(px[:, 0].max()), float(px[:, 1].max())


def nearest_records(run: Run, times: Sequence[float]) -> list[int]:
    assert run.beams is not None
    recorded = run.beams.times
    return [int(np.argmin(np.abs(recorded - t))) for t in times]


def pictures(run_dir: str | Path, times: Sequence[float] | None = None, out: str | Path | None = None,
             view: str = "iso", field: str = "tension", size: tuple[int, int] = (1280, 720)) -> list[Path]:
    """The structure at ``times`` (nearest records; default the last one). ``out``: a .png (one
    file per time, ``<stem>_t<time>.png`` when there are several) or a .pdf (one page each)."""
    run = open_run(run_dir)
    try:
        out = Path(out) if out is not None else run.folder / "render.png"
        if out.suffix not in (".png", ".pdf"):
            raise ValueError(f"--out {out}: a picture is a .png or .pdf (an animation a .gif or .mp4)")
        if run.beams is None or not len(run.beams.times):
            raise RunFolderError(f"{run.folder} has no beams.xdmf with records (the run wrote no XDMF)")
        records = nearest_records(run, times) if times else [len(run.beams.times) - 1]
        renderer = Renderer(run, view, field, size)
        out.parent.mkdir(parents=True, exist_ok=True)
        if out.suffix == ".pdf":
            from matplotlib.backends.backend_pdf import PdfPages

            with PdfPages(out) as pdf:
                for r in records:
                    renderer.draw(r)
                    pdf.savefig(renderer.fig)
            return [out]
        files = []
        for r in records:
            renderer.draw(r)
            name = out if len(records) == 1 else out.with_name(f"{out.stem}_t{run.beams.times[r]:g}{out.suffix}")
            renderer.fig.savefig(name)
            files.append(name)
        return files
    finally:
        run.close()


def animation(run_dir: str | Path, out: str | Path, view: str = "iso", field: str = "tension",
              size: tuple[int, int] = (1280, 720), fps: float = 20.0, frames: int | None = None,
              progress: Callable[[str], None] | None = None) -> Path:
    """The whole run as a GIF (Pillow) or MP4 (ffmpeg): every record, or ``frames`` evenly over
    the run (at most MAX_FRAMES by default)."""
    from matplotlib import animation as anim

    out = Path(out)
    if out.suffix == ".gif":
        writer = anim.PillowWriter(fps=fps)
    elif out.suffix == ".mp4":
        if shutil.which("ffmpeg") is None:
            raise RunFolderError("an .mp4 needs ffmpeg, which is not installed (apt-get install ffmpeg); "
                                 "a .gif needs nothing more")
        writer = anim.FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])
    else:
        raise ValueError(f"--out {out}: an animation is a .gif or .mp4 (a picture a .png or .pdf)")
    if fps <= 0:
        raise ValueError(f"--fps {fps}: expected a positive number")
    run = open_run(run_dir)
    try:
        if run.beams is None or not len(run.beams.times):
            raise RunFolderError(f"{run.folder} has no beams.xdmf with records (the run wrote no XDMF)")
        count = len(run.beams.times)
        wanted = min(count, frames if frames is not None else MAX_FRAMES)
        if wanted < 1:
            raise ValueError(f"--frames {frames}: expected at least 1")
        records = sorted(set(np.linspace(0, count - 1, wanted).round().astype(int).tolist()))
        renderer = Renderer(run, view, field, size, records)
        out.parent.mkdir(parents=True, exist_ok=True)
        with writer.saving(renderer.fig, str(out), dpi=renderer.fig.dpi):
            for i, r in enumerate(records):
                renderer.draw(r)
                writer.grab_frame()
                if progress is not None and (i + 1) % 50 == 0:
                    progress(f"  frame {i + 1} of {len(records)}")
        return out
    finally:
        run.close()


def render_command(args: argparse.Namespace, say: Callable[[str], None]) -> list[Path]:
    """``slidebeam render``: pictures for .png/.pdf, an animation for .gif/.mp4."""
    size = parse_size(args.size)
    parse_view(args.view)
    out = Path(args.out) if args.out else Path(args.run) / "render.png"
    if out.suffix in (".gif", ".mp4"):
        if args.time:
            raise ValueError("--time draws pictures (.png, .pdf); an animation (.gif, .mp4) shows the whole run")
        return [animation(args.run, out, args.view, args.field, size, args.fps, args.frames, say)]
    return pictures(args.run, args.time, out, args.view, args.field, size)
