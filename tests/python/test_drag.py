# SPDX-License-Identifier: MIT
"""Fluid drag on beams ([[drag]]): the step Jacobian against finite differences under every
integrator (director beams and ANCF cables), the energy balance closing to the Newton tolerance
under energy-momentum with a flow, drag in still fluid only taking energy out, the terminal
velocity of a falling horizontal rod against the closed form, a flow by height (the drag on a
post in a sheared current), the table's validation, 1 rank = 2 ranks."""
from __future__ import annotations

import dataclasses
import math

import pytest

import slidebeam
import test_ancf
from checks import check_step_jacobian, distributed_and_serial_records
from test_dynamics import INTEGRATORS, everything_scene

WATER = {"density": 1000.0, "diameter": 0.05, "cd_normal": 1.1, "cd_tangential": 0.3}
GUST = {"type": "sine", "amplitude": 0.5, "frequency": 2.0, "phase": 0.3, "offset": 1.0}


def with_drag(scene: slidebeam.Scene, **drag: object) -> slidebeam.Scene:
    data = dict(scene.data)
    data["drag"] = [{"beam": b.name, **drag} for b in scene.beams]
    return slidebeam.scene_from_dict(data)


def at_rest(scene: slidebeam.Scene) -> slidebeam.Scene:
    data = dict(scene.data)
    data["beam"] = [{k: v for k, v in b.items() if k not in ("velocity", "angular_velocity")} for b in data["beam"]]
    return slidebeam.scene_from_dict(data)


@pytest.mark.parametrize("formulation", ("director", "ancf"))
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_drag_step_jacobian_matches_finite_differences(integrator, formulation):
    """Strong drag (water, a current with a sine gust, tangential drag too) on every beam; the
    ANCF scene has a director beam and two cables. A trial end state off the step's path (noise
    1e-3 over h = 0.05: relative velocities of some 0.1 m/s) so that every term of the tangent
    counts."""
    base = everything_scene(integrator, "full") if formulation == "director" else test_ancf.everything_scene(integrator)
    scene = with_drag(base, flow=[0.8, -0.5, 0.3], time_function=GUST, **WATER)
    sim = slidebeam.Simulation(scene)
    assert [e.type for e in sim.active_effects].count("fluid_drag") == len(scene.beams)
    check_step_jacobian(sim, steps=1, h=0.05, seed=5, label=integrator)


@pytest.mark.parametrize("formulation", ("director", "ancf"))
def test_energy_balance_closes_under_energy_momentum(formulation):
    """A current with a gust drives the beams (W grows), alongside gravity, a hat force, supports
    and joints: H - H_0 - W + D stays at the Newton tolerance. In still water the drag's work is
    negative in every step (it only dissipates)."""
    base = everything_scene("energy-momentum", "full") if formulation == "director" \
        else test_ancf.everything_scene("energy-momentum")
    base = at_rest(base)
    scene = with_drag(base, flow=[0.8, -0.5, 0.3], time_function=GUST, **WATER)
    scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, t_end=1.0, dt=0.01))
    records = slidebeam.Simulation(scene).run_dynamic().records
    K = max(r.kinetic_energy for r in records)
    worst = max(r.energy_balance_error for r in records)
    assert K > 1e-3 and max(abs(r.work) for r in records) > 1e-2 * K
    assert worst <= 1e-9 * K, f"|H - H0 - W + D| = {worst:.3e} of max K {K:.3e}"

    still = with_drag(base, **WATER)
    still = dataclasses.replace(still, analysis=dataclasses.replace(still.analysis, t_end=0.5, dt=0.01))
    sim = slidebeam.Simulation(still)
    records = sim.run_dynamic().records
    K = max(r.kinetic_energy for r in records)
    assert max(r.energy_balance_error for r in records) <= 1e-9 * K
    works = drag_work(sim, records)  # the drag's own work, without the loads'
    assert works[-1] < -1e-3 * K and all(b <= a + 1e-14 * K for a, b in zip(works, works[1:]))


def drag_work(sim, records) -> list[float]:
    flows = [j for j, (k, _, _) in enumerate(sim.integrator.energy_flows) if sim.active_effects[k].type == "fluid_drag"]
    assert flows
    return [sum(r.flows[j] for j in flows) for r in records]


def falling_rod(formulation: str, integrator: str = "energy-momentum", **drag: object) -> slidebeam.Scene:
    """A horizontal rod (L = 1 m, rhoA = 0.5 kg/m) let go in water (D = 0.02 m, C_n = 1.2): it
    falls across its axis, so only normal drag acts and the rod stays straight."""
    section = ({"EA": 1e5, "kGA": 1e5, "GJ": 10.0, "EI2": 10.0, "EI3": 10.0, "rhoA": 0.5, "rhoI2": 1e-5,
                "rhoI3": 1e-5} if formulation == "director" else {"EA": 1e5, "EI": 10.0, "rhoA": 0.5})
    beam = {"name": "rod", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 4, "section": section}
    if formulation == "ancf":
        beam["formulation"] = "ancf"
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": 0.005, "t_end": 0.6},
        "beam": [beam],
        "gravity": {"g": [0.0, 0.0, -9.81]},
        "drag": [{"beam": "rod", "diameter": 0.02, "density": 1000.0, "cd_normal": 1.2, "cd_tangential": 0.02,
                  **drag}],
        "output": {"track": [{"beam": "rod", "at": 0.5}]},
    })


@pytest.mark.parametrize("formulation", ("director", "ancf"))
def test_falling_rod_reaches_the_terminal_velocity(formulation):
    """Drag = weight per length: v_t = sqrt(2 rhoA g / (rho D C_n)) = 0.6393 m/s, reached as
    v = v_t tanh(g t / v_t), z = -(v_t^2 / g) ln cosh(g t / v_t). After 0.6 s (9 time constants)
    the rod falls at v_t (measured 6e-7 below: the regularisation, eps^2 / (4 v_t^2)) and has
    fallen the closed form's distance to 2e-5."""
    g, vt = 9.81, math.sqrt(2 * 0.5 * 9.81 / (1000.0 * 0.02 * 1.2))
    records = slidebeam.Simulation(falling_rod(formulation)).run_dynamic().records
    t = [r.t for r in records]
    z = [r.tracked[0][2] for r in records]
    v = (z[-1] - z[-2]) / (t[-1] - t[-2])
    assert v == pytest.approx(-vt, rel=1e-2)
    assert abs(v / -vt - 1) < 1e-5
    for ti, zi in zip(t[::20], z[::20]):
        expected = -(vt**2 / g) * math.log(math.cosh(g * ti / vt))
        assert zi == pytest.approx(expected, rel=1e-3, abs=1e-6)
    for r in records:
        assert abs(r.tracked[0][0] - 0.5) < 1e-9 and abs(r.tracked[0][1]) < 1e-9  # straight down


@pytest.mark.parametrize("integrator, alpha", (("hht", -0.1), ("hht", -0.3), ("newmark", 0.0)))
def test_the_terminal_velocity_is_the_same_under_newmark_and_hht(integrator, alpha):
    """A rate force counts once under HHT: its history term at the step start (no rate) is zero,
    so it is weighted by 1, not by 1 + alpha like the forces it balances (the terminal velocity
    came out 5.4 % high at alpha = -0.1, the drag short by 1 + alpha)."""
    vt = math.sqrt(2 * 0.5 * 9.81 / (1000.0 * 0.02 * 1.2))
    scene = falling_rod("director", integrator)
    if integrator == "hht":
        scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, hht_alpha=alpha))
    records = slidebeam.Simulation(scene).run_dynamic().records
    v = (records[-1].tracked[0][2] - records[-2].tracked[0][2]) / (records[-1].t - records[-2].t)
    assert abs(v / -vt - 1) < 1e-5, v / -vt - 1


@pytest.mark.parametrize("entry, words", [
    ({"beam": "rod", "density": 1000.0}, "missing required key"),
    ({"beam": "rod", "diameter": 0.0, "density": 1000.0}, "must be > 0 m"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "cd_normal": -1.0}, "must be >= 0"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "flow": [1.0, 0.0]}, "array of 3 numbers"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "time_function": {"type": "sine", "frequency": 0}},
     "frequency"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "cd": 1.0}, "unknown key 'cd'"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "profile_z": [0.0, 1.0]}, "needs both"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "profile_z": [0.0, 1.0], "profile": [1.0]},
     "2 or more numbers"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "profile_z": [0.0, 1.0, 2.0], "profile": [1.0, 0.5]},
     "as many factors"),
    ({"beam": "rod", "diameter": 0.02, "density": 1000.0, "profile_z": [1.0, 0.0], "profile": [1.0, 0.5]},
     "must increase"),
])
def test_drag_tables_are_validated(entry, words):
    data = dict(falling_rod("director").data)
    data["drag"] = [entry]
    with pytest.raises(slidebeam.SceneError) as err:  # the table's keys, then the effect's own checks
        slidebeam.Simulation(slidebeam.scene_from_dict(data))
    assert "[[drag]] #1" in str(err.value) and words in str(err.value)


def test_drag_runs_agree_on_one_and_two_ranks():
    # at rest, driven by the current: the spinning scene at dt = 0.05 is at the edge of Newton's
    # reach, and 1 and 2 ranks (their linear solvers' roundoff) may reject different steps
    scene = with_drag(at_rest(everything_scene("energy-momentum", "full")), flow=[0.8, -0.5, 0.3],
                      time_function=GUST, **WATER)
    for world, alone in distributed_and_serial_records(scene):
        assert abs(world.work - alone.work) <= 1e-10 * max(1.0, abs(alone.work))
    ancf = with_drag(test_ancf.everything_scene("energy-momentum"), flow=[0.8, -0.5, 0.3], **WATER)
    distributed_and_serial_records(ancf)


@pytest.mark.skip_in_parallel
def test_the_rope_in_wind_scene():
    """runs/effects/rope_in_wind.toml: the wind pushes the hanging rope out (about 25 degrees at
    10 m/s) and puts work in; the energy balance closes to the Newton tolerance."""
    from pathlib import Path

    scene = slidebeam.load_scene(Path(__file__).resolve().parents[2] / "runs" / "effects" / "rope_in_wind.toml")
    sim = slidebeam.Simulation(scene)
    records = sim.run_dynamic().records
    assert records[-1].t == pytest.approx(10.0)
    K = max(r.kinetic_energy for r in records)
    assert max(r.energy_balance_error for r in records) <= 1e-9 * K
    at3 = min(records, key=lambda r: abs(r.t - 3.0))
    x, _, z = at3.tracked[0]
    assert 20 < math.degrees(math.atan2(x, -z)) < 35
    assert max(drag_work(sim, records)) > 1.0


PROFILE = {"profile_z": [-0.2, 0.25, 0.8], "profile": [0.2, 1.5, 0.5]}  # a sheared current, through the scenes


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("formulation", ("director", "ancf"))
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_drag_in_a_profiled_flow_has_the_step_jacobian_of_finite_differences(integrator, formulation):
    """The flow by height (the factor's slope enters the tangent through the force state's
    height), as test_drag_step_jacobian_matches_finite_differences."""
    base = everything_scene(integrator, "full") if formulation == "director" else test_ancf.everything_scene(integrator)
    sim = slidebeam.Simulation(with_drag(base, flow=[0.8, -0.5, 0.3], time_function=GUST, **PROFILE, **WATER))
    check_step_jacobian(sim, steps=1, h=0.05, seed=5, label=integrator)


@pytest.mark.skip_in_parallel
def test_a_post_in_a_sheared_current_carries_its_drag():
    """A fixed vertical post (L = 2 m) in a current that grows linearly from 0 at its foot to U at
    its top: the support carries 1/2 rho D C_n U^2 L / 3 (the quadrature is exact on the spans:
    1e-9, the regularisation's share), and the energy balance closes (the post does not move: no
    work)."""
    U, L = 1.5, 2.0
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "dt": 0.01, "t_end": 0.03},
        "beam": [{"name": "post", "start": [0.0, 0.0, 0.0], "end": [0.0, 0.0, L], "spans": 4,
                  "section": {"EA": 1e6, "kGA": 1e6, "GJ": 1e3, "EI2": 1e3, "EI3": 1e3, "rhoA": 1.0,
                              "rhoI2": 1e-3, "rhoI3": 1e-3}}],
        "support": [{"type": "fixed", "beam": "post"}],
        "drag": [{"beam": "post", "flow": [U, 0.0, 0.0], "profile_z": [0.0, L], "profile": [0.0, 1.0],
                  "regularization": 1e-6, **WATER}],
    })
    run = slidebeam.Simulation(scene).run_dynamic()
    assert run.complete, run.message
    (reaction,) = run.records[-1].reactions
    exact = 0.5 * WATER["density"] * WATER["diameter"] * WATER["cd_normal"] * U * U * L / 3
    assert abs(-reaction.force[0] / exact - 1) < 1e-9, (reaction.force, exact)
    assert abs(reaction.force[1]) < 1e-12 * exact and abs(reaction.force[2]) < 1e-12 * exact


@pytest.mark.skip_in_parallel
def test_energy_balance_closes_in_a_profiled_flow():
    """As test_energy_balance_closes_under_energy_momentum, in the sheared current."""
    base = at_rest(everything_scene("energy-momentum", "full"))
    scene = with_drag(base, flow=[0.8, -0.5, 0.3], time_function=GUST, **PROFILE, **WATER)
    scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, t_end=1.0, dt=0.01))
    records = slidebeam.Simulation(scene).run_dynamic().records
    K = max(r.kinetic_energy for r in records)
    assert K > 1e-3 and max(abs(r.work) for r in records) > 1e-2 * K
    assert max(r.energy_balance_error for r in records) <= 1e-9 * K
