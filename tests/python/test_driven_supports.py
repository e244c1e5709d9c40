# SPDX-License-Identifier: MIT
"""Driven supports ([[support]] motion = {displacement, rotation, time_function}): the held
point follows its motion exactly, statically and in time steps; the work the support does is
recorded (W) and the energy balance closes under energy-momentum; step Jacobians against finite
differences under every integrator."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from mpi4py import MPI

import slidebeam
from checks import check_step_jacobian
from test_dynamics import INTEGRATORS, everything_scene

RAMP = {"type": "ramp", "t0": 0.0, "t1": 1.0}


def test_a_turning_clamp_turns_a_free_cantilever_rigidly():
    """Statics, no load: a clamp turned by 90 degrees about z and moved by u carries the beam
    with it rigidly; the tip lands at X0 + u + R (tip0 - X0) to the solver tolerance."""
    u = [0.1, -0.2, 0.3]
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "static", "steps": 8},
        "beam": [{"name": "rod", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 8,
                  "section": {"EA": 1e4, "kGA": 1e4, "GJ": 10.0, "EI2": 10.0, "EI3": 10.0}}],
        "support": [{"type": "clamp", "beam": "rod", "at": "start",
                     "motion": {"displacement": u, "rotation": [0.0, 0.0, math.pi / 2], "time_function": RAMP}}],
    })
    sim = slidebeam.Simulation(scene)
    records = sim.solve_static()
    assert records[-1].converged and records[-1].t == 1.0
    tip = sim.evaluate("rod", 2.0)[0]
    assert np.abs(tip[:3] - (np.array(u) + [0.0, 2.0, 0.0])).max() < 1e-9
    assert np.abs(tip[3:6] - [0.0, 1.0, 0.0]).max() < 1e-9  # d1 turned with the clamp
    assert records[-1].strain_energy < 1e-16


def driven(integrator: str) -> slidebeam.Scene:
    """The every-effect scene at rest, its clamp driven (displaced and turned) and its interior
    spherical support driven."""
    data = dict(everything_scene(integrator, "full").data)
    data["beam"] = [{k: v for k, v in b.items() if k not in ("velocity", "angular_velocity")} for b in data["beam"]]
    hat = {"type": "hat", "t0": 0.0, "t1": 0.3, "t2": 0.6}
    data["support"] = [
        {"type": "clamp", "beam": "b", "at": "start",
         "motion": {"displacement": [0.05, 0.0, 0.02], "rotation": [0.0, 0.1, 0.2], "time_function": hat}},
        {"type": "spherical", "beam": "b", "at": 0.9,
         "motion": {"displacement": [0.0, 0.03, -0.02], "time_function": RAMP}},
    ]
    return slidebeam.scene_from_dict(data)


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_driven_support_step_jacobian_matches_finite_differences(integrator):
    sim = slidebeam.Simulation(driven(integrator))
    check_step_jacobian(sim, steps=1, h=0.05, seed=5, label=integrator)


def test_driven_supports_follow_their_motion_and_the_balance_closes():
    """Energy-momentum: the clamp's control point sits at X0 + f(t) U after every step, the
    supports' work is in W (per support in `<label>.work`), and |H - H0 - W + D| stays at the
    Newton tolerance."""
    scene = driven("energy-momentum")
    scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, t_end=1.0, dt=0.01))
    sim = slidebeam.Simulation(scene)
    records = sim.run_dynamic().records
    labels = sim.energy_flow_labels()
    assert "clamp[b@start].work" in labels and "spherical[b@s=0.9].work" in labels
    K = max(r.kinetic_energy for r in records)
    assert max(abs(w) for r in records for w in r.flows) > 1e-3 * K
    worst = max(r.energy_balance_error for r in records)
    assert worst <= 1e-9 * K, f"|H - H0 - W + D| = {worst:.3e} of max K {K:.3e}"
    start = sim.evaluate("b", 0.0)[0, :3]
    assert np.abs(start - np.array([0.0, 0.0, 0.0])).max() < 1e-12  # the hat is back to 0 at t = 1
    p = sim.evaluate("b", 0.9)[0, :3]
    ref = slidebeam.Simulation(driven("energy-momentum")).evaluate("b", 0.9)[0, :3]
    assert np.abs(p - (ref + [0.0, 0.03, -0.02])).max() < 1e-9


def test_a_motion_must_start_at_zero():
    data = dict(driven("energy-momentum").data)
    data["support"] = [{"type": "clamp", "beam": "b", "at": "start",
                        "motion": {"displacement": [0.1, 0, 0], "time_function": {"type": "constant"}}}]
    with pytest.raises(slidebeam.SceneError, match="must start from the drawn state"):
        slidebeam.scene_from_dict(data)
