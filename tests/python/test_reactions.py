# SPDX-License-Identifier: MIT
"""Reactions of supports and rigid joints (history.csv, summary.json, Simulation.reactions): in
statics they balance the loads and weights, with moments about the held points; over a time
step they balance gravity and the step's change of linear momentum to the Newton tolerance."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import slidebeam
from checks import hanger_toml, static_scene_text

ROOT = Path(__file__).resolve().parents[2]
G = np.array([0.0, 0.0, -9.81])


def by_effect(reactions) -> dict[str, slidebeam.Reaction]:
    return {r.effect: r for r in reactions}


@pytest.mark.parametrize("quadrature", ["full", "assumed_strain"])
def test_clamp_and_rigid_joint_balance_the_loads(quadrature):
    """An L-frame: beam a clamped at the origin, beam b welded to its end, a force at b's end and
    gravity. Clamp: force = -(loads + weights), moment about the clamp = -sum r x f. The rigid
    joint's force and moment on a are what b carries: its load and weight."""
    rho_a = 2.0
    scene = slidebeam.scene_from_dict({
        "analysis": {"type": "static", "steps": 4},
        "beam": [{"name": "a", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 6, "quadrature": quadrature,
                  "section": {"EA": 1e5, "kGA": 1e5, "GJ": 50.0, "EI2": 80.0, "EI3": 80.0, "rhoA": rho_a}},
                 {"name": "b", "start": [1, 0, 0], "end": [1, 0.8, 0], "spans": 4, "quadrature": quadrature,
                  "section": {"EA": 1e5, "kGA": 1e5, "GJ": 50.0, "EI2": 80.0, "EI3": 80.0, "rhoA": rho_a}}],
        "rigid_joint": [{"beams": ["a", "b"], "at": ["end", "start"]}],
        "support": [{"type": "clamp", "beam": "a", "at": "start"}],
        "load": [{"type": "force", "beam": "b", "at": "end", "value": [3.0, -2.0, 5.0]}],
        "gravity": {"g": G.tolist()},
    })
    sim = slidebeam.Simulation(scene)
    assert sim.solve_static()[-1].converged
    r = by_effect(sim.reactions())
    assert set(r) == {"clamp[a@start]", "rigid_joint[a@end-b@start]"}
    F = np.array([3.0, -2.0, 5.0])
    # forces and moments about the clamp of everything but the clamp: the load and the weights
    s = np.linspace(0.0, 1.0, 2001)
    pa = sim.evaluate("a", s)[:, :3]
    pb = sim.evaluate("b", s * 0.8)[:, :3]
    tip = sim.evaluate("b", 0.8)[0, :3]
    wa, wb = rho_a * 1.0 * G, rho_a * 0.8 * G
    # weights per unit length integrated by the trapezoidal rule on a fine sampling (moment arms)
    ma = np.trapz(np.cross(pa, rho_a * G), s, axis=0)
    mb = np.trapz(np.cross(pb, rho_a * G), s * 0.8, axis=0)
    clamp = r["clamp[a@start]"]
    scale = np.linalg.norm(F) + np.linalg.norm(wa + wb)
    assert np.allclose(clamp.force, -(F + wa + wb), atol=1e-8 * scale)
    assert np.allclose(clamp.moment, -(np.cross(tip, F) + ma + mb), atol=1e-5 * scale)  # trapezoid: 1e-7
    joint = r["rigid_joint[a@end-b@start]"]
    end_a = sim.evaluate("a", 1.0)[0, :3]
    assert np.allclose(joint.force, F + wb, atol=1e-8 * scale)
    assert np.allclose(joint.moment, np.cross(tip - end_a, F) + mb - np.cross(end_a, wb), atol=1e-5 * scale)


def test_static_zip_line_reactions_balance_the_weights():
    """A horizontal rope with a trolley that slides freely to rest (the equilibrium start): the
    two supports carry the rope, the hanger and the trolley, to 1e-8 of the weight."""
    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "zip_line.toml", [
        "beam.0.end=[20,0,0]", "beam.1.start=[9,0,0]", "beam.1.end=[9,0,-0.5]", 'sliding_joint.0.static="free"'])
    sim = slidebeam.Simulation(scene)
    assert sim.settle().converged
    rope, hanger = scene.beams
    weight = (rope.section.rhoA * rope.geometry.length + hanger.section.rhoA * hanger.geometry.length + 80.0) * G
    total = sum(np.array(r.force) for r in sim.reactions())
    assert np.allclose(total, -weight, atol=1e-8 * np.linalg.norm(weight))
    (joint,) = sim.joint_states()
    # the landscape is flat near the middle (with a rope of fixed length the trolley rises by about 2 mm
    # over 0.7 m): the rope's discretisation ripple decides where in it the trolley rests (40
    # assumed-strain spans, the default here: 9.32; full quadrature 9.90)
    assert 9.0 < joint.s < 11.0 and joint.gap < 1e-9
    # the trolley's weight reaches the rope through the joint (the carrier's force on the slider)
    assert joint.reaction[2] == pytest.approx(-(hanger.section.rhoA * 0.5 + 80.0) * G[2], rel=1e-6)


def test_static_runs_report_sliding_joints(tmp_path):
    """A static run's records carry the sliding joints' s, reaction and gap, as dynamic ones do:
    a trolley held on the hanging rope (drawn in its sag: statics from a straight rope is a
    mechanism). The first of 4 load steps hangs the trolley on the rope at once: the hanger is
    free to turn about its own axis (a singular tangent), which Newton cannot take and the
    pseudo-transient continuation does (87 Newton iterations before, in Newton's fall-backs on
    the whole system; 36 now, 52 under mpirun, where no zero pivot ends the first attempt)."""
    text = static_scene_text(ROOT / "runs" / "cables" / "hanging_rope.toml", steps=4)
    text += hanger_toml("rope", (10.0, 0.0, -2.0), 0.5) + """
[[point_mass]]
beam = "hanger"
at = "end"
mass = 10.0
"""
    path = tmp_path / "rope_with_trolley.toml"
    path.write_text(text)
    sim = slidebeam.Simulation(slidebeam.load_scene(path))
    records = sim.solve_static()
    assert records[-1].converged and sim.load_step_cuts == 0
    assert sim.load_step_continuations == 1 and records[1].reason == "CONVERGED_BY_CONTINUATION"
    assert records[1].newton_iterations <= 55 and sum(r.newton_iterations for r in records[2:]) <= 25
    (joint,) = records[-1].joints
    assert joint.s == pytest.approx(10.26, abs=0.05) and joint.gap < 1e-9 and joint.reaction[2] > 90.0
    total = sum(np.array(r.force) for r in records[-1].reactions)
    assert total[2] > 10.0 * 9.81  # the supports carry the trolley too


SHAKEN_GRAVITY = 'gravity.time_function={type = "sine", amplitude = 0.5, frequency = 5.0, offset = 1.0}'


@pytest.mark.parametrize("shaken", [False, True], ids=["constant", "sine_gravity"])
@pytest.mark.parametrize("integrator", ["energy-momentum", "midpoint"])
def test_dynamic_reactions_balance_gravity_and_the_change_of_momentum(integrator, shaken):
    """Steps of the zip line (the trolley running down): (p_n+1 - p_n) / h = m g f(t_n+1/2) + the
    support reactions over the step, to the Newton tolerance (measured 3e-8 N against a weight of
    972 N). With gravity varying in time (f: a sine), the reactions must be those of the step
    just taken, at its own times, not the next one's. (Newmark and HHT balance momentum with
    their own average of forces: their reactions are at t_n+1.)"""
    sets = [f'analysis.integrator="{integrator}"', *([SHAKEN_GRAVITY] if shaken else [])]
    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "zip_line.toml", sets)
    sim = slidebeam.Simulation(scene)
    assert sim.settle().converged
    rope, hanger = scene.beams
    mass = rope.section.rhoA * rope.geometry.length + hanger.section.rhoA * hanger.geometry.length + 80.0
    h = scene.analysis.dt
    f = (lambda t: 1.0 + 0.5 * math.sin(2 * math.pi * 5.0 * t)) if shaken else (lambda t: 1.0)
    p0 = np.array(sim.integrator.motion()[1])
    worst = 0.0
    for _ in range(15):
        t0 = sim.t
        assert sim.integrator.step(h).converged
        p1 = np.array(sim.integrator.motion()[1])
        reactions = sim.reactions(over_last_step=True)
        assert {r.effect for r in reactions} == {"spherical[rope@start]", "spherical[rope@end]"}
        weight = mass * G * f(t0 + 0.5 * h)
        worst = max(worst, float(np.linalg.norm((p1 - p0) / h - weight - sum(np.array(r.force) for r in reactions))))
        p0 = p1
    assert worst < 1e-8 * mass * 9.81, worst


@pytest.mark.skip_in_parallel
def test_reactions_are_in_history_and_summary(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "roll", "--set", "beam.0.spans=8",
                  "--set", "analysis.steps=2")
    assert out.returncode == 0, out.stderr
    import csv
    import json

    header = next(csv.reader((tmp_path / "roll" / "history.csv").open()))
    assert [h for h in header if h.startswith("clamp[")] == [f"clamp[strip@start].{c}" for c in
                                                            ("fx", "fy", "fz", "mx", "my", "mz")]
    summary = json.loads((tmp_path / "roll" / "summary.json").read_text())
    (clamp,) = summary["reactions"]
    assert clamp["effect"] == "clamp[strip@start]"
    # the end moment 2 pi EI / L about z, and no force
    assert clamp["moment"] == pytest.approx([0.0, 0.0, -2 * math.pi * 100.0 / 10.0], abs=1e-6)
    assert clamp["force"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-6)


def test_reading_reactions_leaves_a_prepared_step_alone(root):
    """Reactions and joint forces are the last step's: they are evaluated with that step's start,
    and the model's step start is set back to the next step's afterwards, so that a step prepared
    before (prepare_step) has the same residual after sim.joint_states() as before it (it moved
    back a step)."""
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(root / "runs" / "seed" / "free_fall_inclined_1+4.toml"))
    integ = sim.integrator
    for _ in range(3):
        assert integ.step(1e-3).converged
    integ.prepare_step(1e-3)
    x1 = integ.x.copy()
    x1.axpy(1e-3, integ.v)
    before, after = x1.duplicate(), x1.duplicate()
    integ.step_residual(x1, before)
    sim.joint_states()
    sim.reactions()
    integ.step_residual(x1, after)
    after.axpy(-1.0, before)
    assert after.norm() == 0.0, after.norm()
