# SPDX-License-Identifier: MIT
"""Ropes by their unstretched length or pretension (issue 37, item 3): the stress-free state is a
straight rope of that length, the drawing only where the rope starts. The tension, the weight,
the strains and the hanging shape are the rope's; energy-momentum stays exact."""
from __future__ import annotations

import math

import numpy as np
import pytest

import slidebeam
from slidebeam.scene.catenary import ElasticCatenary
from slidebeam.scene import SceneError, stretch_at_tension

EA, RHO_A, G = 1.0e7, 1.0, 9.81


ANCF_SECTION = {"EA": EA, "EI": 10.0, "rhoA": RHO_A}


def rope_scene(beam: dict, *, quadrature: str = "auto", gravity: bool = True, dynamic: bool = False,
               t_end: float = 0.02) -> dict:
    analysis = ({"type": "dynamic", "start": "equilibrium", "t_end": t_end, "dt": 0.01} if dynamic
                else {"type": "static", "steps": 1})
    scene = {
        "scene": {"name": "rope"},
        "analysis": analysis,
        "beam": [{"name": "rope", "start": [0.0, 0.0, 0.0], "end": [100.0, 0.0, 0.0], "spans": 40,
                  "quadrature": quadrature,
                  "section": {"EA": EA, "kGA": 3.5e6, "GJ": 8.0, "EI2": 10.0, "EI3": 10.0, "rhoA": RHO_A,
                              "rhoI2": 1e-5, "rhoI3": 1e-5}, **beam}],
        "support": [{"type": "spherical", "beam": "rope", "at": "start"},
                    {"type": "spherical", "beam": "rope", "at": "end"}],
    }
    if gravity:
        scene["gravity"] = {"g": [0.0, 0.0, -G]}
    if beam.get("formulation") == "ancf":
        scene["beam"][0].pop("quadrature")
        scene["beam"][0]["section"] = ANCF_SECTION
    return scene


def reactions(sim: slidebeam.Simulation) -> dict[str, np.ndarray]:
    return {r.effect: np.asarray(r.force) for r in sim.reactions()}


@pytest.mark.parametrize("quadrature", ["full", "assumed_strain", "ancf"])
def test_pretension_is_the_tension_of_the_straight_rope(quadrature):
    """A straight rope with pretension T between supports, no load: every section carries T, the
    supports T, and the strain output is the rope's own (lambda - 1, or (lambda^2 - 1) / 2 for the
    centre line's measure of assumed strains and the ANCF cable) while the unknowns count along the
    drawing."""
    T = 2.5e4
    ancf = quadrature == "ancf"
    beam = {"pretension": T, **({"formulation": "ancf"} if ancf else {})}
    scene = slidebeam.scene_from_dict(rope_scene(beam, quadrature="full" if ancf else quadrature, gravity=False))
    lam = stretch_at_tension(T / EA, quadrature != "full")
    assert scene.beams[0].unstretched_length == pytest.approx(100.0 / lam, rel=1e-15)
    sim = slidebeam.Simulation(scene)
    sim.solve_static()
    f = reactions(sim)
    assert f["spherical[rope@start]"] == pytest.approx([-T, 0.0, 0.0], rel=1e-9, abs=1e-6)
    samples = sim.sample_beam("rope", samples_per_span=3)
    assert np.allclose(samples["tension"], T, rtol=1e-9)
    axial = lam - 1.0 if quadrature == "full" else 0.5 * (lam * lam - 1.0)
    if ancf:  # (the cable's samples are at its nodes and between them)
        assert np.allclose(np.linalg.norm(samples["force"], axis=1), T, rtol=1e-9)
    assert np.allclose(samples["strain"][:, 0], axial, rtol=1e-9)
    assert samples["s"][-1] == pytest.approx(100.0)


@pytest.mark.parametrize("formulation", ["director", "ancf"])
def test_unstretched_length_longer_than_the_chord_hangs_as_the_elastic_catenary(formulation):
    """100.6 m of rope on a 100 m chord, drawn straight: it starts as an arc of that length sagging
    along gravity and settles on the elastic catenary (support tension within 1e-5; measured
    3e-6 for the director beam), its weight the rope's (rho A L0 g, to roundoff)."""
    L0 = 100.6
    scene = slidebeam.scene_from_dict(rope_scene({"unstretched_length": L0, "formulation": formulation},
                                                 dynamic=True))
    beam = scene.beams[0]
    assert beam.geometry.kind == "arc" and beam.geometry.length == pytest.approx(L0, rel=1e-14)
    assert beam.geometry.point_at(L0 / 2)[2] < -4.0  # sags along gravity
    sim = slidebeam.Simulation(scene)
    outcome = sim.run_dynamic()
    assert outcome.complete and sim.settled.converged
    f = reactions(sim)
    weight = f["spherical[rope@start]"][2] + f["spherical[rope@end]"][2]
    assert weight == pytest.approx(RHO_A * L0 * G, rel=1e-9)
    exact = ElasticCatenary(span=100.0, length=L0, EA=EA, w=RHO_A * G).tension(0.0)
    assert np.linalg.norm(f["spherical[rope@start]"]) == pytest.approx(exact, rel=1e-5)


@pytest.mark.filterwarnings("ignore::slidebeam.run.simulation.ConstraintWarning")  # the supports' ends stay put
def test_a_pretensioned_rope_conserves_energy():
    """A taut rope (stretch 1.002) given a sideways velocity, under energy-momentum: energy to the
    Newton tolerance, no gravity."""
    scene = rope_scene({"pretension": 2.0e4, "velocity": [0.0, 0.5, 0.0]}, gravity=False, dynamic=True, t_end=0.3)
    scene["analysis"]["start"] = "reference"
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(scene))
    outcome = sim.run_dynamic()
    assert outcome.complete
    H = np.array([r.total_energy for r in outcome.records])
    assert H[0] > 1.0 and np.abs(H - H[0]).max() < 1e-9 * H[0]
    T = np.array([r.kinetic_energy for r in outcome.records])
    assert T.min() < 0.9 * T[0]  # the rope swings: energy moves between its forms


@pytest.mark.parametrize("beam, key, text", [
    ({"unstretched_length": 99.0, "pretension": 10.0}, "pretension", "not unstretched_length and pretension"),
    ({"sag": 2.0, "horizontal_tension": 10.0}, "sag", "not horizontal_tension and sag"),
    ({"sag": -2.0}, "sag", "> 0"),
    ({"unstretched_length": -1.0}, "unstretched_length", "> 0"),
    ({"pretension": -5.0}, "pretension", ">= 0"),
    ({"pretension": 10.0, "strain": "seed"}, "pretension", "simo-reissner"),
    # an ANCF cable's stress-free state is straight: a polyline only where it starts, with its length
    ({"formulation": "ancf", "polyline": [[0, 0, 0], [50, 0, -1], [100, 0, 0]]}, "polyline",
     "straight stress-free state"),
])
def test_bad_ropes_are_clear_errors(beam, key, text):
    scene = rope_scene(beam)
    if "polyline" in beam:
        for key in ("start", "end"):
            scene["beam"][0].pop(key)
    with pytest.raises(SceneError) as err:
        slidebeam.scene_from_dict(scene)
    assert key in str(err.value) and text in str(err.value)


def test_a_rope_by_its_horizontal_tension_or_sag():
    """Given by the horizontal tension or the sag of the elastic catenary of 100.6 m, a level rope
    is 100.6 m long; raised 20 m at one end and given a horizontal tension, it settles with that
    horizontal pull at its supports (within 5e-5)."""
    exact = ElasticCatenary(span=100.0, length=100.6, EA=EA, w=RHO_A * G)
    for key, value in (("horizontal_tension", exact.H), ("sag", exact.sag)):
        beam = slidebeam.scene_from_dict(rope_scene({key: value})).beams[0]
        assert beam.unstretched_length == pytest.approx(100.6, rel=1e-9), key
    scene = rope_scene({"horizontal_tension": 3000.0}, dynamic=True)
    scene["beam"][0]["end"] = [100.0, 0.0, 20.0]
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(scene))
    outcome = sim.run_dynamic()
    assert outcome.complete and sim.settled.converged
    for force in reactions(sim).values():
        assert abs(force[0]) == pytest.approx(3000.0, rel=5e-5)  # measured 1.3e-5
    no_gravity = rope_scene({"sag": 2.0}, gravity=False)
    with pytest.raises(SceneError, match="needs \\[gravity\\]"):
        slidebeam.scene_from_dict(no_gravity)


def test_stretch_at_tension():
    assert stretch_at_tension(1e-3, False) == 1.001
    lam = stretch_at_tension(1e-3, True)
    assert lam * (lam * lam - 1.0) / 2.0 == pytest.approx(1e-3, rel=1e-14)
    assert math.isclose(stretch_at_tension(0.0, True), 1.0)


def test_an_ancf_cable_drawn_as_a_polyline_starts_on_it():
    """Given its unstretched length, an ANCF cable may be drawn as a polyline (a mooring chain along
    the seabed and up to its fairlead): its nodes start on the polyline, r' along the sides, at a
    corner their mean direction."""
    polyline = [[0.0, 0.0, 0.0], [50.0, 0.0, 0.0], [100.0, 0.0, 50.0]]
    scene = rope_scene({"formulation": "ancf", "polyline": polyline, "unstretched_length": 130.0, "spans": 4})
    for key in ("start", "end"):
        scene["beam"][0].pop(key)
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(scene))
    nodes = sim.control_points("rope")  # spans + 1 nodes: r, r'
    length = 50.0 + 50.0 * math.sqrt(2.0)
    side = np.array([1.0, 0.0, 1.0]) / math.sqrt(2.0)
    for a, node in enumerate(nodes):
        s = length * a / 4
        expected = (np.array([s, 0.0, 0.0]) if s <= 50.0 else np.array([50.0, 0.0, 0.0]) + (s - 50.0) * side)
        assert np.allclose(node[:3], expected, atol=1e-12)
        assert np.allclose(node[3:6], [1.0, 0.0, 0.0] if s < 50.0 else side, atol=1e-12)
    geometry = slidebeam.scene_from_dict(scene).beams[0].geometry
    mean = np.array([1.0, 0.0, 0.0]) + side
    assert np.allclose(geometry.tangent_at(50.0), mean / np.linalg.norm(mean), atol=1e-12)
