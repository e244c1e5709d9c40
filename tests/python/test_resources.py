# SPDX-License-Identifier: MIT
"""Absurd sizes (issue 22, item 7): a scene that cannot fit in memory is refused before anything
is allocated, naming the key, what it would need and what the machine has; scenes that fit are
not refused; the estimate counts what the run allocates."""
from __future__ import annotations

import re
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import slidebeam
from slidebeam.run import resources
from slidebeam.scene import SceneError

ROOT = Path(__file__).resolve().parents[2]
ROLLUP = ROOT / "runs" / "rollup.toml"
NEED = re.compile(r"need about ([0-9.e+]+) (kB|MB|GB|TB) of memory")
HAVE = re.compile(r"has ([0-9.e+]+) (kB|MB|GB|TB) available")


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("command", ("run", "check"))
def test_a_billion_spans_is_refused_at_once(run_cli, tmp_path, command):
    started = time.perf_counter()
    args = ["--out", "res"] if command == "run" else []
    out = run_cli(command, str(ROLLUP), *args, "--set", "beam.0.spans=1000000000", timeout=60)
    elapsed = time.perf_counter() - started
    assert out.returncode == 2, out.stderr
    assert elapsed < 10
    assert "Traceback" not in out.stderr
    assert "rollup.toml: [[beam]] #1 ('strip'), key 'spans': 1000000000 spans" in out.stderr
    assert NEED.search(out.stderr) and NEED.search(out.stderr).group(2) == "TB"
    assert HAVE.search(out.stderr) and "MemAvailable" in out.stderr
    assert not (tmp_path / "res").exists()  # refused before the output folder


@pytest.mark.skip_in_parallel
@pytest.mark.spawns_ranks
def test_refused_once_under_mpirun(run_cli, tmp_path):
    out = run_cli("run", str(ROLLUP), "--out", "res", "--set", "beam.0.spans=1000000000", np=2, timeout=60)
    assert out.returncode == 2, out.stderr
    assert out.stderr.count("key 'spans'") == 1 and "(2 ranks)" in out.stderr
    assert "Traceback" not in out.stderr


@pytest.mark.skip_in_parallel
def test_a_scene_that_fits_is_not_refused(run_cli, tmp_path):
    out = run_cli("check", str(ROLLUP))
    assert out.returncode == 0, out.stderr
    assert re.search(r"memory: about [0-9.]+ MB of [0-9.]+ GB available \(\d+ unknowns\)", out.stdout)
    out = run_cli("run", str(ROLLUP), "--out", "res", "-q", "--set", "analysis.steps=2", "--set", "beam.0.spans=2000",
                  "--set", "load.0.value=[0,0,0.5]")
    assert out.returncode == 0, out.stderr


def every_shipped_scene() -> list[Path]:
    return sorted(p for p in (ROOT / "runs").rglob("*.toml") if "studies" not in p.parts)


def test_no_shipped_scene_is_refused():
    for path in every_shipped_scene():
        est = resources.check_memory(slidebeam.load_scene(path))
        assert est.total < 100e6, path


@pytest.mark.parametrize("scene, sets", [("rollup.toml", []), ("pendulum16_ancf.toml", []),
                                         ("seed/free_fall_1+4.toml", []), ("cables/ropeway.toml", [])])
def test_estimate_counts_the_model_unknowns(scene, sets):
    sc = slidebeam.load_scene(ROOT / "runs" / scene, sets)
    est = resources.estimate(sc)
    actual = slidebeam.Simulation(sc).x.getSize()
    extras = sum(1 for e in sc.effects if e.table in ("support", "rigid_joint", "sliding_joint"))
    assert actual <= est.unknowns <= actual + resources.UNKNOWNS_PER_EXTRA * extras


def test_the_largest_contributor_is_named(monkeypatch):
    """With little memory available, each kind of size is refused under its own key."""
    monkeypatch.setattr(resources, "available_memory", lambda: (50_000_000, "test"))
    cases = [(ROLLUP, ["beam.0.spans=100000"], "[[beam]] #1 ('strip')", "spans"),
             (ROLLUP, ["output.samples_per_span=100000"], "[output]", "samples_per_span"),
             (ROLLUP, ["analysis.steps=100000"], "[analysis]", "steps"),
             (ROOT / "runs" / "seed" / "free_fall_1+4.toml", ["analysis.dt=1e-9"], "[analysis]", "dt")]
    for path, sets, table, key in cases:
        with pytest.raises(SceneError) as err:
            resources.check_memory(slidebeam.load_scene(path, sets))
        assert (err.value.table, err.value.key) == (table, key), str(err.value)
        assert "has 50 MB available (test)" in str(err.value)
        with pytest.raises(SceneError):  # a Simulation refuses before it allocates
            slidebeam.Simulation(slidebeam.load_scene(path, sets))
    resources.check_memory(slidebeam.load_scene(ROLLUP))  # 10 MB: fits


def test_unknowns_beyond_32_bit_indices_are_refused_even_with_memory(monkeypatch):
    monkeypatch.setattr(resources, "available_memory", lambda: (10**30, "test"))
    with pytest.raises(SceneError) as err:
        resources.check_memory(slidebeam.load_scene(ROLLUP, ["beam.0.spans=200000000"]))
    assert err.value.key == "spans" and "32-bit" in str(err.value)


def test_reference_geometry_needs_memory_linear_in_the_spans():
    """The B-spline collocation is a banded solve: at 4000 spans a dense one took 128 MB."""
    from slidebeam.run.geometry import reference_coordinates

    for path in (ROLLUP, ROOT / "runs" / "bend45.toml", ROOT / "runs" / "right_angle_cantilever.toml"):
        beam = slidebeam.load_scene(path).beams[0]
        q = reference_coordinates(beam)
        # the control points interpolate the reference curve at the Greville abscissae
        from slidebeam import _core

        for a in (0, 1, beam.spans // 2, beam.spans + 1):
            xi = _core.greville(beam.spans, a)
            span, N, _, _ = _core.bspline_basis(beam.spans, xi)
            point = np.asarray(N) @ q[span:span + 3, :3]
            assert np.allclose(point, beam.geometry.point_at(xi * beam.geometry.length), atol=1e-12)
    beam = slidebeam.load_scene(ROLLUP, ["beam.0.spans=4000"]).beams[0]
    tracemalloc.start()
    try:
        reference_coordinates(beam)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 20e6
