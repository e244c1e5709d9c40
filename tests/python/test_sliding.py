# SPDX-License-Identifier: MIT
"""Sliding joint (issue 4): exact step Jacobians with s on either side of knots, energy through
element transitions (exact discrete derivative against the seed's midpoint form), constraint
residuals, the carrier end, input errors, and distributed == serial."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import slidebeam
from checks import check_joint_step_jacobian, distributed_and_serial_records

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "runs" / "seed"
INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
NEWTON_ATOL = 1e-10  # the SNES absolute tolerance (solvers/newton.cpp)


def seed_scene(name: str = "free_fall_inclined_1+4", **sets: object) -> slidebeam.Scene:
    return slidebeam.load_scene(SEED / f"{name}.toml", [f"{k}={v}" for k, v in sets.items()])


@pytest.mark.parametrize("joint_form", ("frame", "spatial"))
@pytest.mark.parametrize("integrator,form", [(i, "exact") for i in INTEGRATORS] + [("energy-momentum", "midpoint")])
@pytest.mark.parametrize("ds", [0.03, 0.17, 0.71])  # same span; across the knot at 0.5; across 0.5 and 1.0
def test_step_jacobian_is_exact_across_knots(integrator, form, ds, joint_form):
    """s_n = 0.4 and s_n+1 = s_n + ds: the span of s is found at every evaluation and the
    Jacobian stays the derivative of the step residual (finite differences), for the
    frame-projected joint (the default) and the spatial one."""
    sim = slidebeam.Simulation(seed_scene(**{"analysis.integrator": integrator, "analysis.dt": 0.01,
                                             "sliding_joint.0.discrete_gradient": form,
                                             "sliding_joint.0.form": f'"{joint_form}"'}))
    check_joint_step_jacobian(sim, ds, f"{integrator}/{form}/{joint_form}")


def energy_run(form: str):
    sim = slidebeam.Simulation(seed_scene(**{"sliding_joint.0.discrete_gradient": form}))
    run = sim.run_dynamic()
    H = np.array([r.total_energy for r in run.records])
    K = max(r.kinetic_energy for r in run.records)
    s = np.array([r.joints[0].s for r in run.records])
    return run, H, K, s


@pytest.fixture(scope="module")
def transition_runs():
    return {form: energy_run(form) for form in ("exact", "midpoint")}


def test_energy_momentum_conserves_energy_through_element_transitions(transition_runs):
    """S2-incl, 1+4 mesh, dt = 1e-3: C crosses the knots at 0.5, 1.0 and 1.5 and reaches the
    carrier end. With the exact discrete derivative the total energy stays within 10x the Newton
    tolerance of its start, relative to the largest kinetic energy."""
    run, H, K, s = transition_runs["exact"]
    assert not run.complete and not run.failed and "reached the end of carrier 'AB'" in run.message
    assert all(s.min() < knot < s.max() for knot in (0.5, 1.0, 1.5))
    drift = np.abs(H - H[0]).max() / K
    assert drift <= 10 * NEWTON_ATOL, f"energy drift {drift:.3e} of the largest kinetic energy {K:.3g}"
    assert max(r.constraint_residual for r in run.records) <= NEWTON_ATOL


def test_seed_midpoint_form_does_not_conserve_energy(transition_runs):
    """The same run with the seed's midpoint-evaluated derivative: same motion, but the joint
    does work, far outside the conserving scheme's band."""
    exact_run, H_exact, K, s_exact = transition_runs["exact"]
    run, H, K_mid, s = transition_runs["midpoint"]
    n = min(len(s), len(s_exact))
    assert np.abs(s[:n] - s_exact[:n]).max() < 1e-5  # the same motion, to the scheme's error
    drift = np.abs(H - H[0]).max() / K_mid
    exact_drift = np.abs(H_exact - H_exact[0]).max() / K
    assert drift > 10 * (10 * NEWTON_ATOL) and drift > 1e4 * exact_drift, (drift, exact_drift)
    assert max(r.constraint_residual for r in run.records) <= NEWTON_ATOL


def test_distributed_equals_serial():
    """Meaningful under mpirun -n 2: the carrier's control points and the joint's unknowns live on
    different ranks."""
    for a, b in distributed_and_serial_records(seed_scene("free_fall_1+4", **{"analysis.t_end": 0.2})):
        assert abs(a.joints[0].s - b.joints[0].s) < 1e-10
        assert np.abs(np.array(a.joints[0].reaction) - np.array(b.joints[0].reaction)).max() < 1e-8


def test_initial_s_is_the_closest_point_and_at_rest():
    sim = slidebeam.Simulation(seed_scene("free_fall_1+4"))
    j = sim.joint_states()[0]
    assert j.s == pytest.approx(0.4, abs=1e-12)
    assert j.ds_dt == 0.0


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_every_integrator_runs_the_joint(integrator):
    """Short run: constraints at solver tolerance, C moves along AB towards mid-span."""
    sim = slidebeam.Simulation(seed_scene("free_fall_1+4", **{"analysis.integrator": integrator,
                                                            "analysis.t_end": 0.1}))
    run = sim.run_dynamic()
    assert run.complete
    assert max(r.constraint_residual for r in run.records) <= NEWTON_ATOL
    assert run.records[-1].joints[0].s > 0.4


def test_slider_off_its_carrier_is_a_scene_error():
    with pytest.raises(slidebeam.SceneError, match=r"sliding_joint\]\] #1.*from carrier 'AB'"):
        slidebeam.Simulation(seed_scene("free_fall_1+4", **{"beam.CM.start": "[0.4, 0.01, 0.0]"}))


def test_the_stepper_locates_the_carrier_end_as_an_event():
    """The core's Stepper knows the sliding joint's two indicators (s and L - s, scale L) without
    being told of sliding joints, takes steps until one crosses, and ends with a step shortened
    so that the slider lies within 1e-9 L inside the carrier's end (the inclined seed: C reaches
    B at t = 0.8137 s, in its 814th step). Before the crossing every call is one accepted step of dt."""
    from slidebeam import _core

    sim = slidebeam.Simulation(seed_scene(**{"analysis.t_end": 2.0}))
    (joint,) = sim.sliding_joint_effects()
    length = sim.scene.beams[sim.scene.sliding_joints[0].carrier].geometry.length
    stepper = _core.Stepper(sim._model, sim.integrator, 1e-3, 1e-3 / 16)
    assert stepper.events == [(joint, 0, length), (joint, 1, length)]
    steps = 0
    while True:
        adv = stepper.advance(2.0)
        if adv.status != "accepted":
            break
        assert adv.h == 1e-3 and adv.newton_iterations == adv.result.iterations
        steps += 1
    assert adv.status == "event" and stepper.events[adv.event][1] == 1 and adv.event_step_taken
    assert 0.0 < adv.h < 1e-3 and steps == 813
    s = sim.joint_states()[0].s
    assert 0.0 <= length - s <= 1e-9 * length
