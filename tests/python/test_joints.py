# SPDX-License-Identifier: MIT
"""Joints anywhere ([[joint]], issue 37 item 2): spherical, universal, revolute and rigid joints
between two beam points at any arc length. The step Jacobian against finite differences under
every integrator; energy and both momenta exact under energy-momentum; a revolute hinge that
swings as a compound pendulum and keeps its plane; reactions that leave the free rotations free;
one rank = two; and the scene's errors."""
from __future__ import annotations

import math

import numpy as np
import pytest

import slidebeam
from checks import (check_step_jacobian_and_rows, distributed_and_serial_records, drifts, joint_multipliers,
                    upward_crossings)

# b's velocity differs from a's on purpose: projected onto the joint, it sets the cross vibrating
pytestmark = pytest.mark.filterwarnings("ignore::slidebeam.ConstraintWarning")

INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
KINDS = ("spherical", "universal", "revolute", "rigid")
SECTION = {"EA": 2e3, "kGA": 1e3, "GJ": 2.0, "EI2": 3.0, "EI3": 4.0, "rhoA": 1.0, "rhoI2": 0.02, "rhoI3": 0.03}
# a crosses b at a's s = 0.7 and b's s = 0.5: inside a span of each
AXES = {"universal": {"axis": [1.0, 0.0, 0.0], "axis_b": [0.0, 1.0, 0.0]}, "revolute": {"axis": [0.0, 0.0, 1.0]}}


def cross(kind: str, integrator: str = "energy-momentum", *, ancf: bool = False, t_end: float = 0.3,
          dt: float = 0.01) -> slidebeam.Scene:
    """Two beams crossing at interior points, joined there, flying free with a spin and with b
    moving against a (the velocity is projected onto the joint)."""
    b = {"name": "b", "start": [0.7, -0.5, 0.0], "end": [0.7, 0.7, 0.0], "spans": 5,
         "velocity": [0.0, 0.0, 0.8], "angular_velocity": [0.0, 1.5, 0.0], "rotation_center": [0.7, 0.0, 0.0]}
    b.update({"formulation": "ancf", "section": {"EA": 2e3, "EI": 3.0, "rhoA": 1.0}} if ancf else {"section": SECTION})
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": dt, "t_end": t_end},
        "beam": [{"name": "a", "start": [0.0, 0.0, 0.0], "end": [2.0, 0.0, 0.0], "spans": 6, "section": SECTION,
                  "velocity": [0.1, 0.2, -0.1], "angular_velocity": [0.3, -0.5, 1.0], "rotation_center": [0.7, 0, 0]},
                 b],
        "joint": [{"type": kind, "beams": ["a", "b"], "at": [0.7, 0.5], **AXES.get(kind, {})}],
    })


@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("kind", KINDS + ("spherical to an ANCF cable",))
def test_step_jacobian_matches_finite_differences(kind, integrator):
    sim = slidebeam.Simulation(cross(kind.split()[0], integrator, ancf="ANCF" in kind))
    multipliers = joint_multipliers(sim, 3 + KINDS.index(kind.split()[0]))
    check_step_jacobian_and_rows(sim, multipliers, seed=3, label=f"{kind}, {integrator}")


@pytest.mark.parametrize("kind", KINDS + ("spherical to an ANCF cable",))
def test_energy_momentum_keeps_energy_and_both_momenta(kind):
    """The free cross, 1 s: energy to the Newton tolerance, linear and angular momentum to 1e-12,
    the joint closed at every step."""
    run = slidebeam.Simulation(cross(kind.split()[0], ancf="ANCF" in kind, t_end=1.0, dt=0.02)).run_dynamic()
    assert run.complete, run.message
    d = drifts(run.records)
    assert d["energy"] <= 1e-9 and d["linear"] <= 2e-12 and d["angular"] <= 2e-12, d
    assert max(r.constraint_residual for r in run.records) < 1e-9


def hinged_pendulum(kind: str = "revolute", g_side: float = 0.0, swing: float = 0.05) -> slidebeam.Scene:
    """A stiff rod (l = 1) hanging from the middle of a stiff beam clamped at both ends, joined
    there with its hinge along y, started with an angular velocity `swing` about the hinge."""
    stiff = {"EA": 1e8, "kGA": 1e8, "GJ": 1e6, "EI2": 1e6, "EI3": 1e6, "rhoA": 1.0, "rhoI2": 1e-8, "rhoI3": 1e-8}
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "dt": 0.005, "t_end": 4.2},
        "beam": [{"name": "beam", "start": [-1.0, 0.0, 0.0], "end": [1.0, 0.0, 0.0], "spans": 4, "section": stiff},
                 {"name": "rod", "start": [0.0, 0.0, 0.0], "end": [0.0, 0.0, -1.0], "spans": 4, "section": stiff,
                  "angular_velocity": [0.0, swing, 0.0], "rotation_center": [0.0, 0.0, 0.0]}],
        "support": [{"type": "clamp", "beam": "beam", "at": "start"}, {"type": "clamp", "beam": "beam", "at": "end"}],
        "joint": [{"type": kind, "beams": ["beam", "rod"], "at": [1.0, "start"], **({"axis": [0, 1, 0]}
                                                                                    if kind == "revolute" else {})}],
        "gravity": {"g": [0.0, g_side, -9.81]},
        "output": {"track": [{"beam": "rod", "at": "end"}]},
    })


def test_a_revolute_hinge_swings_as_a_compound_pendulum_in_its_plane():
    """Period 2 pi sqrt(2 l / (3 g)) of a rigid rod hinged at its end, to 2e-4 (the amplitude,
    0.026 rad, shifts it by theta^2 / 16 = 4e-5); with gravity pulling sideways too, the rod stays
    in the hinge's plane: its tip's y within 1e-5 (the clamped beam twists elastically under the
    rod's sideways pull by about 2e-6), where a spherical joint lets it swing 0.05 out."""
    run = slidebeam.Simulation(hinged_pendulum(g_side=2.0)).run_dynamic()
    assert run.complete, run.message
    tip = np.array([r.tracked[0] for r in run.records])
    up = upward_crossings(run.records, tracked=0)
    period = float(np.mean(np.diff(up)))
    exact = 2 * math.pi * math.sqrt(2.0 / (3 * 9.81))
    assert len(up) >= 2 and abs(period / exact - 1) < 2e-4, (period, exact)
    assert np.abs(tip[:, 1]).max() < 1e-5
    free = slidebeam.Simulation(hinged_pendulum("spherical", g_side=2.0)).run_dynamic()
    assert abs(free.records[-1].tracked[0][1]) > 0.05


def test_reactions_leave_the_free_rotations_free():
    """The joint's moment on the first beam has no part about a free axis: none about a revolute
    joint's hinge (turned with the beam), none about either arm of a universal joint, no moment
    at all from a spherical one; a rigid joint's carries all three. Newmark, whose forces are
    those of the step's end state (under the midpoint rules the reaction is the step's, with the
    arms of the step's middle)."""
    moments = {}
    for kind in KINDS:
        sim = slidebeam.Simulation(cross(kind, "newmark", t_end=0.2, dt=0.02))
        run = sim.run_dynamic()
        assert run.complete, run.message
        (reaction,) = run.records[-1].reactions
        frame = sim.evaluate("a", 0.7)[0]
        d = [frame[3:6], frame[6:9], frame[9:12]]  # a's triad at the joint, in its drawn state e_x, e_y, e_z
        moments[kind] = np.array(reaction.moment if reaction.moment is not None else [0.0, 0.0, 0.0])
        size = np.linalg.norm(reaction.force) * 1.0 + np.linalg.norm(moments[kind])
        assert size > 1e-3, kind
        if kind == "revolute":
            assert abs(moments[kind] @ d[2]) <= 1e-9 * size
        if kind == "universal":  # a's arm is a's d1 (drawn along x); b's arm is b's drawn y axis
            frame_b = sim.evaluate("b", 0.5)[0]
            assert abs(moments[kind] @ d[0]) <= 1e-9 * size and abs(moments[kind] @ frame_b[3:6]) <= 1e-9 * size
    assert np.linalg.norm(moments["spherical"]) == 0.0
    assert np.linalg.norm(moments["rigid"]) > 1e-3


def test_joints_run_alike_on_one_and_two_ranks():
    distributed_and_serial_records(cross("rigid", t_end=0.1))
    distributed_and_serial_records(cross("spherical", ancf=True, t_end=0.1))
    distributed_and_serial_records(welded_cable("cable", t_end=0.1))


@pytest.mark.parametrize("change, words", [
    ({"type": "hinge"}, ["[[joint]] #1", "'type'", "revolute"]),
    ({"axis": None}, ["[[joint]] #1", "'axis'", "missing"]),
    ({"at": [0.7]}, ["[[joint]] #1", "'at'", "2 points"]),
    ({"at": [0.8, 0.5]}, ["[[joint]] #1", "do not meet", "distance"]),
    ({"at": [2.5, 0.5]}, ["[[joint]] #1", "'at'", "[0, L]"]),
])
def test_joint_errors_name_the_table_and_key(change, words):
    table = {"type": "revolute", "beams": ["a", "b"], "at": [0.7, 0.5], "axis": [0, 0, 1]}
    table.update(change)
    table = {k: v for k, v in table.items() if v is not None}
    scene = {"analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
             "beam": [{"name": "a", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 6, "section": SECTION},
                      {"name": "b", "start": [0.7, -0.5, 0], "end": [0.7, 0.7, 0], "spans": 5, "section": SECTION}],
             "joint": [table]}
    with pytest.raises(slidebeam.SceneError) as err:
        slidebeam.Simulation(slidebeam.scene_from_dict(scene))
    assert all(w in str(err.value) for w in words), str(err.value)


def test_universal_arms_must_be_perpendicular_and_ancf_cables_take_no_hinges():
    bad = cross("universal")
    with pytest.raises(slidebeam.SceneError, match="perpendicular"):
        slidebeam.Simulation(slidebeam.scene_from_dict({
            "analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
            "beam": [{"name": "a", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 6, "section": SECTION},
                     {"name": "b", "start": [0.7, -0.5, 0], "end": [0.7, 0.7, 0], "spans": 5, "section": SECTION}],
            "joint": [{"type": "universal", "beams": ["a", "b"], "at": [0.7, 0.5], "axis": [1, 0, 0],
                       "axis_b": [1, 1, 0]}]}))
    assert bad.effects
    with pytest.raises(slidebeam.SceneError, match="ANCF|ancf"):
        slidebeam.scene_from_dict({
            "analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
            "beam": [{"name": "a", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 6, "section": SECTION},
                     {"name": "b", "start": [0.7, -0.5, 0], "end": [0.7, 0.7, 0], "spans": 5, "formulation": "ancf",
                      "section": {"EA": 2e3, "EI": 3.0, "rhoA": 1.0}}],
            "joint": [{"type": "revolute", "beams": ["a", "b"], "at": [0.7, 0.5], "axis": [0, 0, 1]}]})


def test_the_crane_settles_on_its_joints_and_keeps_its_energy_after_slewing(root):
    """runs/multibody/crane.toml (a boom hinged inside the mast, ropes on spherical joints): the
    equilibrium start carries every weight into the clamp, the hoist rope's top joint carries
    the hook and the rope, and once the slewing stops the energy is constant to 1e-10."""
    scene = slidebeam.load_scene(root / "runs" / "multibody" / "crane.toml", ["analysis.t_end=6.5", "output.every=10"])
    sim = slidebeam.Simulation(scene)
    run = sim.run_dynamic()
    assert run.complete and run.records[-1].rejected_steps == 0, run.message
    first = {r.effect: np.array(r.force) for r in run.records[0].reactions}
    g = 9.81
    weight = g * (150.0 * 12 + 60.0 * 14 + 1.6 * (float(np.hypot(7.0, 3.12435565298214)) + 15.0) + 500.0)
    assert abs(first["clamp[mast@start]"][2] - weight) <= 1e-8 * weight
    hoist = first["spherical_joint[boom@end-hoist@start]"]
    assert abs(-hoist[2] - g * (500.0 + 1.6 * 15.0)) <= 1e-6 * weight and np.abs(hoist[:2]).max() <= 1e-6 * weight
    H = np.array([r.total_energy for r in run.records if r.t >= 5.5])
    assert len(H) >= 10 and np.abs(H - H[0]).max() <= 1e-10 * abs(H[0])


CABLE = {"EA": 2e3, "EI": 3.0, "rhoA": 1.0}


def welded_cable(other: str, integrator: str = "energy-momentum", t_end: float = 0.3, dt: float = 0.01
                 ) -> slidebeam.Scene:
    """An ANCF cable b welded (rigid joint) at one of its nodes: across the director beam a
    (other = "beam"; b's node at s = 0.48 sits on a's s = 0.7), or end to end onto the ANCF
    cable a, drawn in line (other = "cable"); spinning and vibrating free."""
    spin = {"angular_velocity": [0.3, -0.5, 1.0], "rotation_center": [0.7, 0.0, 0.0]}
    if other == "beam":
        a = {"name": "a", "start": [0.0, 0.0, 0.0], "end": [2.0, 0.0, 0.0], "spans": 6, "section": SECTION, **spin}
        b_line, at = {"start": [0.7, -0.48, 0.0], "end": [0.7, 0.72, 0.0]}, [0.7, 0.48]
    else:
        a = {"name": "a", "formulation": "ancf", "start": [0.0, 0.0, 0.0], "end": [1.0, 0.0, 0.0], "spans": 4,
             "section": CABLE, **spin}
        b_line, at = {"start": [1.0, 0.0, 0.0], "end": [2.2, 0.0, 0.0]}, ["end", "start"]
    b = {"name": "b", "formulation": "ancf", **b_line, "spans": 5, "section": CABLE,
         "velocity": [0.0, 0.0, 0.8], **spin}
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": dt, "t_end": t_end},
        "beam": [a, b],
        "joint": [{"type": "rigid", "beams": ["a", "b"], "at": at}],
    })


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("other", ("beam", "cable"))
def test_a_cable_welded_by_its_slope_has_the_step_jacobian_of_finite_differences(other, integrator):
    sim = slidebeam.Simulation(welded_cable(other, integrator))
    multipliers = joint_multipliers(sim, {"beam": 5, "cable": 6}[other])
    check_step_jacobian_and_rows(sim, multipliers, seed=9, label=f"cable welded to a {other}, {integrator}")


@pytest.mark.parametrize("other", ("beam", "cable"))
def test_a_welded_cable_keeps_energy_and_both_momenta(other):
    run = slidebeam.Simulation(welded_cable(other, t_end=1.0, dt=0.02)).run_dynamic()
    assert run.complete, run.message
    d = drifts(run.records)
    assert d["energy"] <= 1e-9 and d["linear"] <= 2e-12 and d["angular"] <= 2e-12, d
    assert max(r.constraint_residual for r in run.records) < 1e-9


@pytest.mark.skip_in_parallel
def test_two_cables_welded_end_to_end_bend_as_one():
    """A cantilever of two ANCF cables (4 elements each) welded end to end bends under a tip
    force exactly as one cable of 8 elements (1e-10 of the deflection): the weld makes the slope
    continuous, as a node of one cable does."""
    def tip(beams: list[dict], joints: list[dict]) -> np.ndarray:
        scene = slidebeam.scene_from_dict({
            "analysis": {"type": "static", "steps": 4},
            "beam": beams,
            "support": [{"type": "clamp", "beam": "a", "at": "start"}],
            "joint": joints,
            "load": [{"type": "force", "beam": beams[-1]["name"], "at": "end", "value": [0.0, -2.0, 1.0]}],
            "output": {"track": [{"beam": beams[-1]["name"], "at": "end"}]},
        })
        return np.array(slidebeam.Simulation(scene).solve_static()[-1].tracked[0])
    cable = {"formulation": "ancf", "section": CABLE}
    one = tip([{"name": "a", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 8, **cable}], [])
    two = tip([{"name": "a", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 4, **cable},
               {"name": "b", "start": [1, 0, 0], "end": [2, 0, 0], "spans": 4, **cable}],
              [{"type": "rigid", "beams": ["a", "b"], "at": ["end", "start"]}])
    assert np.linalg.norm(one - [2, 0, 0]) > 0.1
    assert np.abs(one - two).max() <= 1e-10 * np.linalg.norm(one - [2, 0, 0]), (one, two)


@pytest.mark.parametrize("change, words", [
    ({"at": [0.7, 0.5]}, ["[[joint]] #1", "'at'", "node"]),
    ({"type": "revolute", "axis": [0, 0, 1]}, ["[[joint]] #1", "'beams'", "ANCF"]),
])
def test_a_cable_is_welded_at_its_nodes_only(change, words):
    data = {"analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
            "beam": [{"name": "a", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 6, "section": SECTION},
                     {"name": "b", "formulation": "ancf", "start": [0.7, -0.5, 0], "end": [0.7, 0.7, 0], "spans": 5,
                      "section": CABLE}],
            "joint": [{"type": "rigid", "beams": ["a", "b"], "at": [0.7, 0.5], **change}]}
    with pytest.raises(slidebeam.SceneError) as err:
        slidebeam.Simulation(slidebeam.scene_from_dict(data))
    assert all(w in str(err.value) for w in words), str(err.value)
