# SPDX-License-Identifier: MIT
"""Rigid bodies ([[body]], issue 37 item 1): a free body flipping about its intermediate axis
keeps energy and angular momentum under energy-momentum; a body hung from a point by a joint
swings at the compound pendulum's frequency; the step Jacobian against finite differences under
every integrator; one rank = two; and the scene's errors."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import slidebeam
from checks import distributed_and_serial_records, step_jacobian_error, trial_end_state

# the pendulums' spins are projected onto the joint on purpose (a velocity the joint takes away)
pytestmark = pytest.mark.filterwarnings("ignore::slidebeam.ConstraintWarning")

INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
STIFF = {"EA": 1e8, "kGA": 1e8, "GJ": 1e6, "EI2": 1e6, "EI3": 1e6, "rhoA": 1.0, "rhoI2": 1e-6, "rhoI3": 1e-6}
MASS, INERTIA, ARM = 2.0, [0.1, 0.2, 0.15], 0.5  # the hanging body: kg, kg m^2, pivot above its centre (m)


def free_body(t_end: float = 8.0, dt: float = 0.01) -> slidebeam.Scene:
    """A body with principal moments 1, 2, 3 spinning about its intermediate axis (y), slightly off."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "dt": dt, "t_end": t_end},
        "beam": [{"name": "ground", "start": [5, 0, 0], "end": [6, 0, 0], "spans": 1, "section": STIFF}],
        "support": [{"type": "clamp", "beam": "ground", "at": "start"}],
        "body": [{"name": "box", "mass": 3.0, "inertia": [1.0, 2.0, 3.0], "position": [0, 0, 0],
                  "orientation": [0.1, -0.2, 0.3], "angular_velocity": [0.01, 2.0, 0.01], "velocity": [0.2, 0, 0]}],
        "output": {"every": 1},
    })


def test_a_free_body_flips_about_its_intermediate_axis_keeping_energy_and_momentum():
    """The tennis-racket flip: the axis of the middle moment turns over while energy and angular
    momentum stay constant to the Newton tolerance (1e-10 of the kinetic energy, 1e-12)."""
    sim = slidebeam.Simulation(free_body())
    body = sim.scene.bodies[0]
    axis0 = np.array(body.frame[1])  # d2 in the drawing: the intermediate axis
    turns: list[float] = []
    run = sim.run_dynamic(on_step=lambda r: turns.append(float(sim.control_points(body.index)[0, 6:9] @ axis0)))
    assert run.complete, run.message
    H = np.array([r.total_energy for r in run.records])
    J = np.array([r.angular_momentum for r in run.records])
    assert np.abs(H - H[0]).max() <= 1e-10 * H[0]
    assert np.abs(J - J[0]).max() <= 1e-12 * np.linalg.norm(J[0])
    assert min(turns) < -0.9  # it flipped
    centre = np.array([r.tracked[-1] for r in run.records])  # the body is tracked at its centre of mass
    t = np.array([r.t for r in run.records])
    assert np.abs(centre[:, 0] - 0.2 * t).max() < 1e-10


def pendulum(joint: str = "spherical", integrator: str = "energy-momentum", swing: float = 0.05,
             t_end: float = 4.0, dt: float = 0.005) -> slidebeam.Scene:
    """The body's point ARM above its centre joined to the end of a stiff clamped stub."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": dt, "t_end": t_end},
        "beam": [{"name": "stub", "start": [-0.2, 0, 0], "end": [0, 0, 0], "spans": 2, "section": STIFF}],
        "support": [{"type": "clamp", "beam": "stub", "at": "start"}],
        "body": [{"name": "bob", "mass": MASS, "inertia": INERTIA, "position": [0, 0, -ARM],
                  "angular_velocity": [0.3, swing, 0.2] if joint == "spherical" else [0, swing, 0],
                  "velocity": [swing * -ARM, 0, 0] if joint != "spherical" else [0, 0, 0]}],
        "joint": [{"type": joint, "beams": ["stub", "bob"], "at": ["end", [0, 0, 0]],
                   **({"axis": [0, 1, 0]} if joint == "revolute" else {})}],
        "gravity": {"g": [0, 0, -9.81]},
    })


def test_a_hanging_body_swings_at_the_compound_pendulum_frequency():
    """Period 2 pi sqrt((Iyy + m a^2) / (m g a)) on a revolute joint, to 2e-4 (amplitude 0.025
    rad: theta^2 / 16 = 4e-5)."""
    run = slidebeam.Simulation(pendulum("revolute", t_end=3.0)).run_dynamic()
    assert run.complete, run.message
    t = np.array([r.t for r in run.records])
    x = np.array([r.tracked[-1][0] for r in run.records])
    up = [t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i]) for i in range(len(x) - 1) if x[i] < 0 <= x[i + 1]]
    period = float(np.mean(np.diff(up)))
    exact = 2 * math.pi * math.sqrt((INERTIA[1] + MASS * ARM ** 2) / (MASS * 9.81 * ARM))
    assert len(up) >= 2 and abs(period / exact - 1) < 2e-4, (period, exact)


@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("joint", ("spherical", "revolute", "rigid"))
def test_step_jacobian_matches_finite_differences(joint, integrator):
    sim = slidebeam.Simulation(pendulum(joint, integrator, swing=0.5, t_end=0.1, dt=0.01))
    x1 = trial_end_state(sim, steps=2, h=0.01, seed=5)
    x1.assemble()
    worst, scale = step_jacobian_error(sim, x1)
    assert worst <= 1e-6 * scale, f"{joint}, {integrator}: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"
    (k,) = [k for k, e in enumerate(sim.active_effects) if e.type.endswith("_joint")]
    first = sim._model.extra_offset(k)
    rows = list(range(first, first + {"spherical": 3, "revolute": 5, "rigid": 6}[joint]))
    body = sim.first_control_point(sim.scene.bodies[0].index)
    base, n = sim.control_point_unknowns(body)
    rows += list(range(base, base + n + 6))  # the body's coordinates and orthonormality multipliers
    worst, scale = step_jacobian_error(sim, x1, rows=rows)
    assert scale > 0.1 and worst <= 1e-6 * scale, f"{joint}, {integrator}: body |J - FD| = {worst:.3e}"


def test_energy_momentum_keeps_a_swinging_body_s_energy():
    """Energy to the Newton tolerance: 2e-12 of |H| at an absolute tolerance of 1e-13 (9e-10 at
    the default 1e-10, all of it in the first steps, where the stiff stub takes the weight)."""
    scene = pendulum("spherical", swing=0.8, t_end=2.0, dt=0.01)
    scene = dataclasses.replace(scene, petsc_options={"snes_atol": "1e-13", "snes_rtol": "1e-14"})
    run = slidebeam.Simulation(scene).run_dynamic()
    assert run.complete, run.message
    H = np.array([r.total_energy for r in run.records])
    assert np.abs(H - H[0]).max() <= 1e-11 * abs(H[0])
    assert max(r.constraint_residual for r in run.records) < 1e-9


def test_bodies_run_alike_on_one_and_two_ranks():
    distributed_and_serial_records(pendulum("spherical", swing=0.5, t_end=0.1, dt=0.01))


@pytest.mark.parametrize("body, words", [
    ({"inertia": [1.0, 1.0, 3.0]}, ["[[body]] #1", "'inertia'", "triangle"]),
    ({"inertia": [1.0, 2.0]}, ["[[body]] #1", "'inertia'", "Ixx"]),
    ({"mass": 0.0}, ["[[body]] #1", "'mass'", "> 0"]),
    ({"name": "stub"}, ["[[body]] #1", "'name'", "duplicate"]),
])
def test_body_errors_name_the_table_and_key(body, words):
    data = {"analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
            "beam": [{"name": "stub", "start": [-0.2, 0, 0], "end": [0, 0, 0], "spans": 2, "section": STIFF}],
            "body": [{"name": "bob", "mass": 1.0, "inertia": [0.1, 0.1, 0.1], "position": [0, 0, -1], **body}]}
    with pytest.raises(slidebeam.SceneError) as err:
        slidebeam.scene_from_dict(data)
    assert all(w in str(err.value) for w in words), str(err.value)


def test_a_body_has_no_ends_for_a_rigid_joint():
    data = {"analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
            "beam": [{"name": "stub", "start": [-0.2, 0, 0], "end": [0, 0, 0], "spans": 2, "section": STIFF}],
            "body": [{"name": "bob", "mass": 1.0, "inertia": [0.1, 0.1, 0.1], "position": [0, 0, -1]}],
            "rigid_joint": [{"beams": ["stub", "bob"], "at": ["end", "start"]}]}
    with pytest.raises(slidebeam.SceneError, match="beam 'bob' does not exist|no ends"):
        slidebeam.scene_from_dict(data)
