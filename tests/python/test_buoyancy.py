# SPDX-License-Identifier: MIT
"""Buoyancy ([[buoyancy]], issue 39 item 3): the step Jacobian against finite differences under
every integrator (director beams and ANCF cables), energy conserved as a rope falls into the
water, a submerged rope's weight less the water it displaces, a light rope floating half
submerged, gravity taken from [gravity]."""
from __future__ import annotations

import math

import numpy as np
import pytest

import slidebeam
import test_ancf
from checks import check_step_jacobian, distributed_and_serial_records
from test_dynamics import INTEGRATORS, everything_scene

# the water's surface through the test scenes, a wide band of partial submersion (D = 0.3 m)
WATER = {"density": 1000.0, "diameter": 0.03, "surface": [0.0, 0.0, 0.2]}
WIDE = {**WATER, "diameter": 0.3, "density": 10.0}


def with_buoyancy(scene: slidebeam.Scene, **water: object) -> slidebeam.Scene:
    data = dict(scene.data)
    data["buoyancy"] = [{"beam": b.name, **water} for b in scene.beams]
    return slidebeam.scene_from_dict(data)


@pytest.mark.parametrize("formulation", ("director", "ancf"))
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_buoyancy_step_jacobian_matches_finite_differences(integrator, formulation):
    base = everything_scene(integrator, "full") if formulation == "director" else test_ancf.everything_scene(integrator)
    scene = with_buoyancy(base, **WIDE)
    sim = slidebeam.Simulation(scene)
    assert [e.type for e in sim.active_effects].count("buoyancy") == len(scene.beams)
    check_step_jacobian(sim, steps=1, h=0.05, seed=11, label=integrator)


def rope(*, water: dict | None = None, rho_a: float = 2.0, start: list[float] | None = None,
         dynamic: bool = False, formulation: str = "director") -> dict:
    section = ({"EA": 1e5, "EI": 1.0, "rhoA": rho_a} if formulation == "ancf" else
               {"EA": 1e5, "kGA": 5e4, "GJ": 1.0, "EI2": 1.0, "EI3": 1.0, "rhoA": rho_a, "rhoI2": 1e-5,
                "rhoI3": 1e-5})
    start = start or [0.0, 0.0, 0.0]
    return {
        "analysis": ({"type": "dynamic", "integrator": "energy-momentum", "dt": 2e-3, "t_end": 1.0} if dynamic
                     else {"type": "static", "steps": 2}),
        "beam": [{"name": "rope", "start": start, "end": [start[0] + 4.0, start[1], start[2]], "spans": 16,
                  "formulation": formulation, "section": section}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
        "buoyancy": [{"beam": "rope", **(water or WATER)}],
    }


@pytest.mark.parametrize("formulation", ("director", "ancf"))
def test_energy_is_conserved_as_a_rope_falls_into_the_water(formulation):
    """A horizontal rope dropped from 0.3 m above the surface (tilted, so that it enters over
    time) falls in, slows and bobs: H to the Newton tolerance under energy-momentum."""
    data = rope(water={"density": 1000.0, "diameter": 0.06, "surface": [0.0, 0.0, 0.0]}, rho_a=1.5,
                start=[0.0, 0.0, 0.3], dynamic=True, formulation=formulation)
    data["beam"][0]["end"] = [4.0, 0.0, 0.5]
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(data))
    outcome = sim.run_dynamic()
    assert outcome.complete
    H = np.array([r.total_energy for r in outcome.records])
    K = max(r.kinetic_energy for r in outcome.records)
    assert K > 1.0 and np.abs(H - H[0]).max() <= 1e-9 * K
    z = sim.sample_beam("rope", samples_per_span=1)["position"][:, 2]
    assert z.min() < 0.0  # it went in


def test_a_submerged_rope_weighs_less_the_water_it_displaces():
    """Held at both ends 2 m under water, a rope's supports carry (rho A - rho_w pi D^2 / 4) g L."""
    data = rope(start=[0.0, 0.0, -2.0])
    data["support"] = [{"type": "spherical", "beam": "rope", "at": "start"},
                       {"type": "spherical", "beam": "rope", "at": "end"}]
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(data))
    assert all(r.converged for r in sim.solve_static())
    lift = sum(r.force[2] for r in sim.reactions())
    assert lift == pytest.approx((2.0 - 1000.0 * math.pi * 0.03**2 / 4) * 9.81 * 4.0, rel=1e-9)


@pytest.mark.parametrize("formulation", ("director", "ancf"))
def test_a_light_rope_floats_half_submerged(formulation):
    """A rope of half the water's density per displaced volume, free, settles with its centre
    line on the surface (chi = 1/2); dropped in from above (the equilibrium start)."""
    D, rho_w = 0.03, 1000.0
    data = rope(water={"density": rho_w, "diameter": D, "surface": [0.0, 0.0, 0.0]}, rho_a=0.5 * rho_w * math.pi * D * D / 4,
                start=[0.0, 0.0, 0.01], dynamic=True, formulation=formulation)
    data["analysis"].update({"start": "equilibrium", "t_end": 2e-3})
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(data))
    sim.run_dynamic()
    assert sim.settled.converged
    z = sim.sample_beam("rope", samples_per_span=2)["position"][:, 2]
    assert np.abs(z).max() < 1e-6 * D


def test_buoyancy_takes_the_scene_s_gravity():
    data = rope()
    data["gravity"] = {"g": [0.0, -3.0, 0.0]}
    scene = slidebeam.scene_from_dict(data)
    assert scene.entries("buoyancy")[0].vec["g"] == [0.0, -3.0, 0.0]
    data.pop("gravity")
    with pytest.raises(slidebeam.SceneError, match="buoyancy needs gravity"):
        slidebeam.scene_from_dict(data)
    data["buoyancy"][0]["g"] = [0.0, 0.0, -9.81]  # its own: the water weighs, the rope does not
    assert slidebeam.scene_from_dict(data).entries("buoyancy")[0].vec["g"] == [0.0, 0.0, -9.81]


def test_buoyancy_runs_agree_on_one_and_two_ranks():
    distributed_and_serial_records(with_buoyancy(everything_scene("energy-momentum", "full"), **WIDE))
