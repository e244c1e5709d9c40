# SPDX-License-Identifier: MIT
"""Contact of beams with rigid shapes ([[contact]]: plane, cylinder, sphere; issue 39): the step
Jacobian against finite differences under every integrator (director beams and ANCF cables),
energy conserved through touch-down and lift-off under energy-momentum, a rope at rest sinking
w / k into the bed, a taut rope over a drum (tension unchanged, sunk T / (R k)), a mooring line
on the seabed against the closed-form catenary, 1 rank = 2 ranks."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import slidebeam
import test_ancf
from checks import check_step_jacobian, check_step_jacobian_and_rows, distributed_and_serial_records, drifts
from slidebeam.scene.catenary import MooringLine
from test_dynamics import INTEGRATORS, everything_scene

# Shapes through the test scenes' beams: some points in contact, some free
SLOPE = {"type": "plane", "point": [1.0, 0.5, 0.2], "normal": [0.2, 0.3, 1.0], "stiffness": 50.0}
SHAPES = {
    "plane": SLOPE,
    "cylinder": {"type": "cylinder", "point": [0.0, 0.1, -0.2], "axis": [1.0, 0.2, 0.1], "radius": 0.25,
                 "stiffness": 50.0},
    "sphere": {"type": "sphere", "center": [0.5, 0.1, -0.25], "radius": 0.35, "stiffness": 50.0},
}


def with_contact(scene: slidebeam.Scene, **plane: object) -> slidebeam.Scene:
    data = dict(scene.data)
    data["contact"] = [{"beam": b.name, **plane} for b in scene.beams]
    return slidebeam.scene_from_dict(data)


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("formulation", ("director", "ancf"))
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_contact_step_jacobian_matches_finite_differences(integrator, formulation, shape):
    base = everything_scene(integrator, "full") if formulation == "director" else test_ancf.everything_scene(integrator)
    scene = with_contact(base, **SHAPES[shape])
    sim = slidebeam.Simulation(scene)
    assert [e.type for e in sim.active_effects].count(f"{shape}_contact") == len(scene.beams)
    assert sim.energies()["potential"] != slidebeam.Simulation(base).energies()["potential"]  # in contact at t = 0
    check_step_jacobian(sim, steps=1, h=0.05, seed=7, label=integrator)


def dropped_rod(formulation: str, integrator: str = "energy-momentum") -> slidebeam.Scene:
    """A 1 m rod, tilted, dropped from 0.2 m onto the ground (a stiff bed): it lands end first,
    bounces and rocks."""
    section = ({"EA": 1e4, "EI": 5.0, "rhoA": 1.0} if formulation == "ancf" else
               {"EA": 1e4, "kGA": 5e3, "GJ": 3.0, "EI2": 5.0, "EI3": 5.0, "rhoA": 1.0, "rhoI2": 1e-3, "rhoI3": 1e-3})
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": 2e-3, "t_end": 0.5},
        "beam": [{"name": "rod", "start": [0.0, 0.0, 0.2], "end": [0.9, 0.1, 0.6], "spans": 8,
                  "formulation": formulation, "section": section, **({"quadrature": "full"}
                                                                     if formulation == "director" else {})}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
        "contact": [{"type": "plane", "beam": "rod", "point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0],
                     "stiffness": 2e4}],
        "output": {"track": [{"beam": "rod", "at": 0.0}]},
    })


def rod_on_a_ball(integrator: str = "energy-momentum") -> slidebeam.Scene:
    """The rod of dropped_rod falling onto a ball of radius 0.3 m under its middle."""
    data = dict(dropped_rod("director", integrator).data)
    data["contact"] = [{"type": "sphere", "beam": "rod", "center": [0.45, 0.05, -0.1], "radius": 0.3,
                        "stiffness": 2e4}]
    return slidebeam.scene_from_dict(data)


def test_energy_is_conserved_on_a_ball():
    """The rod lands on the ball, rolls off it and swings: H to the Newton tolerance."""
    records = slidebeam.Simulation(rod_on_a_ball()).run_dynamic().records
    H = np.array([r.total_energy for r in records])
    K = max(r.kinetic_energy for r in records)
    assert K > 1.0 and np.abs(H - H[0]).max() <= 1e-9 * K
    midpoint = slidebeam.Simulation(rod_on_a_ball("midpoint")).run_dynamic().records
    assert max(abs(r.total_energy - midpoint[0].total_energy) for r in midpoint) > 1e3 * np.abs(H - H[0]).max()


def test_a_taut_rope_over_a_drum_keeps_its_tension():
    """A rope with pretension T drawn over a frictionless drum (radius R, axis along y) and held at
    its ends: the drum turns it through 90 degrees, its tension over the drum above the free
    parts' by the bed's energy per length, 1/2 k d^2 = T^2 / (2 k R^2) (9.5e-4 of T here: a
    rope leaving a compliant bed gains it as tension), and it sinks d = T / (R k) into the drum
    where it wraps (within 1 %). The jump: 1.7e-3 at 60 spans, 1.1e-3 at 120, 0.96e-3 at 240."""
    T, R, k = 1.0e3, 0.5, 1.0e6
    free = 1.0  # the straight parts, leaving the drum 45 degrees from its top on either side
    arc = [(R * np.sin(a), 0.0, -R + R * np.cos(a)) for a in np.linspace(-np.pi / 4, np.pi / 4, 61)]
    c = 0.5**0.5
    ends = [(-arc[-1][0] - free * c, 0.0, arc[-1][2] - free * c), (arc[-1][0] + free * c, 0.0, arc[-1][2] - free * c)]
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "static", "steps": 1},
        "beam": [{"name": "rope", "polyline": [list(ends[0]), *map(list, arc), list(ends[1])], "spans": 60,
                  "pretension": T,
                  "section": {"EA": 1e6, "kGA": 5e5, "GJ": 1e-2, "EI2": 1e-2, "EI3": 1e-2, "rhoA": 1.0,
                              "rhoI2": 1e-6, "rhoI3": 1e-6}}],
        "support": [{"type": "spherical", "beam": "rope", "at": "start"},
                    {"type": "spherical", "beam": "rope", "at": "end"}],
        "contact": [{"type": "cylinder", "beam": "rope", "point": [0.0, 0.0, -R], "axis": [0.0, 1.0, 0.0],
                     "radius": R, "stiffness": k}],
    })
    sim = slidebeam.Simulation(scene)
    assert all(r.converged for r in sim.solve_static())
    f = sim.sample_beam("rope", samples_per_span=2)
    tension = f["tension"]
    jump = tension[len(tension) // 2] / tension[0] - 1.0
    assert tension[0] / (2 * k * R * R) < jump < 2e-3  # the bed's energy, plus the mesh's error
    wrapped = f["position"][np.abs(f["position"][:, 0]) < 0.2 * R]
    depth = R - np.hypot(wrapped[:, 0], wrapped[:, 2] + R)
    assert np.allclose(depth, tension[0] / (R * k), rtol=0.01)


@pytest.mark.parametrize("formulation", ("director", "ancf"))
def test_energy_is_conserved_through_touch_down_and_lift_off(formulation):
    """Under energy-momentum the contact's discrete gradient makes its work exactly the change of
    its potential: H stays at the Newton tolerance while the rod lands, bounces and rocks (no
    event located); the rod's end reaches the ground and leaves it again."""
    sim = slidebeam.Simulation(dropped_rod(formulation))
    outcome = sim.run_dynamic()
    assert outcome.complete
    records = outcome.records
    H = np.array([r.total_energy for r in records])
    K = max(r.kinetic_energy for r in records)
    assert K > 1.0 and np.abs(H - H[0]).max() <= 1e-9 * K
    z = np.array([r.tracked[0][2] for r in records])
    touched = np.flatnonzero(z < 0.0)
    assert touched.size and z[touched[-1]:].max() > 1e-3  # down into the bed, and up again
    midpoint = slidebeam.Simulation(dropped_rod(formulation, "midpoint")).run_dynamic().records
    drift = max(abs(r.total_energy - midpoint[0].total_energy) for r in midpoint)
    assert drift > 1e3 * np.abs(H - H[0]).max()  # what the discrete gradient is for


def test_a_rope_on_the_ground_sinks_w_over_k():
    """A rope lying on the ground, held at its ends: at rest its middle sinks w / k into the bed
    (statics, load steps). The ends' disturbance decays over (4 EI / k)^(1/4) = 0.14 m, which the
    spans must resolve: with 1 m spans the middle's depth wavers by 5 %."""
    k, w = 1e5, 9.81 * 2.0
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "static", "steps": 2},
        "beam": [{"name": "rope", "start": [0.0, 0.0, 0.0], "end": [10.0, 0.0, 0.0], "spans": 80,
                  "section": {"EA": 1e6, "kGA": 5e5, "GJ": 10.0, "EI2": 10.0, "EI3": 10.0, "rhoA": 2.0,
                              "rhoI2": 1e-4, "rhoI3": 1e-4}}],
        "support": [{"type": "clamp", "beam": "rope", "at": "start"}, {"type": "spherical", "beam": "rope", "at": "end"}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
        "contact": [{"type": "plane", "beam": "rope", "point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0],
                     "stiffness": k}],
    })
    sim = slidebeam.Simulation(scene)
    assert all(r.converged for r in sim.solve_static())
    f = sim.sample_beam("rope", samples_per_span=1)
    middle = (f["s"] > 3.0) & (f["s"] < 7.0)
    assert np.allclose(f["position"][middle, 2], -w / k, rtol=1e-6)  # measured 3e-10


def mooring(k: float = 1e7, spans: int = 110, formulation: str = "director") -> slidebeam.Scene:
    """220 m of chain (EA 5e8 N, 1000 N/m submerged) from an anchor on the seabed (50 m deep) to a
    fairlead at the surface 200 m away, drawn along the seabed and then straight up to the
    fairlead (its unstretched length: the corner is not stress free); a director beam or an ANCF
    cable."""
    section = ({"EA": 5e8, "EI": 1e3, "rhoA": 1000.0 / 9.81} if formulation == "ancf" else
               {"EA": 5e8, "kGA": 1e8, "GJ": 1e3, "EI2": 1e3, "EI3": 1e3, "rhoA": 1000.0 / 9.81, "rhoI2": 1e-2,
                "rhoI3": 1e-2})
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "start": "equilibrium", "dt": 0.1, "t_end": 0.1},
        "beam": [{"name": "chain", "polyline": [[0.0, 0.0, -50.0], [147.5, 0.0, -50.0], [200.0, 0.0, 0.0]],
                  "unstretched_length": 220.0, "spans": spans, "formulation": formulation, "section": section}],
        "support": [{"type": "spherical", "beam": "chain", "at": "start"},
                    {"type": "spherical", "beam": "chain", "at": "end"}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
        "contact": [{"type": "plane", "beam": "chain", "point": [0.0, 0.0, -50.0], "normal": [0.0, 0.0, 1.0],
                     "stiffness": k}],
    })


@pytest.mark.parametrize("formulation", ("director", "ancf"))
def test_mooring_line_on_the_seabed_matches_the_closed_form_catenary(formulation):
    """The fairlead tension, the anchor's horizontal pull and the suspended shape against the
    quasi-static catenary on a frictionless seabed (MooringLine): within 1e-3 (measured 1.3e-4 and
    2.0e-4 at 110 spans, 1.6e-5 and 2.0e-5 at 220; the ANCF cable drawn as the same polyline,
    110 elements: 4.7e-6 and 1.1e-5)."""
    exact = MooringLine(span=200.0, height=50.0, length=220.0, EA=5e8, w=1000.0)
    sim = slidebeam.Simulation(mooring(formulation=formulation))
    outcome = sim.run_dynamic()
    assert outcome.complete and sim.settled.converged
    f = {r.effect: np.asarray(r.force) for r in sim.reactions()}
    fairlead, anchor = f["spherical[chain@end]"], f["spherical[chain@start]"]
    assert np.linalg.norm(fairlead) == pytest.approx(exact.fairlead_tension, rel=1e-3)
    assert -anchor[0] == pytest.approx(exact.H, rel=1e-3)
    assert abs(anchor[2]) < 1e-2 * exact.H  # it pulls along the bed (the anchor's span's weight: 0.3 kN)
    pos = sim.sample_beam("chain", samples_per_span=4)["position"]
    # the suspended chain: z - z_touchdown = H / w (cosh(w (x - x_touchdown) / H) - 1) (stretch aside)
    hanging = pos[pos[:, 0] > exact.touchdown + 5.0]
    z = -50.0 + exact.H / 1000.0 * (np.cosh(1000.0 * (hanging[:, 0] - exact.touchdown) / exact.H) - 1.0)
    assert np.abs(hanging[:, 2] - z).max() < 0.05  # 5 cm in a 50 m rise
    assert np.abs(pos[pos[:, 0] < exact.touchdown - 5.0, 2] + 50.0).max() < 1e-3  # on the bed
    # the contact's outputs (history columns): the length on the bed, counted at the mass
    # quadrature points (measured 0.17 m short of the exact 130.72 m, spans of 2 m), and the bed's
    # force: that length's weight but for what the anchor carries (measured 0.23 % less)
    assert sim.output_labels() == [f"plane_contact[chain].{n}" for n in ("force.x", "force.y", "force.z", "length")]
    fx, fy, fz, on_bed = outcome.records[-1].outputs
    on_bed_exact = 220.0 - exact.suspended_length
    assert abs(on_bed - on_bed_exact) < 0.5 and fx == fy == 0.0
    assert fz == pytest.approx(1000.0 * on_bed_exact, rel=5e-3) and fz < 1000.0 * on_bed_exact


def test_contact_runs_agree_on_one_and_two_ranks():
    for shape in SHAPES.values():
        distributed_and_serial_records(with_contact(everything_scene("energy-momentum", "full"), **shape))
    distributed_and_serial_records(with_contact(test_ancf.everything_scene("energy-momentum"), **SLOPE))


@pytest.mark.parametrize("entry, words", [
    ({"type": "plane", "beam": "rod", "point": [0, 0, 0], "normal": [0, 0, 0], "stiffness": 1e3}, "normal"),
    ({"type": "plane", "beam": "rod", "point": [0, 0, 0], "normal": [0, 0, 1], "stiffness": -1.0}, "stiffness"),
    ({"type": "plane", "beam": "rod", "normal": [0, 0, 1], "stiffness": 1e3}, "point"),
    ({"type": "cylinder", "beam": "rod", "point": [0, 0, 0], "axis": [0, 0, 0], "radius": 1.0, "stiffness": 1e3},
     "axis"),
    ({"type": "cylinder", "beam": "rod", "point": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0, "stiffness": 1e3},
     "normal"),
    ({"type": "sphere", "beam": "rod", "center": [0, 0, 0], "radius": 0.0, "stiffness": 1e3}, "radius"),
    ({"type": "ball", "beam": "rod", "center": [0, 0, 0], "radius": 1.0, "stiffness": 1e3}, "type"),
])
def test_contact_tables_are_validated(entry, words):
    data = dict(dropped_rod("director").data)
    data["contact"] = [entry]
    with pytest.raises(slidebeam.SceneError) as err:
        slidebeam.Simulation(slidebeam.scene_from_dict(data))  # the table's keys, then the plane itself
    assert "[[contact]] #1" in str(err.value) and words in str(err.value)


CARRIED = {  # shapes carried by a body: a ball, and a drum whose axis (along y as drawn) turns with it
    "ball": {"type": "sphere", "radius": 0.25},
    "drum": {"type": "cylinder", "axis": [0.0, 1.0, 0.0], "radius": 0.25},
}


def thrown_at_rope(shape: str = "ball", integrator: str = "energy-momentum", formulation: str = "director", *,
                   supported: bool = False, t_end: float = 1.0, dt: float = 0.005, height: float = 0.235,
                   aside: float = 0.0) -> slidebeam.Scene:
    """A 5 kg body carrying a ball or a drum (radius 0.25 m) thrown spinning at a 4 m rope, `height`
    above it and `aside` off it: free in space (both momenta kept) or, supported, a rope held at its
    ends under gravity, the body right above it (a ball would slide off a single rope's side). At 0.235 the
    shape starts pressed 1.5 cm into the rope (5 cm into the slack, straight rope took Newton over
    100 iterations on a step of 0.01)."""
    section = ({"EA": 1e5, "EI": 1.0, "rhoA": 1.0} if formulation == "ancf" else
               {"EA": 1e5, "kGA": 5e4, "GJ": 1.0, "EI2": 1.0, "EI3": 1.0, "rhoA": 1.0, "rhoI2": 1e-4,
                "rhoI3": 1e-4})
    data: dict = {
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": dt, "t_end": t_end},
        "beam": [{"name": "rope", "start": [-2.0, 0.0, 0.0], "end": [2.0, 0.0, 0.0], "spans": 16,
                  "formulation": formulation, "section": section}],
        "body": [{"name": shape, "mass": 5.0, "inertia": [0.125, 0.2, 0.125],
                  "position": [0.3, aside, height],
                  "orientation": [0.0, 0.0, 0.0] if supported else [0.1, 0.0, 0.2],
                  "velocity": [0.5, 0.0, -2.0], "angular_velocity": [0.0, 3.0, 0.0 if supported else 1.0]}],
        "contact": [{"beam": "rope", "body": shape, "stiffness": 1e5, **CARRIED[shape]}],
        "output": {"track": [{"body": shape}]},
    }
    if supported:
        data["support"] = [{"type": "spherical", "beam": "rope", "at": "start"},
                           {"type": "spherical", "beam": "rope", "at": "end"}]
        data["gravity"] = {"g": [0.0, 0.0, -9.81]}
    return slidebeam.scene_from_dict(data)


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("shape", CARRIED)
@pytest.mark.parametrize("formulation", ("director", "ancf"))
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_a_shape_carried_by_a_body_has_the_step_jacobian_of_finite_differences(integrator, formulation, shape):
    sim = slidebeam.Simulation(thrown_at_rope(shape, integrator, formulation))
    assert sim.energies()["potential"] > 0.0  # pressed into the rope at t = 0
    base, n = sim.control_point_unknowns(sim.first_control_point(sim.scene.bodies[0].index))
    check_step_jacobian_and_rows(sim, list(range(base, base + n)), seed=3, label=f"{shape}, {formulation}, {integrator}")


@pytest.mark.parametrize("shape", CARRIED)
@pytest.mark.parametrize("formulation", ("director", "ancf"))
def test_a_body_thrown_at_a_free_rope_keeps_energy_and_both_momenta(formulation, shape):
    """Body and rope alone in space: the contact's forces (and, for the drum, their moment on the
    body's axes) cancel and, under energy-momentum, the force is the exact discrete gradient, so
    energy (1e-12 of H) and the linear and angular momentum of the pair (1e-12) are kept through
    the impact; the body is slowed by it."""
    run = slidebeam.Simulation(thrown_at_rope(shape, formulation=formulation, height=0.3, aside=0.1)).run_dynamic()
    assert run.complete, run.message
    d = drifts(run.records)
    assert d["energy"] <= 1e-12 and d["linear"] <= 1e-12 and d["angular"] <= 1e-12, d
    z = np.array([r.tracked[-1][2] for r in run.records])
    assert z[-1] - z[0] > -2.0 * 1.0 + 0.1  # it lost speed to the rope


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("shape", CARRIED)
def test_a_body_dropped_on_a_held_rope_bounces_back_keeping_energy(shape):
    """The rope held at its ends under gravity catches the body and throws it back up (its
    centre rises again after its lowest point); energy to 1e-10 of the largest kinetic energy
    through catch and release; the midpoint rule, on the same run, drifts."""
    run = slidebeam.Simulation(thrown_at_rope(shape, supported=True, height=0.5, t_end=1.2)).run_dynamic()
    assert run.complete, run.message
    z = np.array([r.tracked[-1][2] for r in run.records])
    low = int(np.argmin(z))
    assert z[low] < 0.0 and z[low:].max() > z[low] + 0.3
    H = np.array([r.total_energy for r in run.records])
    K = max(r.kinetic_energy for r in run.records)
    assert np.abs(H - H[0]).max() <= 1e-10 * K
    midpoint = slidebeam.Simulation(thrown_at_rope(shape, "midpoint", supported=True, height=0.5,
                                                   t_end=1.2)).run_dynamic()
    assert max(abs(r.total_energy - H[0]) for r in midpoint.records) > 1e3 * np.abs(H - H[0]).max()


def test_carried_shapes_run_alike_on_one_and_two_ranks():
    for shape in CARRIED:
        distributed_and_serial_records(thrown_at_rope(shape, t_end=0.1, dt=0.01))


@pytest.mark.skip_in_parallel
def test_the_winch_reels_its_rope_onto_the_drum(root):
    """runs/multibody/winch.toml: a drum turned half a turn reels in pi R of rope (the load rises
    by it, to 2 mm: the rope's stretch under the load's swing), the wound rope lies on the drum
    (the first pi R of it within 1.5 mm of the drum's radius, sunk by the bed's give T / (R k) =
    0.66 mm to 10 % between its ends, where the rope bends onto and off the drum), no step is cut,
    and the energy balance closes with the drive's work (1e-9 of it)."""
    sim = slidebeam.Simulation(slidebeam.load_scene(root / "runs" / "multibody" / "winch.toml",
                                                    ["analysis.t_end=4.5"]))
    run = sim.run_dynamic()
    assert run.complete and run.records[-1].rejected_steps == 0, run.message
    R = 0.305
    rise = run.records[-1].tracked[0][2] - run.records[0].tracked[0][2]
    assert abs(rise - np.pi * R) < 2e-3, rise
    wound = sim.evaluate("rope", np.linspace(0.05, np.pi * R - 0.05, 12))[:, :3]
    centre = sim.control_points(sim.scene.bodies[0].index)[0, :3]
    radial = np.hypot(wound[:, 0] - centre[0], wound[:, 2] - centre[2])
    assert np.all((radial < R) & (radial > R - 1.5e-3)), radial
    T = (20.0 + 0.15 * 3.04) * 9.81  # the load and the hanging rope
    assert abs(np.mean(R - radial[1:-1]) / (T / (R * 1e6)) - 1) < 0.1, radial
    work = run.records[-1].work
    assert work > 150.0 and max(abs(r.energy_balance_error) for r in run.records) <= 1e-9 * work


@pytest.mark.skip_in_parallel
def test_the_block_and_tackle_hangs_its_block_on_half_its_weight(root):
    """runs/multibody/block_and_tackle.toml, the equilibrium start: on frictionless sheaves the
    rope's tension changes only with height, T(z) = T0 + w z (w its weight per length), and the
    block hangs on both sides of its pulley, 2 T0 = m g + w pi r. So the free end (z = 0.5) pulls
    T0 + 0.5 w (to 1e-4; 3.5e-5 measured) and the anchor (z = 2) T0 + 2 w (to 5e-4; 2e-4: the
    block settles 2.6 mm below its drawing, and the beds give)."""
    sim = slidebeam.Simulation(slidebeam.load_scene(root / "runs" / "multibody" / "block_and_tackle.toml",
                                                    ["analysis.t_end=0.005"]))
    first = sim.run_dynamic().records[0]
    g, w, r = 9.81, 0.1 * 9.81, 0.205
    T0 = (40.0 * g + w * np.pi * r) / 2
    pulls = {f.effect: -f.force[2] for f in first.reactions}
    assert abs(pulls["spherical[rope@end]"] / (T0 + 0.5 * w) - 1) < 1e-4, pulls
    assert abs(-pulls["spherical[rope@start]"] / (T0 + 2.0 * w) - 1) < 5e-4, pulls


def test_contact_outputs_are_history_columns(tmp_path):
    """The contact's force and length in contact go to history.csv as <label>.force.x/y/z and
    .length, bit for bit the records' values, and come back from the history table a checkpoint
    keeps; summary.json has the last values, and the outputs plot draws the history's. While
    the rod lands the bed pushes up; before it lands, and high in its bounce, nothing."""
    import csv

    from slidebeam.output import history

    from mpi4py import MPI

    data = dict(dropped_rod("director").data)
    data["analysis"] = {**data["analysis"], "t_end": 0.3}
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(data), MPI.COMM_SELF)  # each rank its own folder
    outcome = sim.run_dynamic()
    slidebeam.write_results(sim, outcome, tmp_path)
    with open(tmp_path / "history.csv") as f:
        rows = list(csv.DictReader(f))
    names = [f"plane_contact[rod].{n}" for n in ("force.x", "force.y", "force.z", "length")]
    assert sim.output_labels() == names
    table = np.array([[float(row[n]) for n in names] for row in rows])
    assert np.array_equal(table, np.array([r.outputs for r in outcome.records]))
    assert table[0].tolist() == [0.0, 0.0, 0.0, 0.0]  # drawn above the ground
    landed = table[:, 3] > 0.0
    assert landed.any() and (table[landed, 2] > 0.0).all() and (table[~landed, :3] == 0.0).all()
    values, reasons, layout = history.table(outcome.records, len(sim.energy_flow_labels()))
    assert layout.outputs == 4 and history.Layout.from_dict(layout.as_dict()) == layout
    assert [r.outputs for r in history.records(values, reasons, layout)] == [r.outputs for r in outcome.records]
    import json

    from slidebeam import plots
    from slidebeam.output.rundata import open_run

    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["outputs"] == {"plane_contact[rod]": dict(zip(("force.x", "force.y", "force.z", "length"),
                                                                 outcome.records[-1].outputs))}
    run = open_run(tmp_path)
    assert "outputs" in plots.available(run)
    fig = plots.figure("outputs", [run])
    lines = {ln.get_label(): ln.get_ydata() for a in fig.axes for ln in a.get_lines()}
    assert np.array_equal(lines["length"], table[:, 3]) and np.array_equal(lines["force.z"], table[:, 2])


def test_two_contacts_on_one_beam_have_their_own_columns():
    """A second [[contact]] on the same beam reports under the label the history gives it (#2)."""
    data = dict(dropped_rod("director").data)
    data["contact"] = [*data["contact"], {"type": "plane", "beam": "rod", "point": [0.0, 0.0, -0.1],
                                          "normal": [0.0, 0.0, 1.0], "stiffness": 1e3}]
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(data))
    assert list(sim.output_groups()) == ["plane_contact[rod]", "plane_contact[rod]#2"]
    assert len(set(sim.output_labels())) == 8
