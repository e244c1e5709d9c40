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


def test_the_steps_start_small_and_grow():
    """The first two steps have no estimate: they are 1/100 of the first step asked for."""
    _, _, out = _final(["analysis.adapt={rtol=1e-3}", "analysis.dt=1e-2"])
    dts = [r.dt for r in out.records[1:]]
    assert dts[0] == pytest.approx(1e-4, rel=1e-12) and dts[1] == dts[0]
    assert max(dts) > 10 * dts[0]


def test_adapt_false_means_fixed_steps():
    sc = scene.load_scene(PENDULUM, ["analysis.adapt=false", "analysis.dt=1e-2"])
    assert sc.analysis.adapt is None and sc.analysis.dt == 1e-2


SEED = ROOT / "runs" / "seed" / "free_fall_1+4.toml"


def _seed(sets: list[str]):
    sc = scene.load_scene(SEED, ["analysis.t_end=0.5", "output.every=1000000", "analysis.dt_min=1e-12", *sets])
    sim = slidebeam.Simulation(sc, MPI.COMM_SELF)
    out = sim.run_dynamic()
    assert out.complete, out.message
    points = [i for b in range(2) for c in range(sim.control_points(b).shape[0])
              for i in range(sim.control_point_unknowns(sim.first_control_point(b) + c)[0],
                             sim.control_point_unknowns(sim.first_control_point(b) + c)[0] + 3)]
    return sim.x.getArray()[points].copy(), out


def test_a_stiff_mode_below_the_tolerance_asks_for_no_small_steps():
    """The seed's steel beams vibrate axially far above the motion, with amplitudes below the
    tolerance: the estimate's oscillation bound keeps them from setting the step (without it, the
    whole run at rtol = 1e-3 took 7173 steps; 2892 with it). The work stays within 1.6x of the
    fixed step of the same error (error ~ h^2)."""
    ref, _ = _seed(["analysis.dt=2.5e-5"])
    fixed, fixed_out = _seed(["analysis.dt=3e-4"])
    adapt, out = _seed(["analysis.adapt={rtol=1e-3}"])
    err = float(np.abs(adapt - ref).max()) / 2.0  # over the carrier's length
    assert 0.1e-3 < err < 10e-3, err
    fixed_err = float(np.abs(fixed - ref).max()) / 2.0
    assert out.steps < 1.6 * fixed_out.steps * (fixed_err / err) ** 0.5, (out.steps, fixed_out.steps, err, fixed_err)


def test_a_small_step_converges_at_the_residuals_rounding_level():
    """At h = 2e-6 the ropeway's step residual cannot fall below eps |J| |x| (the inertia's
    2 M / h^2 times the coordinates' roundoff), 1e-3 of its initial value: Newton stops there
    instead of failing the step."""
    sc = scene.load_scene(ROOT / "runs" / "cables" / "ropeway.toml",
                          ["analysis.dt=2e-6", "analysis.t_end=6e-6", "output.every=1"])
    out = slidebeam.Simulation(sc, MPI.COMM_SELF).run_dynamic()
    assert out.complete and out.rejected_steps == 0, out.message
    assert all(r.newton_iterations <= 6 for r in out.records[1:])


def test_a_slack_rope_snaps_taut_without_a_step_of_its_own():
    """runs/cables/snap.toml gives no dt: the steps are large while the mass falls and the
    rope is slack, and some thousand times smaller in the snap; the energy balance (the
    rope's damping dissipates) closes to the Newton tolerance through it."""
    sc = scene.load_scene(ROOT / "runs" / "cables" / "snap.toml", ["analysis.t_end=0.65", "output.every=1"])
    out = slidebeam.Simulation(sc, MPI.COMM_SELF).run_dynamic()
    assert out.complete, out.message
    recs = out.records
    dts = [r.dt for r in recs[1:]]
    assert max(dts) > 1e-3 and max(dts) > 1000 * min(dts), (min(dts), max(dts))
    kinetic = max(r.kinetic_energy for r in recs)
    assert max(r.energy_balance_error for r in recs) < 1e-8 * kinetic
    tension = [float(np.linalg.norm(r.reactions[0].force)) for r in recs]
    peak = int(np.argmax(tension))
    assert recs[peak].t > 0.5 and tension[peak] > 1000.0, (recs[peak].t, tension[peak])  # the snap: kN, not 20 N
    assert recs[peak].dt < 0.1 * max(dts)


def test_records_by_time_under_adapt():
    """Without output.every an adaptive run records about 200 times, at the first step that
    reaches each multiple of t_end / 200 (output.interval); a given interval is kept the same
    way, and every together with interval is refused."""
    data = scene.load_scene(PENDULUM, [f"analysis.t_end={T_END}", "analysis.adapt={rtol=1e-4}"]).data
    data["output"].pop("every")
    sc = scene.scene_from_dict(data, str(PENDULUM), PENDULUM.parent)
    assert sc.output.interval == pytest.approx(T_END / 200)
    for s in (sc, scene.scene_from_dict({**data, "output": {**data["output"], "interval": 0.02}}, str(PENDULUM),
                                        PENDULUM.parent)):
        interval = s.output.interval
        out = slidebeam.Simulation(s, MPI.COMM_SELF).run_dynamic()
        assert out.complete, out.message
        t = np.array([r.t for r in out.records])
        assert t[-1] == pytest.approx(T_END) and out.steps > len(t)  # fewer records than steps
        due = (np.floor(t[:-2] / interval + 1e-9) + 1) * interval  # the multiple after each record
        h = np.array([r.dt for r in out.records[1:-1]])
        assert np.all(t[1:-1] >= due - 1e-12) and np.all(t[1:-1] - h < due - 1e-12), (t, due)  # its first step
        assert len(t) <= T_END / interval + 2
    with pytest.raises(scene.SceneError) as info:
        scene.load_scene(PENDULUM, ["output.interval=0.01"])  # the scene has every = 10
    assert info.value.key == "interval" and "not both" in str(info.value)
