# SPDX-License-Identifier: MIT
"""Error-controlled steps ([analysis] adapt, src/time/error_control.hpp): the error at t_end
follows the tolerance, energy-momentum stays exact at every step size, bad input is named."""
from __future__ import annotations

import pathlib

import numpy as np
import pytest
from mpi4py import MPI

import slidebeam
from slidebeam import scene

ROOT = pathlib.Path(__file__).resolve().parents[2]
PENDULUM = ROOT / "runs" / "soft_pendulum.toml"
T_END = 0.3


def _final(sets: list[str]) -> tuple[np.ndarray, slidebeam.Simulation, object]:
    sc = scene.load_scene(PENDULUM, [f"analysis.t_end={T_END}", "output.every=1", *sets])
    sim = slidebeam.Simulation(sc, MPI.COMM_SELF)
    out = sim.run_dynamic()
    assert out.complete, out.message
    return sim.x.getArray().copy(), sim, out


def _global_error(x: np.ndarray, ref: np.ndarray, sim: slidebeam.Simulation) -> float:
    """The controller's norm: points / the beam's length (1 m), directors as they are."""
    first = sim.first_control_point(0)
    err = 0.0
    for c in range(sim.control_points(0).shape[0]):
        base, nq = sim.control_point_unknowns(first + c)
        err = max(err, float(np.abs(x[base:base + nq] - ref[base:base + nq]).max()))
    return err


@pytest.fixture(scope="module")
def reference() -> np.ndarray:
    return _final(["analysis.dt=5e-5"])[0]


@pytest.mark.parametrize("rtol", [1e-3, 1e-4])
def test_error_at_t_end_follows_the_tolerance(reference, rtol):
    x, sim, out = _final([f"analysis.adapt={{rtol={rtol}}}"])
    err = _global_error(x, reference, sim)
    assert 0.1 * rtol < err < 10 * rtol, (rtol, err)
    dts = [r.dt for r in out.records[1:]]
    assert len(set(dts)) > 2 and max(dts) > 2 * min(dts)  # the steps follow the error, not dt


def test_energy_momentum_stays_exact_at_every_step_size():
    _, _, out = _final(["analysis.adapt={rtol=1e-3}"])
    recs = out.records
    assert len({r.dt for r in recs[1:]}) > 3
    kinetic = max(r.kinetic_energy for r in recs)
    e0 = recs[0].total_energy
    assert max(abs(r.total_energy - e0) for r in recs) < 1e-10 * kinetic
    assert max(r.energy_balance_error for r in recs) < 1e-10 * kinetic


def test_a_tolerance_that_cannot_be_met_above_dt_min_fails_clearly():
    sc = scene.load_scene(PENDULUM, ["analysis.adapt={rtol=1e-9}", "analysis.dt=1e-2", "analysis.dt_min=5e-3"])
    out = slidebeam.Simulation(sc, MPI.COMM_SELF).run_dynamic()
    assert not out.complete and out.failed
    assert "the error control failed" in out.message and "times the tolerance" in out.message


@pytest.mark.parametrize("sets, key, words", [
    (["analysis.type=\"static\"", "analysis.adapt={rtol=1e-3}"], "adapt", 'type = "dynamic" only'),
    (["analysis.adapt={rtol=2.0}"], "rtol", "in (0, 1)"),
    (["analysis.adapt={rtol=1e-3, atol=-1}"], "atol", "> 0"),
    (["analysis.adapt={rtol=1e-3, dtmax=1}"], "dtmax", "did you mean 'dt_max'"),
    (["analysis.adapt={rtol=1e-3, dt_max=1e-3}", "analysis.dt=1e-2"], "dt", "must not exceed adapt.dt_max"),
])
def test_bad_adapt_tables_are_named(sets, key, words):
    with pytest.raises(scene.SceneError) as info:
        scene.load_scene(PENDULUM, sets)
    text = str(info.value)
    assert "soft_pendulum.toml" in text and key in text and words in text, text
