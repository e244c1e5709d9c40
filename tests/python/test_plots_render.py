# SPDX-License-Identifier: MIT
"""`slidebeam plot` and `slidebeam render` (issue 40): the plots carry the run's own numbers, the
pictures show the structure where it is, bad requests are refused with exit code 2."""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

from slidebeam import plots
from slidebeam.plots.render import BEAM_COLOUR, MASS_COLOUR, SLIDER_COLOUR, Renderer, parse_view
from slidebeam.output.rundata import open_run

pytestmark = pytest.mark.skip_in_parallel  # spawns its own runs; reading results has no parallel part

ROOT = Path(__file__).resolve().parents[2]


def _cli(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(ROOT / "scripts" / "slidebeam"), *args], capture_output=True, text=True, cwd=cwd,
                          timeout=600, env={k: v for k, v in os.environ.items() if not k.startswith(("OMPI_COMM", "PMIX"))})


@pytest.fixture(scope="module")
def ropeway(tmp_path_factory) -> Path:
    """The shipped ropeway (track rope, driven carriage, hanger, point mass, supports, damping,
    drag) over 0.3 s, a record every second step."""
    folder = tmp_path_factory.mktemp("plots")
    run = _cli("run", str(ROOT / "runs" / "effects" / "ropeway.toml"), "--out", "ropeway", "-q",
               "--set", "analysis.t_end=0.3", "--set", "output.every=2", cwd=folder)
    assert run.returncode == 0, run.stderr
    return folder / "ropeway"


def test_every_plot_the_run_has(ropeway, tmp_path):
    run = open_run(ropeway)
    kinds = [k for k in plots.KINDS if k != "outputs"]  # the ropeway has each but outputs (test_contact.py)
    assert plots.available(run) == kinds
    out = _cli("plot", str(ropeway), "--out", "figures", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    for kind in kinds:
        assert (tmp_path / "figures" / f"{kind}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    pdf = _cli("plot", str(ropeway), "--what", "tension,reactions", "--out", "two.pdf", cwd=tmp_path)
    assert pdf.returncode == 0, pdf.stderr
    assert (tmp_path / "two.pdf").read_bytes().count(b"/Type /Page\n") + \
        (tmp_path / "two.pdf").read_bytes().count(b"/Type /Page ") == 2
    png = _cli("plot", str(ropeway), "--out", "energy.png", cwd=tmp_path)  # a .png: the energy plot
    assert png.returncode == 0 and (tmp_path / "energy.png").is_file(), png.stderr


def test_plots_draw_the_runs_numbers(ropeway):
    run = open_run(ropeway)
    beams = run.beams
    assert beams is not None and beams.names == ["track", "hanger"]
    with h5py.File(ropeway / "beams.h5") as h5:
        last = len(beams.times) - 1
        tension = np.asarray(h5[f"tension/{last}"])
        ids = np.asarray(h5["mesh/beam_id"])
    t, maps = plots.engineering.tension_map(run)
    assert np.array_equal(t, beams.times) and len(t) == 16  # 0, 0.02, ..., 0.3
    s, T = maps["hanger"]
    assert np.array_equal(T[-1], tension[ids == 1]) and s[0] == 0.0 and s[-1] == pytest.approx(1.0)
    fig = plots.figure("tension", [run])
    mesh = fig.axes[0].collections[0]  # the beam with the larger tension first: the track
    assert np.allclose(np.asarray(mesh.get_array()).reshape(-1), maps["track"][1].T.reshape(-1))
    h = run.history
    reactions = plots.engineering.reactions(run)
    assert set(reactions) == {"spherical[track@start]", "spherical[track@end]", "sliding joint hanger_on_track"}
    assert np.array_equal(reactions["spherical[track@end]"]["force"][:, 2], h["spherical[track@end].fz"])
    points = plots.engineering.tracked_points(run)
    assert np.array_equal(points["hanger@1"][1][:, 0], h["hanger@1.x"])
    cabin = points["mass point_mass[hanger@end]"][1]  # the point mass at the hanger's end: where hanger@1 is
    assert np.allclose(cabin, points["hanger@1"][1], atol=1e-12)
    assert run.sliders.names == ["hanger_on_track"]  # from sliders.h5's joint_names
    with h5py.File(ropeway / "sliders.h5") as h5:
        assert [n.decode() if isinstance(n, bytes) else n for n in h5["mesh"].attrs["joint_names"]] == ["hanger_on_track"]
    lines = plots.figure("sliders", [run]).axes[0].lines
    assert np.array_equal(lines[0].get_ydata(), h["hanger_on_track.s"])
    run.close()


def test_bad_plot_requests(ropeway, tmp_path):
    unknown = _cli("plot", str(ropeway), "--what", "tension,stress", cwd=tmp_path)
    assert unknown.returncode == 2 and "'stress'" in unknown.stderr and "Traceback" not in unknown.stderr
    several = _cli("plot", str(ropeway), "--what", "tension,reactions", "--out", "x.png", cwd=tmp_path)
    assert several.returncode == 2 and "holds one plot" in several.stderr
    static = _cli("run", str(ROOT / "runs" / "bend45.toml"), "--out", "static", "-q", cwd=tmp_path)
    assert static.returncode == 0, static.stderr
    assert "energy" not in plots.available(open_run(tmp_path / "static"))
    energy = _cli("plot", "static", "--what", "energy", cwd=tmp_path)
    assert energy.returncode == 2 and "static run" in energy.stderr


def _image(renderer: Renderer) -> np.ndarray:
    canvas = renderer.fig.canvas
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[:, :, :3].astype(int)


def _pixels_of(image: np.ndarray, colour: str) -> np.ndarray:
    from matplotlib.colors import to_rgb

    rgb = np.array(to_rgb(colour)) * 255
    return np.argwhere(np.abs(image - rgb).sum(axis=2) < 30)  # (row, column) of that colour


@pytest.mark.parametrize("view", ["iso", "front", "top", "30,10"])
def test_picture_shows_the_structure_where_it_is(ropeway, view):
    """The beams' pixels span the projected bounding box of their points (to the line width),
    and the slider and the point mass (the cabin) are drawn at their projected positions."""
    run = open_run(ropeway)
    renderer = Renderer(run, view, "none", (800, 600))
    last = len(run.beams.times) - 1
    renderer.draw(last)
    image = _image(renderer)
    beam = _pixels_of(image, BEAM_COLOUR)
    assert len(beam) > 500  # not blank
    x0, y0, x1, y1 = renderer.projected_box()
    height = image.shape[0]
    rows, cols = beam[:, 0], beam[:, 1]
    width = renderer.lines.get_linewidth()[0] * renderer.fig.dpi / 72.0 + 2.0
    assert cols.min() == pytest.approx(x0, abs=width) and cols.max() == pytest.approx(x1, abs=width)
    assert (height - rows.max()) == pytest.approx(y0, abs=width) and (height - rows.min()) == pytest.approx(y1, abs=width)
    from mpl_toolkits.mplot3d import proj3d

    for series, colour in ((run.sliders, SLIDER_COLOUR), (run.masses, MASS_COLOUR)):
        pixels = _pixels_of(image, colour)
        assert len(pixels) > 10
        p = series.positions(int(np.argmin(np.abs(series.times - run.beams.times[last]))))[0]
        x, y, _ = proj3d.proj_transform(p[0:1], p[1:2], p[2:3], renderer.ax.get_proj())
        px, py = renderer.ax.transData.transform((x[0], y[0]))
        near = np.hypot(pixels[:, 1] - px, height - pixels[:, 0] - py) < 8.0
        assert near.sum() > 10  # the marker (the mass's colour is also the axes' text: look where it is)
    run.close()


def test_render_command(ropeway, tmp_path):
    three = _cli("render", str(ropeway), "--time", "0", "0.1", "0.3", "--out", "pic.png", "--view", "front",
                 cwd=tmp_path)
    assert three.returncode == 0, three.stderr
    for name in ("pic_t0.png", "pic_t0.1.png", "pic_t0.3.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    gif = _cli("render", str(ropeway), "--out", "run.gif", "--frames", "5", "--size", "320x240", cwd=tmp_path)
    assert gif.returncode == 0, gif.stderr
    from PIL import Image

    with Image.open(tmp_path / "run.gif") as image:
        assert image.n_frames == 5 and image.size == (320, 240)
    for bad, expect in ((["--view", "sideways"], "--view"), (["--size", "big"], "--size"),
                        (["--field", "stress"], "--field"), (["--out", "x.gif", "--time", "0.1"], "--time"),
                        (["--out", "x.txt"], ".png or .pdf")):
        out = _cli("render", str(ropeway), *bad, cwd=tmp_path)
        assert out.returncode == 2 and expect in out.stderr and "Traceback" not in out.stderr, (bad, out.stderr)
    mp4 = _cli("render", str(ropeway), "--out", "run.mp4", "--frames", "3", cwd=tmp_path)
    if __import__("shutil").which("ffmpeg") is None:
        assert mp4.returncode == 2 and "apt-get install ffmpeg" in mp4.stderr
    else:
        assert mp4.returncode == 0 and (tmp_path / "run.mp4").stat().st_size > 0


def test_views():
    assert parse_view("top") == (90.0, -90.0) and parse_view("12.5,-30") == (12.5, -30.0)
    with pytest.raises(ValueError, match="ELEVATION,AZIMUTH"):
        parse_view("12")
