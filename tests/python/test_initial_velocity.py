# SPDX-License-Identifier: MIT
"""Consistent initial velocities (issue 21): a scene's initial velocities are projected onto the
constraints' velocity level with the mass metric before the first step, with a warning when
they violated them; the sliding rates follow from the projection."""
from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI
from petsc4py import PETSc

import slidebeam

ROOT = Path(__file__).resolve().parents[2]
INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")


def seed(**sets: object) -> slidebeam.Scene:
    return slidebeam.load_scene(ROOT / "runs" / "seed" / "free_fall_1+4.toml", [f"{k}={v}" for k, v in sets.items()])


def simulation(scene: slidebeam.Scene, project: bool = True) -> tuple[slidebeam.Simulation, list[str]]:
    """The simulation and the ConstraintWarnings its start raised (-sb_project_velocity false:
    the velocities as given, sliding rates 0, as before issue 21)."""
    opts = PETSc.Options()
    if not project:
        opts.setValue("sb_project_velocity", "false")
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            sim = slidebeam.Simulation(scene)
    finally:
        opts.delValue("sb_project_velocity")
    return sim, [str(w.message) for w in caught if issubclass(w.category, slidebeam.ConstraintWarning)]


def velocity_constraint_residual(sim: slidebeam.Simulation, eps: float = 1e-6) -> float:
    """max |d/dt Phi| over every constraint row (orthonormality, supports, the joint) for the
    integrator's velocity v and sliding rates: the central difference of the static residual's
    constraint rows along (v, sdot) (collective)."""
    integ = sim.integrator
    w = integ.v.copy()
    w.axpy(1.0, integ.sliding_rate)
    xp, xm, Fp, Fm = (integ.x.duplicate() for _ in range(4))
    integ.x.copy(xp)
    xp.axpy(eps, w)
    integ.x.copy(xm)
    xm.axpy(-eps, w)
    sim.residual(x=xp).copy(Fp)
    sim.residual(x=xm).copy(Fm)
    Fp.axpy(-1.0, Fm)
    Fp.scale(0.5 / eps)
    # constraint rows: multipliers (not coordinates, not sliding coordinates) and supports' rows
    rows = set(range(*Fp.getOwnershipRange()))
    for cp in range(sum(b.spans + 2 for b in sim.scene.beams)):
        first, nq = sim.control_point_unknowns(cp)
        rows -= set(range(first, first + nq))
    rows -= {sim.sliding_coordinate_index(k) for k in range(len(sim.scene.sliding_joints))}
    rows |= set(sim.prescribed_rows)
    lo = Fp.getOwnershipRange()[0]
    a = Fp.getArray()
    local = max((abs(a[i - lo]) for i in rows), default=0.0)
    for v in (w, xp, xm, Fp, Fm):
        v.destroy()
    return MPI.COMM_WORLD.allreduce(local, op=MPI.MAX)


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_velocity_along_the_carrier_is_a_sliding_rate(integrator):
    """CM moving at 0.3 m/s along AB: consistent, kept as given (no warning), and the sliding
    rate is 0.3 from the start (it was taken as 0)."""
    sim, said = simulation(seed(**{"analysis.integrator": f'"{integrator}"', "analysis.t_end": 0.05,
                                   "beam.CM.velocity": "[0.3, 0, 0]"}))
    assert not said
    p = sim.velocity_projection
    assert p["solved"] and not p["projected"] and p["change"] <= 1e-10 * p["size"]
    assert sim.joint_states()[0].ds_dt == pytest.approx(0.3, abs=1e-12)
    assert velocity_constraint_residual(sim) < 1e-8
    run = sim.run_dynamic()
    assert run.complete and run.rejected_steps == 0
    assert run.newton_iterations <= 3.5 * run.steps
    assert run.records[-1].joints[0].s == pytest.approx(0.4 + 0.3 * 0.05, abs=2e-4)


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_velocity_off_the_carrier_is_projected(integrator):
    """CM given 1 m/s along its own axis, off the carrier AB: projected onto the constraints with
    a warning that says by how much (12 % of the velocity's mass norm, kinetic energy 0.5975 ->
    0.5882); the projected velocity satisfies every velocity-level constraint. Then every scheme
    runs at 3 to 4 Newton iterations a step; Newmark without the projection blew up (energy
    1.5e5 and Newton failure at t = 0.022, serial)."""
    serial = MPI.COMM_WORLD.Get_size() == 1  # (parallel steps of this small scene are slow)
    scene = seed(**{"analysis.integrator": f'"{integrator}"', "analysis.t_end": 0.03 if serial else 0.01, "analysis.dt": 1e-4,
                    "beam.CM.velocity": "[0, 0, 1.0]"})
    sim, said = simulation(scene)
    assert len(said) == 1 and "violate the constraints" in said[0] and "0.125 of their mass norm" in said[0], said
    assert "kinetic energy 0.5975 -> 0.588226" in said[0]
    assert said == sim.warnings
    assert velocity_constraint_residual(sim) < 1e-8
    run = sim.run_dynamic()
    assert run.complete and run.rejected_steps == 0 and run.newton_iterations <= 4.5 * run.steps, run.message
    if integrator == "newmark":
        given, _ = simulation(scene, project=False)
        assert velocity_constraint_residual(given) > 0.1
        if serial:  # (on 2 ranks the Schwarz solves' path gets through)
            assert not given.run_dynamic().complete


def test_projection_keeps_the_momenta_of_a_free_structure():
    """The free-floating two-beam structure with CM given a different velocity than the carrier:
    rigid motions satisfy every constraint, so the projection (orthogonal in the mass metric)
    keeps the linear and angular momentum of the given velocities and only lowers the kinetic
    energy."""
    scene = slidebeam.load_scene(ROOT / "runs" / "free_floating" / "two_beams.toml", ["beam.CM.velocity=[1.5, 1.0, 1.5]"])
    sim, said = simulation(scene)
    given, none = simulation(scene, project=False)
    assert len(said) == 1 and not none
    k1, lin1, ang1 = sim.integrator.motion()
    k0, lin0, ang0 = given.integrator.motion()
    assert np.abs(np.array(lin1) - lin0).max() <= 1e-12 * np.linalg.norm(lin0)
    assert np.abs(np.array(ang1) - ang0).max() <= 1e-12 * np.linalg.norm(ang0)
    assert k1 < k0 * (1 - 1e-4)
    assert velocity_constraint_residual(sim) < 1e-8 < 1e-2 < velocity_constraint_residual(given)


@pytest.mark.skip_in_parallel
def test_cli_warns_and_reports_the_projection(run_cli, tmp_path):
    import json

    out = tmp_path / "out"
    r = run_cli("run", str(ROOT / "runs" / "seed" / "free_fall_1+4.toml"), "--set", "analysis.t_end=0.005",
                "--set", "beam.CM.velocity=[0, 0, 1.0]", "--out", str(out), "-q")
    assert r.returncode == 0, r.stderr
    assert r.stderr.count("slidebeam: warning: the initial velocities violate the constraints") == 1, r.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["initial_velocity"]["projected"]
    assert summary["initial_velocity"]["relative_change"] == pytest.approx(0.1246, abs=1e-3)


def test_a_slider_drawn_off_its_carrier_is_announced():
    """A slider drawn 1e-6 m off its carrier (inside the joint's tolerance) is pulled on in the
    first step, and the work that takes is no effect's. The start says so, naming the joint and
    the gap; after the first step the energy the pull put in is said, and the balance counts
    from there (it showed in energy_balance_error for the whole run). Drawn on the carrier,
    nothing is said and the balance closes to roundoff. An equilibrium start closes the gap
    before the run: nothing is said there either."""
    section = {"EA": 1e4, "kGA": 1e4, "GJ": 1, "EI2": 1, "EI3": 1, "rhoA": 1, "rhoI2": 1e-3, "rhoI3": 1e-3}
    errors = {}
    for dz in (0.0, 1e-6):
        data = {"analysis": {"type": "dynamic", "t_end": 0.02, "dt": 0.01},
                "beam": [{"name": "carrier", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 4, "section": section},
                         {"name": "hanger", "start": [0.5, 0, dz], "end": [0.5, 0, -1], "spans": 1,
                          "section": section}],
                "support": [{"type": "clamp", "beam": "carrier", "at": "start"}],
                "sliding_joint": [{"slider": "hanger", "carrier": "carrier"}], "gravity": {"g": [0, 0, -9.81]}}
        sim, messages = simulation(slidebeam.scene_from_dict(data))
        gap_messages = [m for m in messages if "off their carriers" in m]
        if dz == 0.0:
            assert gap_messages == [], gap_messages
        else:
            assert len(gap_messages) == 1 and "by up to 1e-06 m ([[sliding_joint]] #1)" in gap_messages[0], messages
            assert gap_messages[0] in sim.warnings
        if dz == 0.0:
            errors[dz] = sim.run_dynamic().records[-1].energy_balance_error
        else:
            with pytest.warns(slidebeam.ConstraintWarning, match="pull of the sliders"):
                errors[dz] = sim.run_dynamic().records[-1].energy_balance_error
        snap = [m for m in sim.warnings if "pull of the sliders" in m]
        if dz == 0.0:
            assert snap == [] and sim.initial_snap_energy == 0.0
        else:
            assert len(snap) == 1 and f"{sim.initial_snap_energy:.3g} J" in snap[0], sim.warnings
            assert abs(sim.initial_snap_energy) >= 1e-8  # (2.7e-7 J)
    assert errors[0.0] <= 1e-12 and errors[1e-6] <= 1e-12, errors
    data["analysis"]["start"] = "equilibrium"
    sim, messages = simulation(slidebeam.scene_from_dict(data))
    sim.run_dynamic()
    assert not [m for m in messages + sim.warnings if "off their carriers" in m], (messages, sim.warnings)
