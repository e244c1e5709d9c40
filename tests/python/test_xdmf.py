# SPDX-License-Identifier: MIT
"""XDMF/HDF5 output as users open it (issue 5): read back with meshio against history.csv, the
.h5 beside its .xdmf whatever the working directory, 1 rank = 2 ranks, ParaView's three readers
(one copy of the beams in each, issue 22), a clean stop when the disk fills, the point masses'
series and the run's ParaView script view.py (issue 40)."""
from __future__ import annotations

import csv
import json
import resource
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.skip_in_parallel  # each test starts its own processes

SEED = ("runs", "seed", "free_fall_inclined_1+4.toml")
SHORT = ["--set", "analysis.t_end=0.05", "--set", "output.every=5", "--set", "output.samples_per_span=3"]
BEAM_FIELDS = {"displacement": 3, "velocity": 3, "d1": 3, "d2": 3, "d3": 3, "strain": 6, "force": 3, "moment": 3,
               "tension": 1, "section_d2": 3, "section_d3": 3, "s": 1, "beam_id": 1}


def read_series(path: Path) -> tuple[np.ndarray, list[tuple[float, dict[str, np.ndarray]]]]:
    import meshio

    with meshio.xdmf.TimeSeriesReader(str(path)) as reader:
        points, cells = reader.read_points_cells()
        steps = [reader.read_data(k)[:2] for k in range(reader.num_steps)]
    return points, steps


def history(run: Path) -> list[dict[str, str]]:
    return list(csv.DictReader((run / "history.csv").open()))


def test_beams_and_sliders_read_back_against_the_history(run_cli, root, tmp_path):
    """Every recorded step is in the series with every array in its shape, and the values agree
    with history.csv: the end of CM (its last sample) is the tracked point CM@1, the slider's
    s and reaction are the joint's columns. Run from another working directory: the .h5 files
    must land beside their .xdmf."""
    elsewhere = tmp_path / "cwd"
    elsewhere.mkdir()
    out = run_cli("run", str(root.joinpath(*SEED)), "--out", str(tmp_path / "res"), "-q", *SHORT, cwd=elsewhere)
    assert out.returncode == 0, out.stderr
    assert not list(elsewhere.iterdir())  # nothing written to the working directory
    run = tmp_path / "res"
    rows = history(run)
    points, steps = read_series(run / "beams.xdmf")
    assert len(steps) == len(rows) == 11  # t = 0, 0.005, ..., 0.05
    n = (4 * 3 + 1) + (1 * 3 + 1)  # AB: 4 spans, CM: 1 span; 3 samples per span and the end
    assert points.shape == (n, 3)
    for (t, data), row in zip(steps, rows):
        assert t == pytest.approx(float(row["t"]), abs=1e-15)
        assert set(data) == set(BEAM_FIELDS)
        for name, width in BEAM_FIELDS.items():
            assert data[name].shape == ((n,) if width == 1 else (n, width)), name
            assert np.isfinite(data[name]).all()
        tip = points[-1] + data["displacement"][-1]
        assert tip == pytest.approx([float(row[f"CM@1.{c}"]) for c in "xyz"], abs=1e-12)
        start = points[13] + data["displacement"][13]  # CM's first sample: the slider C
        assert start == pytest.approx([float(row[f"CM@0.{c}"]) for c in "xyz"], abs=1e-12)
        assert list(data["beam_id"]) == [0] * 13 + [1] * 4
        assert np.linalg.norm(data["d1"], axis=1) == pytest.approx(1.0, abs=1e-3)
        half = np.linalg.norm(data["section_d2"], axis=1)
        assert half == pytest.approx(0.0025, rel=1e-3)  # 5 mm square section: half width
    t0, first = steps[0]
    assert np.abs(first["displacement"]).max() == 0.0 and np.abs(first["strain"]).max() < 1e-12
    slider_points, slider_steps = read_series(run / "sliders.xdmf")
    assert slider_points.shape == (1, 3)
    for (t, data), row in zip(slider_steps, rows):
        assert data["s"][0] == pytest.approx(float(row["CM_on_AB.s"]), abs=1e-14)
        assert data["reaction"][0] == pytest.approx([float(row[f"CM_on_AB.reaction.{c}"]) for c in "xyz"], abs=1e-12)
        assert slider_points[0] + data["displacement"][0] == pytest.approx(
            [float(row[f"CM@0.{c}"]) for c in "xyz"], abs=1e-12)
    mass_points, mass_steps = read_series(run / "masses.xdmf")
    assert mass_points.shape == (1, 3) and mass_points[0] == pytest.approx(points[-1], abs=0)  # CM's end
    assert len(mass_steps) == len(steps)
    for (t, data), (tb, beams) in zip(mass_steps, steps):
        assert t == tb and set(data) == {"displacement", "velocity", "mass", "mass_id"}
        assert np.array_equal(data["displacement"][0], beams["displacement"][-1])  # the same sample point
        assert data["velocity"][0] == pytest.approx(beams["velocity"][-1], rel=1e-12, abs=1e-15)
        assert list(data["mass"]) == [1.0] and list(data["mass_id"]) == [0]
    assert np.abs(mass_steps[-1][1]["velocity"]).max() > 0.1  # falling: the comparison compares something
    import h5py

    with h5py.File(run / "beams.h5", "r") as f:
        assert list(f["mesh"].attrs["beam_names"]) == ["AB", "CM"]
    with h5py.File(run / "masses.h5", "r") as f:
        assert list(f["mesh"].attrs["mass_names"]) == ["point_mass[CM@end]"]
    summary = json.loads((run / "summary.json").read_text())
    assert "point_mass[CM@end]" in summary["active_effects"]  # the names are the effects' labels


def test_the_series_reads_back_with_meshio_as_the_simulation_sampled(root, tmp_path, monkeypatch):
    """meshio's TimeSeriesReader reads, at every record, the very numbers the simulation sampled
    (Simulation.sample_beam per beam, the sliding joint's state), and the .xdmf on disk describes
    flushed records only: with FLUSH_EVERY = 3, after 4 records it has 3 steps or is not there yet
    (the writer appends them once their data is written), 4 after a flush that waits."""
    import slidebeam
    from slidebeam.output import xdmf

    monkeypatch.setattr(xdmf, "FLUSH_EVERY", 3)
    scene = slidebeam.load_scene(root.joinpath(*SEED), ["analysis.t_end=0.007", "output.every=1",
                                                       "output.samples_per_span=3"])
    sim = slidebeam.Simulation(scene)
    output = xdmf.XdmfOutput(sim, tmp_path, rank=0)
    sampled, steps_on_disk = [], []

    def on_step(rec) -> None:
        output.write(rec.t, rec.joints)
        beams = [sim.sample_beam(b.index, 3) for b in scene.beams]
        sampled.append((rec.t, {key: np.concatenate([p[key] for p in beams]) for key in beams[0]},
                        sim.joint_states()[0]))
        if len(sampled) == 4:  # the writer may still be writing the first 3: their steps follow their data
            xdmf_file = tmp_path / "beams.xdmf"
            steps_on_disk.append(len(read_series(xdmf_file)[1]) if xdmf_file.exists() else 0)
            output.flush()  # waits
            steps_on_disk.append(len(read_series(tmp_path / "beams.xdmf")[1]))

    sim.run_dynamic(on_step)
    output.close()
    assert steps_on_disk[0] in (0, 3) and steps_on_disk[1] == 4
    points, steps = read_series(tmp_path / "beams.xdmf")
    _, slider_steps = read_series(tmp_path / "sliders.xdmf")
    assert len(steps) == len(slider_steps) == len(sampled) == 8  # t = 0, 0.001, ..., 0.007
    for (t, data), (_, slider), (ts, want, joint) in zip(steps, slider_steps, sampled):
        assert t == ts
        for key in ("velocity", "d1", "d2", "d3", "strain", "force", "moment", "tension", "s"):
            assert np.array_equal(data[key], want[key]), key
        assert np.abs(points + data["displacement"] - want["position"]).max() <= 1e-15
        assert slider["s"][0] == joint.s and np.array_equal(slider["reaction"][0], joint.reaction)
    assert np.abs(steps[-1][1]["displacement"]).max() > 1e-6  # the beams moved: the check compares something


def test_static_runs_write_the_series_too(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "r", "-q", "--set", "analysis.steps=3",
                  "--set", "beam.0.spans=6")
    assert out.returncode == 0, out.stderr
    points, steps = read_series(tmp_path / "r" / "beams.xdmf")
    assert [t for t, _ in steps] == pytest.approx([0.0, 1 / 3, 2 / 3, 1.0])
    assert not (tmp_path / "r" / "sliders.xdmf").exists()  # no sliding joints, no slider series
    assert not (tmp_path / "r" / "masses.xdmf").exists()  # no point masses, no mass series
    assert (tmp_path / "r" / "view.py").is_file()
    assert np.abs(steps[0][1]["velocity"]).max() == 0.0


# a second point mass inside the carrier AB (at a knot: a sample point of its polyline), placed by
# evaluating the beam, which is spread over the ranks under mpirun -n 2
INNER_MASS = """
[[point_mass]]
beam = "AB"
at = 0.5
mass = 0.5
"""


def seed_with_inner_mass(root: Path, folder: Path) -> Path:
    scene = folder / "seed_masses.toml"
    scene.write_text(root.joinpath(*SEED).read_text() + INNER_MASS)
    return scene


def test_two_ranks_write_the_same_series_as_one(run_cli, root, tmp_path):
    """Fields are gathered to rank 0, which writes: the files hold the same numbers. The point
    mass inside AB is where AB's sample point at s = 0.5 is."""
    scene = seed_with_inner_mass(root, tmp_path)
    for np_, name in ((1, "one"), (2, "two")):
        out = run_cli("run", str(scene), "--out", name, "-q", *SHORT, np=np_)
        assert out.returncode == 0, out.stderr
    points, beams = read_series(tmp_path / "two" / "beams.xdmf")
    mass_points, masses = read_series(tmp_path / "two" / "masses.xdmf")
    assert mass_points == pytest.approx(points[[16, 3]], abs=1e-15)  # CM's end, AB at s = 0.5 (3 samples a span)
    for (_, b), (_, m) in zip(beams, masses):
        assert m["displacement"] == pytest.approx(b["displacement"][[16, 3]], rel=1e-12, abs=1e-15)
        assert m["velocity"] == pytest.approx(b["velocity"][[16, 3]], rel=1e-12, abs=1e-15)
    assert list(m["mass"]) == [1.0, 0.5]
    for series in ("beams.xdmf", "sliders.xdmf", "masses.xdmf"):
        p1, s1 = read_series(tmp_path / "one" / series)
        p2, s2 = read_series(tmp_path / "two" / series)
        assert np.array_equal(p1, p2) and len(s1) == len(s2)
        for (t1, d1), (t2, d2) in zip(s1, s2):
            assert t1 == t2 and set(d1) == set(d2)
            for key in d1:
                scale = max(1.0, np.abs(d1[key]).max())
                # the reaction is the joint's multipliers and force, moment, tension are C (eps - eps0):
                # the linear solvers (PETSc LU serial, GMRES + block Jacobi parallel) leave them
                # less exact than the state, ~1e-9 at Newton tolerance (times the stiffness)
                tol = 1e-8 if key in ("reaction", "force", "moment", "tension", "strain") else 1e-9
                assert np.abs(d1[key] - d2[key]).max() <= tol * scale, (series, key)


def test_a_restart_continues_the_point_masses_series(run_cli, root, tmp_path):
    """masses.xdmf follows the checkpoints as the other series do: a run stopped at t = 0.03
    (with a checkpoint at 0.02 on the way, after which its records go into masses.1.h5) and
    restarted to 0.05 has the series of the run that went on."""
    scene = str(root.joinpath(*SEED))
    common = ["-q", "--set", "output.every=5", "--set", "output.samples_per_span=3",
              "--set", "output.checkpoint_every=20"]
    for args in (["--out", "whole", "--set", "analysis.t_end=0.05"], ["--out", "parts", "--set", "analysis.t_end=0.03"],
                 ["--restart", "parts/checkpoint.h5", "--set", "analysis.t_end=0.05"]):
        out = run_cli("run", scene, *common, *args)
        assert out.returncode == 0, out.stderr
    assert (tmp_path / "parts" / "masses.1.h5").is_file() and (tmp_path / "parts" / "masses.2.h5").is_file()
    pa, whole = read_series(tmp_path / "whole" / "masses.xdmf")
    pb, parts = read_series(tmp_path / "parts" / "masses.xdmf")
    assert np.array_equal(pa, pb) and len(whole) == len(parts) == 11
    for (ta, da), (tb, db) in zip(whole, parts):
        assert ta == pytest.approx(tb, abs=1e-15)
        for key in da:
            assert np.abs(da[key] - db[key]).max() <= 1e-12 * max(1.0, np.abs(da[key]).max()), key
    _, beams = read_series(tmp_path / "parts" / "beams.xdmf")
    assert all(np.array_equal(m["displacement"][0], b["displacement"][-1]) for (_, m), (_, b) in zip(parts, beams))


def load_view_script(path: Path):
    """view.py as a module (it imports ParaView only when it builds or renders)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("view", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_run_with_xdmf_writes_its_paraview_script(run_cli, root, tmp_path):
    """view.py names the series the run wrote and a tube radius of at least 0.4 % of the
    structure (the seed's bars: 5 mm across a 2.2 m structure); no XDMF, no script."""
    out = run_cli("run", str(root.joinpath(*SEED)), "--out", "res", "-q", *SHORT)
    assert out.returncode == 0, out.stderr
    view = load_view_script(tmp_path / "res" / "view.py")
    assert view.SCENE == "free_fall_inclined_1+4" and view.SERIES == ("beams", "sliders", "masses")
    points, _ = read_series(tmp_path / "res" / "beams.xdmf")
    extent = np.linalg.norm(points.max(axis=0) - points.min(axis=0))
    assert view.TUBE_RADIUS == pytest.approx(0.004 * extent) and view.TUBE_RADIUS > 0.0025
    assert view.UP == (0.0, 1.0, 0.0)  # the seed's gravity is -y
    assert not list((tmp_path / "res").glob(".*.tmp"))  # written whole, then renamed
    none = run_cli("run", str(root.joinpath(*SEED)), "--out", "none", "-q", *SHORT, "--set", "output.xdmf=false")
    assert none.returncode == 0, none.stderr
    assert not (tmp_path / "none" / "view.py").exists()


def _paraview_available() -> bool:
    probe = subprocess.run(["/usr/bin/python3", "-c", "import paraview.simple"], capture_output=True)
    return probe.returncode == 0


@pytest.mark.skipif(not _paraview_available(), reason="python3-paraview is not installed")
def test_paraview_opens_the_run(run_cli, root, tmp_path):
    """ParaView's own XDMF reader sees every time step, the polyline and the arrays, and the
    user guide's filter chain (Warp By Vector, Extract Surface, Ribbon) runs."""
    out = run_cli("run", str(root.joinpath(*SEED)), "--out", "res", "-q", *SHORT)
    assert out.returncode == 0, out.stderr
    script = f"""
import json
from paraview import simple
beams = simple.Xdmf3ReaderS(FileName=[{str(tmp_path / 'res' / 'beams.xdmf')!r}])
beams.UpdatePipelineInformation()
times = list(beams.TimestepValues)
warp = simple.WarpByVector(Input=beams, Vectors=['POINTS', 'displacement'])
surface = simple.ExtractSurface(Input=warp)  # Ribbon and Tube need polydata
ribbon = simple.Ribbon(Input=surface, Vectors=['POINTS', 'section_d3'], Width=0.0025)
ribbon.UpdatePipeline(times[-1])
beams.UpdatePipeline(times[-1])
info = beams.GetDataInformation()
sliders = simple.Xdmf3ReaderS(FileName=[{str(tmp_path / 'res' / 'sliders.xdmf')!r}])
sliders.UpdatePipeline(times[-1])
print(json.dumps({{"times": times, "points": info.GetNumberOfPoints(), "cells": info.GetNumberOfCells(),
                  "arrays": sorted(beams.PointData.keys()), "ribbon_points": ribbon.GetDataInformation().GetNumberOfPoints(),
                  "slider_arrays": sorted(sliders.PointData.keys())}}))
"""
    res = subprocess.run(["/usr/bin/python3", "-c", script], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    info = json.loads(res.stdout.strip().splitlines()[-1])
    assert info["times"] == pytest.approx([0.005 * k for k in range(11)])
    assert info["points"] == 17 and info["cells"] == 15
    assert set(BEAM_FIELDS) <= set(info["arrays"])
    assert info["ribbon_points"] > 17
    assert {"s", "reaction", "displacement"} <= set(info["slider_arrays"])


_READERS_SCRIPT = """
import json, sys
from paraview import simple, servermanager
from vtkmodules.util.numpy_support import vtk_to_numpy
path, t = sys.argv[1], float(sys.argv[2])
seen = {}
for reader in ("XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT"):
    # the legacy reader's file property is FileNames, the XDMF3 readers' FileName
    source = getattr(simple, reader)(**{("FileNames" if reader == "XDMFReader" else "FileName"): [path]})
    source.UpdatePipelineInformation()
    source.UpdatePipeline(t)
    info = source.GetDataInformation()
    data = servermanager.Fetch(source)
    blocks = data.GetNumberOfBlocks() if data.IsA("vtkMultiBlockDataSet") else 1
    disp = data.GetPointData().GetArray("displacement") if blocks == 1 else None
    seen[reader] = {"times": list(source.TimestepValues), "points": info.GetNumberOfPoints(),
                    "cells": info.GetNumberOfCells(), "blocks": blocks,
                    "displacement": None if disp is None else vtk_to_numpy(disp).tolist()}
print(json.dumps(seen))
"""


@pytest.mark.skipif(not _paraview_available(), reason="python3-paraview is not installed")
def test_every_paraview_reader_shows_one_copy(run_cli, root, tmp_path):
    """Issue 22: the legacy XDMFReader showed a separate reference-mesh grid beside the time
    series, so every beam (and slider) twice, the copy frozen at the reference. All three
    readers must see one grid per time step holding that step's data."""
    out = run_cli("run", str(root.joinpath(*SEED)), "--out", "res", "-q", *SHORT)
    assert out.returncode == 0, out.stderr
    k = 7  # a step away from the start: the displacement is not zero there
    for series, points, cells in (("beams.xdmf", 17, 15), ("sliders.xdmf", 1, 1), ("masses.xdmf", 1, 1)):
        _, steps = read_series(tmp_path / "res" / series)
        t, data = steps[k]
        assert np.abs(data["displacement"]).max() > 1e-4
        res = subprocess.run(["/usr/bin/python3", "-c", _READERS_SCRIPT, str(tmp_path / "res" / series), repr(t)],
                             capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stderr
        seen = json.loads(res.stdout.strip().splitlines()[-1])
        for reader, got in seen.items():
            assert got["times"] == pytest.approx([0.005 * j for j in range(11)]), (series, reader)
            assert (got["blocks"], got["points"], got["cells"]) == (1, points, cells), (series, reader)
            assert np.array(got["displacement"]) == pytest.approx(data["displacement"], abs=1e-15), (series, reader)


def test_a_series_written_before_issue_22_is_continued_in_the_new_structure(tmp_path, monkeypatch):
    """A restart may continue a series written with meshio's structure (a separate reference
    grid XIncluded by every step): the continued file has no separate grid and every step,
    old and new, carries the reference mesh."""
    import xml.etree.ElementTree as ET

    from meshio.xdmf import TimeSeriesWriter
    from slidebeam.output.xdmf import Series

    monkeypatch.chdir(tmp_path)  # meshio's own writer puts the .h5 in the working directory
    points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    with TimeSeriesWriter("old.xdmf") as old:
        old.write_points_cells(points, [("line", np.array([[0, 1], [1, 2]]))])
        for t in (0.0, 0.1, 0.2):
            old.write_data(t, point_data={"displacement": np.full((3, 3), t)})
    lines = np.array([[0, 1], [1, 2]])
    series = Series(tmp_path / "old.xdmf", points, lines, "Polyline", {}, resume_after=0.1)
    series.add(0.15, {"displacement": np.full((3, 3), 0.15)})
    series.close()
    domain = ET.parse(tmp_path / "old.xdmf").getroot().find("Domain")
    assert [g.get("GridType") for g in domain.findall("Grid")] == ["Collection"]
    text = (tmp_path / "old.xdmf").read_text()
    assert "XInclude" not in text and 'Name="mesh"' not in text
    got_points, steps = read_series(tmp_path / "old.xdmf")
    assert np.array_equal(got_points, points)
    assert [t for t, _ in steps] == [0.0, 0.1, 0.15]
    assert [d["displacement"][0, 0] for _, d in steps] == [0.0, 0.1, 0.15]


def test_a_run_warns_once_when_its_results_would_be_large(run_cli, root, tmp_path):
    """The estimate (12 records of about 23 kB) against output.warn_size_gb: above it one warning
    before the run, naming the key and output.every; below it, or with 0, none."""
    scene = str(root / "runs" / "seed" / "free_fall_1+4.toml")
    short = ["--set", "analysis.t_end=0.01", "--set", "output.every=1"]
    out = run_cli("run", scene, "--out", "a", "-q", *short, "--set", "output.warn_size_gb=1e-4")
    assert out.returncode == 0, out.stderr
    assert out.stderr.count("warning: the results of this run will take about") == 1, out.stderr
    assert "output.warn_size_gb = 0.0001" in out.stderr and "output.every (now 1)" in out.stderr
    size = sum(f.stat().st_size for f in (tmp_path / "a").iterdir() if f.name != "checkpoint.h5")
    estimate = float(out.stderr.split("take about ")[1].split(" kB")[0]) * 1e3
    assert 0.7 * size < estimate < 1.5 * size  # the estimate is near what is written
    for limit in ("1e-3", "0"):
        quiet = run_cli("run", scene, "--out", "b", "-q", *short, "--set", f"output.warn_size_gb={limit}")
        assert quiet.returncode == 0 and "warning" not in quiet.stderr, quiet.stderr


def _small_file_limit() -> None:
    """In the child: no file may grow beyond 8 MiB (MPI's own shared-memory files need a few),
    and exceeding it is an error (EFBIG), as on a full disk."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (8 << 20, 8 << 20))


def test_a_full_disk_stops_the_run_cleanly(root, tmp_path):
    """beams.h5 outgrows the limit near t = 0.1: exit 2 with one message, no trace, no crash, no
    summary claiming a complete run."""
    cmd = [str(root / "scripts" / "slidebeam"), "run", str(root / "runs" / "seed" / "free_fall_1+8.toml"),
           "--out", "full", "-q", "--set", "analysis.t_end=0.5", "--set", "output.every=1",
           "--set", "output.samples_per_span=64"]
    res = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path, preexec_fn=_small_file_limit, timeout=300)
    assert res.returncode == 2, (res.returncode, res.stderr)
    assert "XDMF output" in res.stderr and "File too large" in res.stderr and "run stopped at t =" in res.stderr
    assert "Traceback" not in res.stderr and "PETSC ERROR" not in res.stderr
    assert not (tmp_path / "full" / "summary.json").exists()  # nothing claims a complete run
    import h5py

    with h5py.File(tmp_path / "full" / "beams.h5", "r") as f:  # whole: every record before the refused one reads
        records = sorted(int(k) for k in f["displacement"].keys())
        assert records == list(range(len(records))) and len(records) > 10
        assert all(f[f"{name}/{records[-1]}"].shape[0] == (8 * 64 + 1) + (64 + 1) for name in ("displacement", "tension"))


def test_output_that_cannot_fit_is_refused_at_the_start(run_cli, root, tmp_path):
    # 3e5 records of 100002 sample points: 8.9 TB of XDMF, but a history that fits in memory (the
    # memory check refuses a billion records before the disk check would see them)
    out = run_cli("run", str(root.joinpath(*SEED)), "--out", "big", "-q", "--set", "analysis.t_end=3000",
                  "--set", "output.samples_per_span=20000")
    assert out.returncode == 2
    assert "needs about" in out.stderr and "MB are free" in out.stderr and "output.every" in out.stderr
    assert not (tmp_path / "big" / "beams.h5").exists()


def test_the_record_writer_writes_records_then_the_text_that_names_them(tmp_path):
    """The background writer: every record as /<field>/<record> (float64 and int32, bit for bit),
    the text appended over the closing tags only after the records before it, and a record that
    would break the file's size limit refused with the reason, the file still whole."""
    import h5py

    from slidebeam import _core

    h5 = tmp_path / "s.h5"
    with h5py.File(h5, "w") as f:
        f.create_group("mesh")
    text = tmp_path / "s.txt"
    text.write_bytes(b"<a>" + b"</a>")
    writer = _core.RecordWriter(str(h5))
    writer.set_text_file(str(text), 3, b"</a>")
    rng = np.random.default_rng(1)
    records = [{"x": rng.random((5, 3)), "k": np.arange(r, r + 4, dtype=np.int32)} for r in range(40)]
    for r, fields in enumerate(records):
        writer.add(r, fields)
        if r == 19:
            writer.append_text(b"<b/>")
    writer.append_text(b"<c/>")
    assert writer.wait() == "" and writer.pending == 0 and writer.failed_record == -1
    assert text.read_bytes() == b"<a><b/><c/></a>"
    assert writer.close() == ""
    with h5py.File(h5, "r") as f:
        for r, fields in enumerate(records):
            assert np.array_equal(f[f"x/{r}"][()], fields["x"]) and f[f"x/{r}"].dtype == np.float64
            assert np.array_equal(f[f"k/{r}"][()], fields["k"]) and f[f"k/{r}"].dtype == np.int32

    script = f"""
import resource, signal, numpy as np, h5py
from slidebeam import _core
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
with h5py.File({str(tmp_path / 'big.h5')!r}, "w") as f:
    f.create_group("mesh")
resource.setrlimit(resource.RLIMIT_FSIZE, (8 << 20, 8 << 20))
w = _core.RecordWriter({str(tmp_path / 'big.h5')!r})
for r in range(40):
    w.add(r, {{"x": np.full((20000, 3), float(r))}})
print(w.wait(), "|", w.failed_record, "|", w.close())
"""
    res = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    error, failed, closed = (part.strip() for part in res.stdout.split("|"))
    assert "File too large" in error and 0 < int(failed) < 40 and closed == error
    with h5py.File(tmp_path / "big.h5", "r") as f:  # the records before the refused one are whole
        assert all(f[f"x/{r}"][0, 0] == r for r in range(int(failed)))


_BUILD_SCRIPT = """
import json, sys
sys.path.insert(0, sys.argv[1])
import view  # the moved run's own script: it finds the series beside itself
p = view.build()
out = {"times": p["times"], "tension_range": list(p["tension_range"]), "lut": list(p["lut"].RGBPoints),
       "colour": list(p["tube_display"].ColorArrayName), "radius": p["tube"].Radius}
for name in ("beams", "sliders", "masses"):
    reader = p[name + "_reader"]
    out[name + "_times"] = view._values(reader.TimestepValues)
for name in ("tube", "sliders_glyph", "masses_glyph"):
    p[name].UpdatePipeline(p["times"][-1])
    out[name + "_points"] = p[name].GetDataInformation().GetNumberOfPoints()
    out[name + "_type"] = p[name].GetXMLName()
print(json.dumps(out))
"""


@pytest.mark.skipif(not _paraview_available(), reason="python3-paraview is not installed")
def test_the_paraview_script_builds_the_view_of_a_moved_run(run_cli, root, tmp_path):
    """view.py's build() (no rendering: that needs an X display) in a run folder moved after the
    run: the readers see every recorded step, the beams are tubes coloured by the tension on
    the scale of the whole run, the slider and the point mass are spheres."""
    import shutil

    out = run_cli("run", str(root.joinpath(*SEED)), "--out", "res", "-q", *SHORT)
    assert out.returncode == 0, out.stderr
    moved = tmp_path / "elsewhere" / "res"
    shutil.move(tmp_path / "res", moved)
    res = subprocess.run(["/usr/bin/python3", "-c", _BUILD_SCRIPT, str(moved)], capture_output=True, text=True,
                         timeout=300, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    got = json.loads(res.stdout.strip().splitlines()[-1])
    times = [0.005 * k for k in range(11)]
    for name in ("times", "beams_times", "sliders_times", "masses_times"):
        assert got[name] == pytest.approx(times), name
    tension = [d["tension"] for _, d in read_series(moved / "beams.xdmf")[1]]
    lo, hi = min(t.min() for t in tension), max(t.max() for t in tension)
    assert got["tension_range"] == pytest.approx([lo, hi], rel=1e-12)
    assert (got["lut"][0], got["lut"][-4]) == pytest.approx((lo, hi), rel=1e-12)  # the scale's ends (x, r, g, b)
    assert got["colour"] == ["POINTS", "tension"]
    assert (got["tube_type"], got["sliders_glyph_type"], got["masses_glyph_type"]) == ("TubeFilter", "Glyph", "Glyph")
    assert got["tube_points"] > 17 and got["sliders_glyph_points"] > 1 and got["masses_glyph_points"] > 1
    assert got["radius"] == pytest.approx(load_view_script(moved / "view.py").TUBE_RADIUS)


_BODY_AXES_SCRIPT = """
import json, sys
sys.path.insert(0, sys.argv[1])
import view
p = view.build()
out = {}
for axis in ("d1", "d2", "d3"):
    glyph = p["bodies_" + axis + "_glyph"]
    glyph.UpdatePipeline(p["times"][0])
    out[axis] = list(glyph.GetDataInformation().GetBounds())
print(json.dumps(out))
"""


@pytest.mark.skipif(not _paraview_available(), reason="python3-paraview is not installed")
def test_the_paraview_script_draws_a_body_s_axes(run_cli, root, tmp_path):
    """A body's axes are arrows from its centre along d1, d2, d3 (the cable robot's platform,
    drawn along x, y, z): each reaches 2.5 sphere diameters along its own axis only."""
    out = run_cli("run", str(root / "runs" / "multibody" / "cable_robot.toml"), "--out", "res", "-q",
                  "--set", "analysis.t_end=0.02")
    assert out.returncode == 0, out.stderr
    res = subprocess.run(["/usr/bin/python3", "-c", _BODY_AXES_SCRIPT, str(tmp_path / "res")], capture_output=True,
                         text=True, timeout=300, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    bounds = json.loads(res.stdout.strip().splitlines()[-1])
    length = 2.5 * load_view_script(tmp_path / "res" / "view.py").SPHERE_DIAMETER["bodies"]
    centre = (0.0, 0.0, 1.5)
    for k, axis in enumerate(("d1", "d2", "d3")):
        lo, hi = bounds[axis][2 * k], bounds[axis][2 * k + 1]
        assert hi - centre[k] == pytest.approx(length, rel=1e-3) and lo == pytest.approx(centre[k], abs=1e-3 * length)


def test_guides_read_back_against_the_history(run_cli, root, tmp_path):
    """runs/multibody/ropeway_towers.toml: guides.xdmf has one vertex per guide at its drawn
    point, named in guide order, and each record's s, ds_dt and reaction are the history's
    <rope>_at_<name> columns; the fixed guides do not move."""
    import h5py

    out = run_cli("run", str(root / "runs" / "multibody" / "ropeway_towers.toml"), "--out", str(tmp_path / "r"),
                  "-q", "--set", "analysis.t_end=0.05", "--set", "output.every=1")
    assert out.returncode == 0, out.stderr
    rows = history(tmp_path / "r")
    points, steps = read_series(tmp_path / "r" / "guides.xdmf")
    assert points == pytest.approx(np.array([[40.0, 0.0, 3.0], [80.0, 0.0, 3.0]]), abs=1e-12)
    assert len(steps) == len(rows) == 6
    with h5py.File(tmp_path / "r" / "guides.h5") as f:
        assert [n.decode() if isinstance(n, bytes) else n for n in f["mesh"].attrs["guide_names"]] == ["tower1", "tower2"]
    for (t, data), row in zip(steps, rows):
        assert t == pytest.approx(float(row["t"]), abs=1e-15)
        for i, name in enumerate(("tower1", "tower2")):
            prefix = f"track_at_{name}"
            assert data["s"][i] == pytest.approx(float(row[f"{prefix}.s"]), abs=1e-12)
            assert data["ds_dt"][i] == pytest.approx(float(row[f"{prefix}.ds_dt"]), abs=1e-12)
            assert data["reaction"][i] == pytest.approx([float(row[f"{prefix}.reaction.{c}"]) for c in "xyz"], rel=1e-12)
            assert np.abs(data["displacement"][i]).max() < 1e-12
