# SPDX-License-Identifier: MIT
"""Rigid bodies ([[body]], issue 37 item 1): a free body flipping about its intermediate axis
keeps energy and angular momentum under energy-momentum; a body hung from a point by a joint
swings at the compound pendulum's frequency, and hung from a rope on the double pendulum's
modes; a heavy top precesses at the closed-form rate; moments on a body; the step Jacobian
against finite differences under every integrator; one rank = two; the scene's errors; the
bodies' XDMF series; and the multibody scenes (cable robot, ropeway)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import slidebeam
from slidebeam.scene import TimeFunction
from checks import (check_step_jacobian_and_rows, distributed_and_serial_records, joint_multipliers,
                    upward_crossings)

# the pendulums' spins are projected onto the joint on purpose (a velocity the joint takes away)
pytestmark = pytest.mark.filterwarnings("ignore::slidebeam.ConstraintWarning")

INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
STIFF = {"EA": 1e8, "kGA": 1e8, "GJ": 1e6, "EI2": 1e6, "EI3": 1e6, "rhoA": 1.0, "rhoI2": 1e-6, "rhoI3": 1e-6}
MASS, INERTIA, ARM = 2.0, [0.1, 0.2, 0.15], 0.5  # the hanging body: kg, kg m^2, pivot above its centre (m)


def free_body(t_end: float = 8.0, dt: float = 0.01, integrator: str = "energy-momentum",
              **tables: object) -> slidebeam.Scene:
    """A body with principal moments 1, 2, 3 spinning about its intermediate axis (y), slightly off."""
    return slidebeam.scene_from_dict({
        **tables,
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": dt, "t_end": t_end},
        "beam": [{"name": "ground", "start": [5, 0, 0], "end": [6, 0, 0], "spans": 1, "section": STIFF}],
        "support": [{"type": "clamp", "beam": "ground", "at": "start"}],
        "body": [{"name": "box", "mass": 3.0, "inertia": [1.0, 2.0, 3.0], "position": [0, 0, 0],
                  "orientation": [0.1, -0.2, 0.3], "angular_velocity": [0.01, 2.0, 0.01], "velocity": [0.2, 0, 0]}],
        "output": {"every": 1},
    })


def test_a_free_body_flips_about_its_intermediate_axis_keeping_energy_and_momentum():
    """The tennis-racket flip: the axis of the middle moment turns over while energy and angular
    momentum stay constant to the Newton tolerance (1e-12 of each; 1.2e-13 and 9e-14 measured)."""
    sim = slidebeam.Simulation(free_body())
    body = sim.scene.bodies[0]
    axis0 = np.array(body.frame[1])  # d2 in the drawing: the intermediate axis
    turns: list[float] = []
    run = sim.run_dynamic(on_step=lambda r: turns.append(float(sim.control_points(body.index)[0, 6:9] @ axis0)))
    assert run.complete, run.message
    H = np.array([r.total_energy for r in run.records])
    J = np.array([r.angular_momentum for r in run.records])
    assert np.abs(H - H[0]).max() <= 1e-12 * H[0]
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
    up = upward_crossings(run.records)
    period = float(np.mean(np.diff(up)))
    exact = 2 * math.pi * math.sqrt((INERTIA[1] + MASS * ARM ** 2) / (MASS * 9.81 * ARM))
    assert len(up) >= 2 and abs(period / exact - 1) < 2e-4, (period, exact)


def hung_from_a_rope(mode: int, rope: float = 1.0, swing: float = 0.01) -> tuple[slidebeam.Scene, float]:
    """The body hung by its point ARM above the centre from a light ANCF rope (1e-4 of its mass)
    on a spherical support, started on a swing mode of the double pendulum (rope angle, body
    angle) with rates of size `swing`; and that mode's period."""
    m, inertia, a, g = MASS, INERTIA[1], ARM, 9.81
    M = np.array([[m * rope ** 2, m * rope * a], [m * rope * a, m * a * a + inertia]])
    K = np.diag([m * g * rope, m * g * a])
    w2, modes = np.linalg.eig(np.linalg.solve(M, K))
    k = np.argsort(w2)[mode]
    omega = math.sqrt(w2[k])
    rate = omega * swing * modes[:, k] / np.abs(modes[:, k]).max()  # angles from the vertical, +x
    period = 2 * math.pi / omega
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "dt": 0.002, "t_end": 3.5 * period},
        "beam": [{"name": "rope", "formulation": "ancf", "start": [0, 0, 0], "end": [0, 0, -rope], "spans": 4,
                  "section": {"EA": 1e6, "EI": 1e-6, "rhoA": 2e-4 / rope},
                  "angular_velocity": [0, -rate[0], 0], "rotation_center": [0, 0, 0]}],
        "support": [{"type": "spherical", "beam": "rope", "at": "start"}],
        "body": [{"name": "bob", "mass": m, "inertia": INERTIA, "position": [0, 0, -rope - a],
                  "velocity": [rope * rate[0] + a * rate[1], 0, 0], "angular_velocity": [0, -rate[1], 0]}],
        "joint": [{"type": "spherical", "beams": ["rope", "bob"], "at": ["end", [0, 0, -rope]]}],
        "gravity": {"g": [0, 0, -g]},
        "output": {"track": [{"body": "bob"}]},
    }), period


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("mode, tolerance", [(0, 2e-5), (1, 5e-4)])
def test_a_body_hung_from_a_rope_swings_on_the_double_pendulum_s_modes(mode, tolerance):
    """A rope (length l) and a body hung by a point a above its centre: the linear double
    pendulum M theta'' + K theta = 0 with M = [[m l^2, m l a], [m l a, m a^2 + Iyy]] and
    K = diag(m g l, m g a). Started on either mode, the body's centre swings at its period: the
    slow mode to 2e-5 (5e-6 measured; the rope's mass is 1e-4 of the body's), the fast one to
    5e-4 (3.4e-4: what the velocities' projection leaves of the slow mode beats in the crossings)."""
    scene, period = hung_from_a_rope(mode)
    run = slidebeam.Simulation(scene).run_dynamic()
    assert run.complete, run.message
    up = upward_crossings(run.records)
    assert len(up) >= 3 and np.abs(np.diff(up) / period - 1).max() < tolerance, (np.diff(up), period)


@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("joint", ("spherical", "revolute", "rigid"))
def test_step_jacobian_matches_finite_differences(joint, integrator):
    sim = slidebeam.Simulation(pendulum(joint, integrator, swing=0.5, t_end=0.1, dt=0.01))
    rows = joint_multipliers(sim, {"spherical": 3, "revolute": 5, "rigid": 6}[joint])
    base, n = sim.control_point_unknowns(sim.first_control_point(sim.scene.bodies[0].index))
    rows += list(range(base, base + n + 6))  # the body's coordinates and orthonormality multipliers
    check_step_jacobian_and_rows(sim, rows, seed=5, label=f"{joint}, {integrator}")


def twisted(frame: str, integrator: str = "energy-momentum", t_end: float = 0.1, dt: float = 0.01) -> slidebeam.Scene:
    """free_body turned by a moment (at a point of the body: a moment's point does not matter)."""
    return free_body(t_end, dt, integrator, load=[{"type": "moment", "beam": "box", "at": [0.2, 0.0, 0.0],
                                                     "value": [0.3, -0.2, 0.5], "frame": frame}])


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("integrator", INTEGRATORS)
@pytest.mark.parametrize("frame", ("spatial", "material"))
def test_a_moment_on_a_body_has_the_step_jacobian_of_finite_differences(frame, integrator):
    sim = slidebeam.Simulation(twisted(frame, integrator))
    base, n = sim.control_point_unknowns(sim.first_control_point(sim.scene.bodies[0].index))
    check_step_jacobian_and_rows(sim, list(range(base, base + n + 6)), seed=7, label=f"{frame} moment, {integrator}")


@pytest.mark.skip_in_parallel
def test_a_spatial_moment_changes_a_free_body_s_angular_momentum_by_its_impulse():
    """J(t) = J(0) + M t under energy-momentum to second order in the step: the moment acts
    through director forces 1/2 M x d_i on the step's middle triad, which is orthonormal only to
    O(h^2) (4e-5 of |M| t at h = 0.01, a quarter of it at h / 2); the linear momentum stays put
    (1e-12)."""
    errors = []
    for dt in (0.01, 0.005):
        run = slidebeam.Simulation(twisted("spatial", t_end=1.0, dt=dt)).run_dynamic()
        assert run.complete, run.message
        J = np.array([r.angular_momentum for r in run.records])
        L = np.array([r.linear_momentum for r in run.records])
        t = np.array([r.t for r in run.records])
        errors.append(float(np.abs(J - J[0] - np.outer(t - t[0], [0.3, -0.2, 0.5])).max()))
        assert np.abs(L - L[0]).max() < 1e-12
    assert errors[0] < 1e-4 * np.linalg.norm([0.3, -0.2, 0.5]) and 3.8 < errors[0] / errors[1] < 4.2, errors


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


def test_a_heavy_symmetric_top_precesses_steadily_at_the_closed_form_rate():
    """A symmetric top (I1 = I2 about its centre, I3 about its axis) on a spherical joint at the
    point l below its centre, its axis tilted theta = 30 degrees, started on the steady precession
    of rate Omega = 1 rad/s with the spin from m g l = Omega w3 I3 - Omega^2 I1' cos(theta) (I1' =
    I1 + m l^2 about the pivot, w3 the axis' angular velocity): after 3 s its centre has turned by
    Omega t about the vertical and its tilt is still theta (to 2e-4 rad at dt = 2.5 ms)."""
    m, I1, I3, l, theta, Omega, g = 1.0, 0.02, 0.04, 0.1, math.radians(30.0), 1.0, 9.81
    I1p = I1 + m * l * l
    w3 = (m * g * l + Omega ** 2 * I1p * math.cos(theta)) / (Omega * I3)  # the spin along the axis
    axis = np.array([math.sin(theta), 0.0, math.cos(theta)])
    # angular velocity: precession about z plus spin about the axis, with the axis' component w3
    spin = w3 - Omega * math.cos(theta)
    omega = Omega * np.array([0.0, 0.0, 1.0]) + spin * axis
    centre = l * axis
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "dt": 0.0025, "t_end": 3.0},
        "beam": [{"name": "stub", "start": [0, 0, -0.2], "end": [0, 0, 0], "spans": 2, "section": STIFF}],
        "support": [{"type": "clamp", "beam": "stub", "at": "start"}],
        "body": [{"name": "top", "mass": m, "inertia": [I1, I1, I3], "position": centre.tolist(),
                  "orientation": [0.0, theta, 0.0], "velocity": np.cross(omega, centre).tolist(),
                  "angular_velocity": omega.tolist()}],
        "joint": [{"type": "spherical", "beams": ["stub", "top"], "at": ["end", [0, 0, 0]]}],
        "gravity": {"g": [0, 0, -g]},
        "output": {"track": [{"body": "top"}], "every": 40},
    })
    run = slidebeam.Simulation(scene).run_dynamic()
    assert run.complete, run.message
    for r in run.records:
        c = np.array(r.tracked[0])
        tilt = math.acos(c[2] / np.linalg.norm(c))
        turned = math.atan2(c[1], c[0])
        assert abs(tilt - theta) < 2e-4, (r.t, tilt - theta)
        assert abs(math.remainder(turned - Omega * r.t, 2 * math.pi)) < 2e-4 * max(1.0, r.t), (r.t, turned)


BOB_TOML = """
[analysis]
type = "dynamic"
integrator = "energy-momentum"
dt = 0.01
t_end = 0.2

[[beam]]
name = "stub"
start = [-0.2, 0.0, 0.0]
end = [0.0, 0.0, 0.0]
spans = 2
section = { EA = 1e8, kGA = 1e8, GJ = 1e6, EI2 = 1e6, EI3 = 1e6, rhoA = 1.0, rhoI2 = 1e-6, rhoI3 = 1e-6 }

[[support]]
type = "clamp"
beam = "stub"
at = "start"

[[body]]
name = "bob"
mass = 2.0
inertia = [0.1, 0.2, 0.15]
position = [0.0, 0.0, -0.5]
velocity = [-0.5, 0.0, 0.0]
angular_velocity = [0.0, 1.0, 0.0]

[[joint]]
type = "revolute"
beams = ["stub", "bob"]
at = ["end", [0.0, 0.0, 0.0]]
axis = [0.0, 1.0, 0.0]

[gravity]
g = [0.0, 0.0, -9.81]
"""


@pytest.mark.skip_in_parallel
def test_bodies_are_written_for_paraview_and_read_back(run_cli, tmp_path):
    """bodies.xdmf: one vertex per body with displacement, velocity and its axes, read back by
    slidebeam.output.rundata as the history has it; view.py shows the series; slidebeam render draws
    the body's axes from its centre."""
    from slidebeam.output import rundata

    (tmp_path / "bob.toml").write_text(BOB_TOML)
    out = run_cli("run", "bob.toml", "--out", "res", "-q")
    assert out.returncode == 0, out.stderr
    run = rundata.open_run(tmp_path / "res")
    assert run.bodies is not None and run.bodies.names == ["bob"]
    last = len(run.bodies.times) - 1
    centre = run.bodies.positions(last)[0]
    assert np.allclose(centre, [run.history[f"bob.{c}"][-1] for c in "xyz"], atol=1e-12)
    d3 = run.bodies.field("d3", last)[0]
    assert abs(np.linalg.norm(d3) - 1.0) < 1e-9 and abs(centre[0]) > 0.01  # it swung
    assert "'bodies'" in (tmp_path / "res" / "view.py").read_text()
    assert np.allclose(run.summary["final_bodies"]["bob"]["position"], centre, atol=1e-12)
    # slidebeam render draws the body at its centre with its axes d1, d2, d3
    from slidebeam.plots.render import Renderer

    frame = Renderer(run, size=(320, 200)).frame(last)
    assert np.allclose(frame.masses[-1], centre)
    for k in range(3):
        start, end = frame.axes[k, 0]
        assert np.allclose(start, centre)
        direction = run.bodies.field(f"d{k + 1}", last)[0]
        assert np.allclose(np.cross(end - start, direction), 0.0, atol=1e-12) and (end - start) @ direction > 0


def hung_by_support(force: float, **analysis: object) -> slidebeam.Scene:
    """The body hung from a spherical support at its point ARM above the centre, pushed sideways
    at its centre."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "start": "equilibrium", "dt": 0.01, "t_end": 0.02, **analysis},
        "beam": [{"name": "stub", "start": [5, 0, 0], "end": [6, 0, 0], "spans": 1, "section": STIFF}],
        "support": [{"type": "clamp", "beam": "stub", "at": "start"},
                    {"type": "spherical", "beam": "bob", "at": [0, 0, 0]}],
        "body": [{"name": "bob", "mass": MASS, "inertia": INERTIA, "position": [0, 0, -ARM]}],
        "load": [{"type": "force", "beam": "bob", "at": [0, 0, -ARM], "value": [force, 0, 0]}],
        "gravity": {"g": [0, 0, -9.81]},
    })


def test_a_body_on_a_spherical_support_leans_under_a_force_as_statics_says():
    """A spherical support at a body point and a force at its centre: the equilibrium start
    leans the body by atan(F / (m g)) and the support carries F and the weight (1e-12)."""
    sim = slidebeam.Simulation(hung_by_support(5.0))
    run = sim.run_dynamic()
    assert run.complete, run.message
    first = run.records[0]
    centre = np.array(first.tracked[-1])
    assert abs(math.atan2(centre[0], -centre[2]) - math.atan(5.0 / (MASS * 9.81))) < 1e-12
    (support,) = [r for r in first.reactions if r.effect.startswith("spherical[bob")]
    assert np.allclose(support.force, [-5.0, 0.0, MASS * 9.81], atol=1e-10)


@pytest.mark.parametrize("change, words", [
    ({"support": [{"type": "clamp", "beam": "bob", "at": "start"}]}, ["[[support]] #1", "'at'", "no ends"]),
    ({"point_mass": [{"beam": "bob", "at": "start", "mass": 1.0}]},
     ["[[point_mass]] #1", "'beam'", "[[body]]", "mass and inertia"]),
    ({"drag": [{"beam": "bob", "density": 1.2, "diameter": 0.1}]}, ["[[drag]] #1", "'beam'", "beams only"]),
])
def test_what_a_body_cannot_take_is_refused_by_name(change, words):
    data = {"analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.02},
            "beam": [{"name": "stub", "start": [5, 0, 0], "end": [6, 0, 0], "spans": 1, "section": STIFF}],
            "body": [{"name": "bob", "mass": MASS, "inertia": INERTIA, "position": [0, 0, -ARM]}], **change}
    with pytest.raises(slidebeam.SceneError) as err:
        slidebeam.Simulation(slidebeam.scene_from_dict(data))
    assert all(w in str(err.value) for w in words), str(err.value)


def test_a_fixed_body_driven_through_a_turn_carries_a_welded_rod():
    """[[support]] type = "fixed" on a body with a driven rotation of 1 rad about z: the body's
    axes turn exactly (1e-12); a stiff rod welded to it by a rigid joint at a point of the body
    follows, its tip within 1e-5 of the rigid turn (the rod's elastic bending)."""
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "dt": 0.01, "t_end": 1.0},
        "beam": [{"name": "rod", "start": [0.5, 0, 0], "end": [1.5, 0, 0], "spans": 4, "section": STIFF}],
        "support": [{"type": "fixed", "beam": "plate",
                     "motion": {"rotation": [0, 0, 1.0], "time_function": {"type": "smooth_ramp", "t0": 0, "t1": 1}}}],
        "body": [{"name": "plate", "mass": 5.0, "inertia": [0.1, 0.2, 0.3], "position": [0, 0, 0]}],
        "joint": [{"type": "rigid", "beams": ["plate", "rod"], "at": [[0.5, 0, 0], "start"]}],
    })
    sim = slidebeam.Simulation(scene)
    run = sim.run_dynamic()
    assert run.complete, run.message
    axes = sim.control_points(sim.scene.bodies[0].index)[0]
    assert np.allclose(axes[3:6], [math.cos(1.0), math.sin(1.0), 0.0], atol=1e-12)
    assert np.allclose(sim.evaluate("rod", 1.0)[0, :3], [1.5 * math.cos(1.0), 1.5 * math.sin(1.0), 0.0], atol=1e-5)


@pytest.mark.skip_in_parallel
def test_the_cable_robot_brings_its_platform_to_the_target_on_taut_ropes(root):
    """runs/multibody/cable_robot.toml: the anchors' travels bring the platform's centre to
    (0.6, 0, 2.0) within 1e-4 m, every rope pulls at least 20 N at its anchor all the way, no
    step is cut, and the energy balance (the driven anchors' work) closes to 1e-9 of it."""
    run = slidebeam.Simulation(slidebeam.load_scene(root / "runs" / "multibody" / "cable_robot.toml")).run_dynamic()
    assert run.complete and run.records[-1].rejected_steps == 0, run.message
    assert np.abs(np.subtract(run.records[-1].tracked[-1], [0.6, 0.0, 2.0])).max() < 1e-4
    pulls = [r.force[2] for rec in run.records for r in rec.reactions if r.effect.startswith("spherical[cable")]
    assert min(pulls) > 20.0
    assert max(abs(r.energy_balance_error) for r in run.records) <= 1e-9 * abs(run.records[-1].work)


@pytest.mark.skip_in_parallel
def test_the_ropeway_hangs_its_cabin_on_a_rope_given_by_its_length(root):
    """runs/multibody/ropeway.toml: the equilibrium start's anchors carry the rope's weight (rho A
    times its unstretched length, 60.5 m), the hanger's and the cabin's (1e-8), with equal and
    opposite horizontal pulls; the cabin hangs straight under the carriage (1e-9); and, driven,
    the energy balance closes with the drive's work (1e-9 of it)."""
    scene = slidebeam.load_scene(root / "runs" / "multibody" / "ropeway.toml", ["analysis.t_end=2.0"])
    run = slidebeam.Simulation(scene).run_dynamic()
    assert run.complete and run.records[-1].rejected_steps == 0, run.message
    first = run.records[0]
    anchors = [np.array(r.force) for r in first.reactions if r.effect.startswith("spherical[track")]
    weight = 9.81 * (math.pi * 0.01 ** 2 * 7850.0 * 60.5 + math.pi * 0.015 ** 2 * 7800.0 * 2.0 + 300.0)
    assert abs(sum(f[2] for f in anchors) - weight) <= 1e-8 * weight
    assert abs(anchors[0][0] + anchors[1][0]) <= 1e-8 * weight and abs(anchors[0][0]) > 1e4
    hanger_foot, cabin = np.array(first.tracked[0]), np.array(first.tracked[1])
    assert np.abs((hanger_foot - cabin)[:2]).max() < 1e-9
    work = run.records[-1].work
    assert abs(work) > 100.0 and max(abs(r.energy_balance_error) for r in run.records) <= 1e-9 * abs(work)


@pytest.mark.skip_in_parallel
def test_the_crane_winds_its_hoist_rope_onto_the_winch_drum_over_the_boom_tip_sheave(root):
    """runs/multibody/crane_winch.toml, its first 1.5 s: the drum's turn phi winds the rope on at
    its centre line's radius less the bed's sinkage under the rope's pull (0.61 - T / (0.61 k)),
    and the rope runs over the sheave, so the hook rises by that radius times phi: 0.104 m here,
    1.9 mm short while the rope's first metre bends onto the drum from its fixed end (over the
    whole 3 m, 0.5 mm long: docs/verification.md); no step cut or on the pivoting LU; the balance
    closes with the drum's work (1e-10 of the largest kinetic energy)."""
    scene = slidebeam.load_scene(root / "runs" / "multibody" / "crane_winch.toml",
                                 ["analysis.t_end=1.5", "output.every=10", "output.xdmf=false"])
    sim = slidebeam.Simulation(scene)
    run = sim.run_dynamic()
    assert run.complete and sum(r.rejected_steps for r in run.records) == 0, run.message
    assert sim.integrator.pivoting_lu_steps == 0
    f = TimeFunction.of_entry(next(e for e in scene.entries("support") if e.text.get("tf_type")))  # the drum's
    radius = 0.61 - 500.0 * 9.81 / (0.61 * 1.0e7)
    first, last = run.records[0], run.records[-1]
    rise = last.tracked[0][2] - first.tracked[0][2]
    assert rise > 0.1 and abs(rise - radius * 4.918032786885246 * f.value(last.t)) < 2.5e-3
    k_max = max(r.kinetic_energy for r in run.records)
    assert max(abs(r.energy_balance_error) for r in run.records) <= 1e-10 * k_max
