# SPDX-License-Identifier: MIT
"""ParaView script of a slidebeam run (view.py, written beside the run's XDMF series).

    paraview --script=view.py                                     the run in ParaView's window
    xvfb-run -a pvbatch view.py --screenshot pic.png [--time T] [--size 1280x720]
    xvfb-run -a pvbatch view.py --animation anim.png [--frames N] [--size 1280x720]

It opens beams.xdmf and shows the beams as tubes coloured by the axial force (``tension``) on
one colour scale for the whole run, the sliders and point masses as spheres, the camera on the
structure and the time at the last recorded step. The files are found beside this script, so
the run's folder may be moved. ``--animation`` writes numbered images (anim.0000.png, ...) or,
with .avi or .ogv, a movie. ``build(folder)`` sets everything up without rendering.
(slidebeam's docs/user-guide.md, "Viewing a run in ParaView", explains the filter chain.)
"""
from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path

# <run> the run's own values, filled in by slidebeam.output.paraview_script
SCENE = "scene"
SERIES = ("beams",)  # the series the run writes, of beams, sliders, masses
TUBE_RADIUS = 0.01  # m
SPHERE_DIAMETER = {"sliders": 0.04, "guides": 0.05, "masses": 0.06, "bodies": 0.1}  # m
UP = (0.0, 0.0, 1.0)  # against gravity: the picture's up
WRITTEN_IN = "."  # the folder the run wrote this script into (if neither __file__ nor --script tells)
# </run>

RANGE_RECORDS = 200  # records read for the colour scale and the camera: spread over the run
SIZE = (1280, 720)
SPHERE_COLOUR = {"sliders": (0.95, 0.55, 0.1), "guides": (0.55, 0.2, 0.6), "masses": (0.25, 0.25, 0.3),
                 "bodies": (0.2, 0.45, 0.75)}
AXIS_COLOUR = {"d1": (0.85, 0.15, 0.15), "d2": (0.15, 0.65, 0.2), "d3": (0.15, 0.3, 0.85)}  # a body's axes


def here() -> Path:
    """This script's folder. ParaView's window runs ``--script=view.py`` without ``__file__``
    and with an empty ``sys.argv``: the path then comes from the process's command line, and
    failing that it is the folder the run wrote the script into."""
    try:
        return Path(__file__).resolve().parent
    except NameError:
        pass
    script = _script_option()
    return script.resolve().parent if script is not None else Path(WRITTEN_IN)


def _script_option() -> Path | None:
    """The file of ParaView's ``--script=FILE`` (or ``--script FILE``) option, where the system
    shows a process its command line (Linux)."""
    try:
        args = Path("/proc/self/cmdline").read_bytes().decode(errors="replace").split("\0")
    except OSError:
        return None
    for k, arg in enumerate(args):
        if arg.startswith("--script="):
            return Path(arg.split("=", 1)[1])
        if arg == "--script" and k + 1 < len(args):
            return Path(args[k + 1])
    return None


def _values(prop) -> list[float]:
    """A ParaView vector property as a list (one value comes back as a plain number)."""
    return [float(prop)] if isinstance(prop, (int, float)) else [float(v) for v in prop]


def _records(xdmf: Path, field: str) -> list[tuple[str, str]]:
    """(data file, dataset) of every record of a field, in time order, as the .xdmf names them."""
    return re.findall(rf">([^<>:]+):(/{field}/\d+)<", xdmf.read_text())


def _spread(items: list, n: int) -> list:
    """At most n of the items, evenly spaced, the first and the last among them."""
    if len(items) <= n:
        return items
    return [items[round(k * (len(items) - 1) / (n - 1))] for k in range(n)]


def run_ranges(folder: Path) -> tuple[tuple[float, float] | None, list[float] | None]:
    """The tension's range and the beams' bounding box (xmin, xmax, ymin, ...) over the run,
    read from the .h5 files (h5py) at up to RANGE_RECORDS records: a colour scale that does not
    change from frame to frame and a camera that sees the whole motion. (None, None) without
    h5py: the last step's then serve."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        return None, None
    xdmf = folder / "beams.xdmf"
    files: dict[str, object] = {}

    def read(name: str, path: str):
        if name not in files:
            try:  # the run may still be writing: its writer takes no file lock either
                files[name] = h5py.File(folder / name, "r", locking=False)
            except (TypeError, ValueError):  # an h5py or HDF5 without the locking switch
                files[name] = h5py.File(folder / name, "r")
        return files[name][path][()]

    try:
        lo, hi = math.inf, -math.inf
        for name, path in _spread(_records(xdmf, "tension"), RANGE_RECORDS):
            t = read(name, path)
            lo, hi = min(lo, float(t.min())), max(hi, float(t.max()))
        points = read("beams.h5", "/mesh/points")
        box = [math.inf, -math.inf] * 3
        for name, path in _spread(_records(xdmf, "displacement"), RANGE_RECORDS):
            p = points + read(name, path)
            for k in range(3):
                box[2 * k] = min(box[2 * k], float(p[:, k].min()))
                box[2 * k + 1] = max(box[2 * k + 1], float(p[:, k].max()))
    finally:
        for f in files.values():
            f.close()
    return ((lo, hi) if lo <= hi else None), (box if box[0] <= box[1] else None)


def _reader(simple, folder: Path, name: str):
    reader = simple.Xdmf3ReaderS(registrationName=f"{name}.xdmf", FileName=[str(folder / f"{name}.xdmf")])
    reader.UpdatePipelineInformation()
    return reader


def _warp(simple, source, name: str):
    """The mesh at the current positions: the series stores the reference and displacements."""
    return simple.WarpByVector(registrationName=f"{name} moved", Input=source,
                               Vectors=["POINTS", "displacement"], ScaleFactor=1.0)


def _spheres(simple, view, folder: Path, name: str) -> dict:
    reader = _reader(simple, folder, name)
    moved = _warp(simple, reader, name)
    glyph = simple.Glyph(registrationName=f"{name} spheres", Input=moved, GlyphType="Sphere")
    glyph.GlyphMode = "All Points"  # the default samples points by bounds and may drop some
    glyph.ScaleArray = ["POINTS", "No scale array"]
    glyph.OrientationArray = ["POINTS", "No orientation array"]
    glyph.ScaleFactor = SPHERE_DIAMETER[name]
    display = simple.Show(glyph, view)
    simple.ColorBy(display, None)
    display.AmbientColor = display.DiffuseColor = list(SPHERE_COLOUR[name])
    return {f"{name}_reader": reader, f"{name}_warp": moved, f"{name}_glyph": glyph, f"{name}_display": display}


def _axes(simple, view, moved) -> dict:
    """A body's axes d1, d2, d3 as arrows from its centre (red, green, blue), 2.5 spheres long."""
    out = {}
    for axis, colour in AXIS_COLOUR.items():
        arrows = simple.Glyph(registrationName=f"bodies {axis}", Input=moved, GlyphType="Arrow")
        arrows.GlyphMode = "All Points"
        arrows.ScaleArray = ["POINTS", "No scale array"]
        arrows.OrientationArray = ["POINTS", axis]
        arrows.ScaleFactor = 2.5 * SPHERE_DIAMETER["bodies"]
        display = simple.Show(arrows, view)
        simple.ColorBy(display, None)
        display.AmbientColor = display.DiffuseColor = list(colour)
        out[f"bodies_{axis}_glyph"] = arrows
    return out


def _tension_scale(simple, tension: tuple[float, float] | None):
    """The colour scale of the tension, fixed over the run (ParaView would rescale it to
    each frame's data, and a colour would then mean another force in every frame). Set after
    ColorBy, which fits a new scale to the data at hand."""
    lut = simple.GetColorTransferFunction("tension")
    if tension is not None:
        lo, hi = tension
        if hi - lo <= 1e-12 * max(1.0, abs(lo), abs(hi)):  # no range (a run of one record at rest)
            lo, hi = lo - 1.0, hi + 1.0
        lut.AutomaticRescaleRangeMode = "Never"
        lut.RescaleTransferFunction(lo, hi)
    return lut


def _camera(view, bounds: list[float] | None) -> None:
    """Up against gravity; looking across the structure's longest horizontal extent, a little
    from above and from the side, so that a sag and a swing both show."""
    up = UP
    if bounds is not None:
        extent = [bounds[2 * k + 1] - bounds[2 * k] for k in range(3)]
        flat = [k for k in range(3) if abs(up[k]) < 0.5] or [0, 1]
        along = max(flat, key=lambda k: extent[k])
        a = [1.0 if k == along else 0.0 for k in range(3)]
        side = [up[1] * a[2] - up[2] * a[1], up[2] * a[0] - up[0] * a[2], up[0] * a[1] - up[1] * a[0]]
        look = [-(s + 0.35 * u + 0.25 * x) for s, u, x in zip(side, up, a)]  # from the camera to the centre
        centre = [(bounds[2 * k] + bounds[2 * k + 1]) / 2 for k in range(3)]
        view.CameraFocalPoint = centre
        view.CameraPosition = [c - d for c, d in zip(centre, look)]
        view.CameraViewUp = list(up)
        view.ResetCamera(*bounds)
    else:
        view.CameraViewUp = list(up)
        view.ResetCamera()


def build(folder: str | Path | None = None, view=None) -> dict:
    """Set up the pipeline, the displays and the camera at the last record, without rendering
    (go_to() then sets the animation's time): the readers, the filters (``beams_reader``,
    ``beams_warp``, ``beams_surface``, ``beams_lines``, ``tube``; per series of points ``<name>_reader``,
    ``_warp``, ``_glyph``; the bodies' axes ``bodies_d1_glyph``, ``_d2_``, ``_d3_``), the displays,
    ``lut`` (the tension's colour scale), ``view``, ``times`` and ``tension_range`` (None if h5py is
    missing).
    ``folder``: the run's folder (default: this script's); ``view``: a render view (default: the
    active one, made if there is none)."""
    from paraview import simple

    folder = here() if folder is None else Path(folder)
    view = view or simple.GetActiveViewOrCreate("RenderView")
    tension, bounds = run_ranges(folder)
    beams = _reader(simple, folder, "beams")
    moved = _warp(simple, beams, "beams")
    surface = simple.ExtractSurface(registrationName="beams surface", Input=moved)  # Tube needs polydata
    # each beam's segments joined into one polyline (vtkStripper): a tube without seams and
    # caps at every sample point, and 4x quicker to make (the ropeway's frames: 133 -> 30 ms)
    lines = simple.TriangleStrips(registrationName="beams lines", Input=surface, MaximumLength=100000)
    tube = simple.Tube(registrationName="beams tube", Input=lines, Radius=TUBE_RADIUS, NumberofSides=16)
    tube.Capping = 1
    display = simple.Show(tube, view)
    simple.ColorBy(display, ("POINTS", "tension"))
    lut = _tension_scale(simple, tension)
    display.LookupTable = lut
    display.SetScalarBarVisibility(view, True)
    p = {"beams_reader": beams, "beams_warp": moved, "beams_surface": surface, "beams_lines": lines, "tube": tube,
         "tube_display": display,
         "lut": lut, "view": view, "tension_range": tension}
    for name in SERIES:
        if name != "beams":
            p.update(_spheres(simple, view, folder, name))
    if "bodies" in SERIES:
        p.update(_axes(simple, view, p["bodies_warp"]))
    clock = simple.AnnotateTime(registrationName="time", Format="t = {time:.4g} s")
    p["clock_display"] = simple.Show(clock, view)
    p["times"] = _values(beams.TimestepValues)
    view.ViewTime = p["times"][-1]
    _camera(view, bounds)
    return p


def go_to(p: dict, t: float | None = None) -> None:
    """The animation over the run's records, at time t (default: the last record). This renders
    (the animation scene draws its views when its time changes), so build() leaves it out."""
    from paraview import simple

    times = p["times"]
    t = times[-1] if t is None else min(max(t, times[0]), times[-1])
    scene = simple.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = t
    p["view"].ViewTime = t
    p["scene"] = scene


def _size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"(\d+)x(\d+)", text)
    if not match:
        raise argparse.ArgumentTypeError(f"'{text}' is not WIDTHxHEIGHT in pixels, e.g. 1280x720")
    return int(match.group(1)), int(match.group(2))


def _arguments(argv: list[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="pvbatch view.py", description=f"Pictures of the slidebeam run '{SCENE}'.")
    parser.add_argument("--screenshot", metavar="FILE", help="save one picture (png, jpg, ...)")
    parser.add_argument("--animation", metavar="FILE",
                        help="save the run as numbered pictures (anim.png: anim.0000.png, ...) or a movie (.avi, .ogv)")
    parser.add_argument("--time", type=float, help="the screenshot's time (s; default: the last recorded step)")
    parser.add_argument("--frames", type=int, help="animation frames, spread evenly over the run (default: every record)")
    parser.add_argument("--fps", type=int, default=10, help="a movie's frames per second (default: 10)")
    parser.add_argument("--size", type=_size, default=SIZE, help="picture size in pixels (default: 1280x720)")
    return parser.parse_args(argv)


def _save_animation(simple, p: dict, file: str, frames: int | None, size: tuple[int, int], fps: int = 10) -> None:
    scene, times = p["scene"], p["times"]
    if frames is not None:
        scene.PlayMode = "Sequence"
        scene.StartTime, scene.EndTime = times[0], times[-1]
        scene.NumberOfFrames = max(1, frames)
    simple.SaveAnimation(file, p["view"], ImageResolution=list(size), FrameRate=max(1, fps))


def main(argv: list[str]) -> None:
    """Under pvbatch: save what the arguments ask for. In ParaView's window (no arguments): show."""
    args = _arguments(argv)
    from paraview import simple

    p = build()
    view = p["view"]
    view.ViewSize = list(args.size)
    go_to(p, args.time)
    for file in (args.screenshot, args.animation):
        if file:  # ParaView writes nothing, and says nothing, into a folder that does not exist
            Path(file).parent.mkdir(parents=True, exist_ok=True)
    if args.screenshot:
        simple.SaveScreenshot(args.screenshot, view, ImageResolution=list(args.size))
    if args.animation:
        _save_animation(simple, p, args.animation, args.frames, args.size, args.fps)
    if not (args.screenshot or args.animation):
        simple.Render(view)
        if _as_command():
            print("view.py: nothing saved (--screenshot FILE or --animation FILE); to look at the run: "
                  "paraview --script=view.py", file=sys.stderr)


def _as_command() -> bool:
    """Run as pvbatch's or pvpython's script (its arguments are ours), not by ParaView's window."""
    try:
        return bool(sys.argv) and Path(sys.argv[0]).resolve() == Path(__file__).resolve()
    except NameError:
        return False


if __name__ == "__main__":
    # no sys.exit at the end: pvbatch then tears Python down before its OpenGL context and crashes
    main(sys.argv[1:] if _as_command() else [])  # in ParaView's window sys.argv is the window's
