# SPDX-License-Identifier: MIT
"""Joints to a point fixed in space (issue 37 item 2): [[support]] type = "revolute" (a pin),
"universal", and a clamp inside a beam or on a body. The step Jacobian against finite
differences under every integrator; energy exact under energy-momentum; a rod pinned inside its
length swings as the compound pendulum and stays in the pin's plane; a clamped body's reaction is
its weight and the weight's moment; one rank = two; and the scene's errors."""
from __future__ import annotations

import math

import numpy as np
import pytest

import slidebeam
from checks import check_step_jacobian_and_rows, distributed_and_serial_records, drifts, upward_crossings

# the spin about a point the support does not let it turn about: projected onto the support
pytestmark = pytest.mark.filterwarnings("ignore::slidebeam.ConstraintWarning")

INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
SECTION = {"EA": 2e3, "kGA": 1e3, "GJ": 2.0, "EI2": 3.0, "EI3": 4.0, "rhoA": 1.0, "rhoI2": 0.02, "rhoI3": 0.03}
STIFF = {"EA": 1e8, "kGA": 1e8, "GJ": 1e6, "EI2": 1e6, "EI3": 1e6, "rhoA": 1.0, "rhoI2": 1e-8, "rhoI3": 1e-8}
SUPPORTS = {"revolute": {"axis": [0.0, 1.0, 0.0]},
            "universal": {"axis": [1.0, 0.0, 0.0], "axis_b": [0.0, 1.0, 0.0]},
            "clamp": {}}
ORIENTATIONS = {"revolute": 2, "universal": 1, "clamp": 3}


def swinging(kind: str, integrator: str = "energy-momentum", *, t_end: float = 0.3, dt: float = 0.01,
             at: float = 0.7) -> slidebeam.Scene:
    """A flexible beam held at an interior point by the support, spinning about it under
    gravity."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": dt, "t_end": t_end},
        "beam": [{"name": "a", "start": [0.0, 0.0, 0.0], "end": [2.0, 0.0, 0.0], "spans": 6, "section": SECTION,
                  "angular_velocity": [0.3, -0.5, 1.0], "rotation_center": [at, 0.0, 0.0]}],
        "support": [{"type": kind, "beam": "a", "at": at, **SUPPORTS[kind]}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
    })


def support_multipliers(sim, count: int) -> list[int]:
    (k,) = [k for k, e in enumerate(sim.active_effects) if e.type in SUPPORTS]
    first = sim._model.extra_offset(k)
    return list(range(first, first + count))


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("kind", tuple(SUPPORTS))
def test_step_jacobian_matches_finite_differences(kind, integrator):
    sim = slidebeam.Simulation(swinging(kind, integrator))
    check_step_jacobian_and_rows(sim, support_multipliers(sim, 3 + ORIENTATIONS[kind]), seed=5,
                                 label=f"{kind} support, {integrator}")


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_a_clamp_at_a_node_inside_an_ancf_cable_has_the_step_jacobian_of_finite_differences(integrator):
    """It holds the node's position and the direction of its slope (2 constraints), not the
    stretch."""
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": 0.01, "t_end": 0.3},
        "beam": [{"name": "a", "formulation": "ancf", "start": [0.0, 0.0, 0.0], "end": [2.0, 0.0, 0.0], "spans": 6,
                  "section": {"EA": 2e3, "EI": 3.0, "rhoA": 1.0}, "angular_velocity": [0.3, -0.5, 1.0],
                  "rotation_center": [2.0 / 3.0, 0.0, 0.0]}],
        "support": [{"type": "clamp", "beam": "a", "at": 2.0 / 3.0}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
    })
    sim = slidebeam.Simulation(scene)
    check_step_jacobian_and_rows(sim, support_multipliers(sim, 5), seed=5, label=f"clamp in a cable, {integrator}")


@pytest.mark.parametrize("kind", ("revolute", "universal"))
def test_energy_momentum_keeps_the_energy_of_a_beam_swinging_on_the_support(kind):
    run = slidebeam.Simulation(swinging(kind, t_end=1.0, dt=0.02)).run_dynamic()
    assert run.complete, run.message
    assert drifts(run.records)["energy"] <= 1e-9
    assert max(r.constraint_residual for r in run.records) < 1e-9


def pinned_rod(kind: str = "revolute", g_side: float = 2.0) -> slidebeam.Scene:
    """A stiff rod 1.25 m long, pinned 0.25 m below its top end (about y), started swinging."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "dt": 0.005, "t_end": 5.0},
        "beam": [{"name": "rod", "start": [0.0, 0.0, 0.25], "end": [0.0, 0.0, -1.0], "spans": 5, "section": STIFF,
                  "angular_velocity": [0.0, 0.05, 0.0], "rotation_center": [0.0, 0.0, 0.0]}],
        "support": [{"type": kind, "beam": "rod", "at": 0.25, **({"axis": [0, 1, 0]} if kind == "revolute" else {})}],
        "gravity": {"g": [0.0, g_side, -9.81]},
        "output": {"track": [{"beam": "rod", "at": "end"}]},
    })


@pytest.mark.skip_in_parallel
def test_a_rod_pinned_inside_its_length_swings_as_the_compound_pendulum_in_the_pins_plane():
    """Pivot d = 0.375 m above the centre of a rod of length L = 1.25: period
    2 pi sqrt((L^2 / 12 + d^2) / (g d)), to 2e-4 (the amplitude shifts it by 3e-5); gravity
    pulling sideways too, the tip stays in the pin's plane (y within 1e-6), where a spherical
    support lets it swing out."""
    run = slidebeam.Simulation(pinned_rod()).run_dynamic()
    assert run.complete, run.message
    tip = np.array([r.tracked[0] for r in run.records])
    up = upward_crossings(run.records, tracked=0)
    period = float(np.mean(np.diff(up)))
    L, d = 1.25, 0.375
    exact = 2 * math.pi * math.sqrt((L * L / 12 + d * d) / (9.81 * d))
    assert len(up) >= 2 and abs(period / exact - 1) < 2e-4, (period, exact)
    assert np.abs(tip[:, 1]).max() < 1e-6
    free = slidebeam.Simulation(pinned_rod("spherical")).run_dynamic()
    assert max(abs(r.tracked[0][1]) for r in free.records) > 0.05


def clamped_in_the_middle(spans: int, P: float = 0.01) -> tuple[np.ndarray, np.ndarray, slidebeam.Reaction]:
    """A beam 2 m long clamped at s = 1 with a tip force P at its end: (tip, start, reaction)."""
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "static", "steps": 1},
        "beam": [{"name": "a", "start": [-1.0, 0.0, 0.0], "end": [1.0, 0.0, 0.0], "spans": spans, "section": SECTION}],
        "support": [{"type": "clamp", "beam": "a", "at": 1.0}],
        "load": [{"type": "force", "beam": "a", "at": "end", "value": [0.0, -P, 0.0]}],
        "output": {"track": [{"beam": "a", "at": "end"}, {"beam": "a", "at": "start"}]},
    })
    record = slidebeam.Simulation(scene).solve_static()[-1]
    return np.array(record.tracked[0]), np.array(record.tracked[1]), record.reactions[0]


@pytest.mark.skip_in_parallel
def test_a_clamp_inside_a_beam_holds_it_as_a_cantilever():
    """A tip force P on a beam clamped in the middle: the clamp's reaction is exactly P (1e-12)
    and its moment P times the tip's lever (1e-9, Newton's tolerance); the free half bends as the
    cantilever P L^3 / (3 EI) + P L / kGA, converging at first order in the span length (the
    spline's turns are C1 across the clamp, where the exact curvature jumps): the error halves
    from 16 to 32 spans, 5.7 % at 16."""
    P, EI, kGA = 0.01, 4.0, 1e3
    exact = P / (3 * EI) + P / kGA
    errors = []
    for spans in (16, 32):
        tip, start, reaction = clamped_in_the_middle(spans, P)
        errors.append(abs(-tip[1] / exact - 1))
        assert np.allclose(reaction.force, [0.0, P, 0.0], rtol=0, atol=1e-12 * P)
        assert abs(reaction.moment[2] - P * tip[0]) < 1e-9 * P
    assert errors[0] < 0.06 and 1.8 < errors[0] / errors[1] < 2.2, errors


def test_a_body_clamped_by_a_point_carries_its_weight_and_its_moment():
    """A 3 kg body clamped 0.5 m off its centre: the clamp holds it up against its weight and
    against the weight's moment about the clamp, and the body does not move (1e-12)."""
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.1},
        "beam": [{"name": "post", "start": [0.0, 0.0, -2.0], "end": [0.0, 0.0, -1.0], "spans": 2, "section": SECTION}],
        "body": [{"name": "box", "mass": 3.0, "inertia": [0.1, 0.2, 0.3], "position": [0.5, 0.0, 0.0]}],
        "support": [{"type": "clamp", "beam": "box", "at": [0.0, 0.0, 0.0]},
                    {"type": "clamp", "beam": "post", "at": "start"}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
        "output": {"track": [{"body": "box"}]},
    })
    run = slidebeam.Simulation(scene).run_dynamic()
    assert run.complete, run.message
    box = run.records[-1]
    assert np.abs(np.subtract(box.tracked[0], [0.5, 0.0, 0.0])).max() < 1e-12
    reaction = box.reactions[0]
    w = 3.0 * 9.81
    assert np.allclose(reaction.force, [0.0, 0.0, w], rtol=1e-9), reaction.force
    # the clamp holds the body: on the body, M = -(lever x weight) with the lever 0.5 e_x
    assert np.allclose(reaction.moment, [0.0, -0.5 * w, 0.0], rtol=1e-9), reaction.moment


def test_ground_joints_run_alike_on_one_and_two_ranks():
    distributed_and_serial_records(swinging("revolute", t_end=0.1))
    distributed_and_serial_records(swinging("clamp", t_end=0.1, at=1.3))


BASE = {"analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
        "beam": [{"name": "a", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 6, "section": SECTION},
                 {"name": "c", "start": [0, 1, 0], "end": [2, 1, 0], "spans": 4, "formulation": "ancf",
                  "section": {"EA": 2e3, "EI": 3.0, "rhoA": 1.0}}]}


@pytest.mark.parametrize("support, words", [
    ({"type": "pin", "beam": "a", "at": 0.5}, ["[[support]] #1", "'type'", "revolute"]),
    ({"type": "revolute", "beam": "a", "at": 0.5}, ["[[support]] #1", "'axis'", "missing"]),
    ({"type": "revolute", "beam": "a", "at": 2.5, "axis": [0, 1, 0]}, ["[[support]] #1", "'at'"]),
    ({"type": "revolute", "beam": "c", "at": 0.5, "axis": [0, 1, 0]}, ["[[support]] #1", "'beam'", "ANCF"]),
    ({"type": "universal", "beam": "a", "at": 0.5, "axis": [1, 0, 0], "axis_b": [1, 1, 0]},
     ["[[support]] #1", "'axis_b'", "perpendicular"]),
    ({"type": "clamp", "beam": "a", "at": 0.5, "motion": {"displacement": [0, 0, 1],
                                                          "time_function": {"type": "ramp", "t1": 1.0}}},
     ["[[support]] #1", "'motion'", "beam end"]),
    ({"type": "clamp", "beam": "c", "at": 0.6}, ["[[support]] #1", "'at'", "ANCF", "node"]),
])
def test_ground_joint_errors_name_the_table_and_key(support, words):
    with pytest.raises(slidebeam.SceneError) as err:
        slidebeam.Simulation(slidebeam.scene_from_dict({**BASE, "support": [support]}))
    assert all(w in str(err.value) for w in words), str(err.value)
