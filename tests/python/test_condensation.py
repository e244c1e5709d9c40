# SPDX-License-Identifier: MIT
"""Serial time steps solve the Newton systems of director beams condensed to 6 unknowns per
control point (solvers/director_condensation.hpp): the orthonormality multipliers are eliminated
with the null space of the constraint Jacobian and every iterate is kept on the constraint
manifold. The solution must be that of the full saddle-point system; only the path changes."""
from __future__ import annotations

import contextlib
import dataclasses
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI
from petsc4py import PETSc

import slidebeam
from test_ancf_sliding import seed_scene
from test_dynamics import everything_scene

ROOT = Path(__file__).resolve().parents[2]
serial_only = pytest.mark.skipif(MPI.COMM_WORLD.Get_size() > 1, reason="the condensed solve is the serial fast path")


@contextlib.contextmanager
def petsc_options(**opts: str):
    """Set PETSc options for the block and restore what was there before (under mpirun the
    tests' -sb_serial_below 0, for one)."""
    o = PETSc.Options()
    before = {k: o.getString(k) if o.hasName(k) else None for k in opts}
    for k, v in opts.items():
        o.setValue(k, v)
    try:
        yield
    finally:
        for k, v in before.items():
            if v is None:
                o.delValue(k)
            else:
                o.setValue(k, v)


def sliding_scene(integrator: str, t_end: float = 0.21, cable_slider: bool = False) -> slidebeam.Scene:
    """The seed's inclined free fall: in its first 210 steps the tip slides from s = 0.4
    across the carrier's knot at 0.5 (to about 0.51), by step 790 to about 1.9. The sliding
    beam CM as an ANCF cable on request (the carrier stays a director beam)."""
    analysis = {"t_end": t_end, "integrator": integrator}
    if cable_slider:
        return seed_scene("free_fall_inclined_1+4", ("CM",), analysis=analysis)
    return slidebeam.load_scene(ROOT / "runs" / "seed" / "free_fall_inclined_1+4.toml",
                                [f"analysis.{k}={v!r}".replace("'", '"') for k, v in analysis.items()])


def states(scene: slidebeam.Scene, condense: bool, steps: int) -> tuple[np.ndarray, list[float], str, tuple[float, float]]:
    """Final state, total energy per step, preconditioner type, first joint's s at start and end."""
    with petsc_options(sb_condense_directors="true" if condense else "false"):
        sim = slidebeam.Simulation(scene)
    dt = scene.analysis.dt
    s0 = sim.joint_states()[0].s if sim.joint_states() else 0.0
    energies = []
    for _ in range(steps):
        r = sim.integrator.step(dt)
        assert r.converged, r.reason_name
        e = sim.energies()
        energies.append(sim.integrator.kinetic_energy() + e["strain"] + e["potential"])
    s1 = sim.joint_states()[0].s if sim.joint_states() else 0.0
    return sim.x.getArray().copy(), energies, sim.snes.getKSP().getPC().getType(), (s0, s1)


def coordinate_rows(sim: slidebeam.Simulation) -> np.ndarray:
    """Everything but the orthonormality multipliers of director triads."""
    keep = np.ones(sim.x.getSize(), dtype=bool)
    for b in sim.scene.beams:
        if b.formulation == "ancf":
            continue
        first = sim.first_control_point(b.name)
        for cp in range(first, first + b.spans + 2):
            q0, _ = sim.control_point_unknowns(cp)
            keep[q0 + 12:q0 + 18] = False
    return keep


@serial_only
@pytest.mark.parametrize("integrator", ("energy-momentum", "midpoint", "newmark", "hht"))
@pytest.mark.parametrize("which", ("everything", "sliding", "pendulum"))
def test_condensed_steps_equal_full_steps(integrator, which):
    """Same states (multipliers included) and energies as Newton on the full system, for a scene
    with every effect (clamp, interior support, rigid joint, point mass, loads), for a tip
    sliding across knots, and for the stiff pendulum (beam points only: 6 x 6 block LU; its
    scene reuses the Jacobian, rotated to each iterate)."""
    if which == "everything":  # at dt = 0.01 (its own dt = 0.05 is too large from t = 0.1 on)
        scene = everything_scene(integrator)
        scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, dt=0.01))
    elif which == "sliding":  # the seed's free fall: a tip sliding across the carrier's knots
        scene = sliding_scene(integrator)
    else:
        scene = slidebeam.load_scene(ROOT / "runs" / "pendulum16.toml", [f'analysis.integrator="{integrator}"'])
    steps = {"everything": 10, "sliding": 210, "pendulum": 200}[which]
    x_c, e_c, pc_c, s_c = states(scene, True, steps)
    x_f, e_f, pc_f, s_f = states(scene, False, steps)
    if which == "sliding":
        assert s_c[0] < 0.5 < s_c[1], s_c
    assert pc_c == "shell" and pc_f == "lu"
    scale = max(1.0, np.abs(x_f).max())
    assert np.abs(x_c - x_f).max() < 1e-8 * scale
    assert np.abs(np.array(e_c) - np.array(e_f)).max() < 1e-9 * max(1.0, max(abs(e) for e in e_f))


@serial_only
@pytest.mark.parametrize("integrator", ("energy-momentum", "midpoint", "newmark", "hht"))
def test_condensed_linear_solve_matches_the_full_system(integrator):
    """One linear solve at a moved state: the condensed preconditioner gives the full system's
    Newton step on every coordinate (and leaves the triads' multipliers to the line search),
    for right-hand sides with zero constraint rows, as on the constraint manifold. Every scheme:
    HHT scales the whole residual by 1 + alpha, which the solve rotated to the current triads
    once took for part of the triads (its Newton steps were (1 + alpha)^2 short, issue 22)."""
    sim = slidebeam.Simulation(everything_scene(integrator))
    integ = sim.integrator
    for _ in range(2):
        assert integ.step(0.05).converged
    integ.prepare_step(0.05)
    x1 = sim.x.copy()
    J = integ.jacobian
    integ.step_jacobian(x1, J)
    keep = coordinate_rows(sim)
    rng = np.random.default_rng(7)
    b = J.createVecLeft()
    b.setArray(np.where(keep, rng.standard_normal(b.getSize()), 0.0))
    # full system, pivoting LU
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setOperators(J)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("superlu")
    y_full = J.createVecRight()
    ksp.solve(b, y_full)
    # the integrator's condensed preconditioner
    pc = integ.snes.getKSP().getPC()
    assert pc.getType() == "shell"
    pc.setOperators(J, J)
    pc.setUp()
    y = J.createVecRight()
    pc.apply(b, y)
    yf, yc = y_full.getArray(), y.getArray()
    assert np.abs(yc[keep] - yf[keep]).max() < 1e-9 * np.abs(yf[keep]).max()
    assert np.abs(yc[~keep]).max() == 0.0


@serial_only
def test_exact_block_solve_matches_the_full_system(tmp_path):
    """The block solve of the parallel path (block Jacobi, here with one block: -sb_schwarz on
    one rank) is exact for any right-hand side, constraint rows and multipliers included: GMRES
    preconditioned by it solves the full system in one iteration."""
    with petsc_options(sb_schwarz="true"):
        sim = slidebeam.Simulation(everything_scene("energy-momentum"))
    integ = sim.integrator
    assert integ.step(0.05).converged
    ksp = integ.snes.getKSP()
    view = tmp_path / "ksp.txt"
    viewer = PETSc.Viewer().createASCII(str(view), comm=PETSc.COMM_SELF)
    ksp.view(viewer)
    viewer.destroy()
    assert "exact block solve, director triads condensed" in view.read_text()
    integ.prepare_step(0.05)
    J = integ.jacobian
    integ.step_jacobian(sim.x, J)
    b = J.createVecLeft()
    b.setArray(np.random.default_rng(3).standard_normal(b.getSize()))
    full = PETSc.KSP().create(PETSc.COMM_SELF)
    full.setOperators(J)
    full.setType("preonly")
    full.getPC().setType("lu")
    full.getPC().setFactorSolverType("superlu")
    y_full, y = J.createVecRight(), J.createVecRight()
    full.solve(b, y_full)
    ksp.setOperators(J, J)
    ksp.solve(b, y)
    assert ksp.getIterationNumber() <= 1
    assert np.abs(y.getArray() - y_full.getArray()).max() < 1e-8 * np.abs(y_full.getArray()).max()


@pytest.mark.parametrize("slider", ("director", "cable"))
def test_exact_block_solves_follow_pattern_changes(slider):
    """A tip sliding along the carrier (s from 0.4 to 1.9, across the knots at 0.5, 1.0, 1.5 and,
    on 2 ranks, across the rank boundary) changes the Jacobian's pattern, and with it each
    rank's block matrix: on more than one rank a new object, whose nonzero-state counter can
    equal the old block's. The exact block solve must rebuild its reduced pattern every time;
    with a stale one it is no longer exact, or writes out of bounds (seen with the cable
    slider on 2 ranks). Block Jacobi on any rank count (-sb_schwarz on one rank): every step
    takes the same Newton and GMRES iterations (within two per step, for roundoff: GMRES counts on
    2 ranks move by one or two between runs) as with LU block
    solves, and on one rank one GMRES iteration per Newton iteration."""
    counts = {}
    for sub in ("condensed", "lu"):
        opts = {"sb_schwarz": "true"} | ({"sub_pc_type": "lu"} if sub == "lu" else {})
        with petsc_options(**opts):
            sim = slidebeam.Simulation(sliding_scene("energy-momentum", t_end=0.79, cable_slider=slider == "cable"))
        s0 = sim.joint_states()[0].s
        counts[sub] = []
        for n in range(790):
            r = sim.integrator.step(sim.scene.analysis.dt)
            assert r.converged, f"{sub} block solves, step {n}: {r.reason_name}"
            counts[sub].append((r.iterations, r.linear_iterations))
        s1 = sim.joint_states()[0].s
        assert s0 < 0.5 and s1 > 1.5, (s0, s1)
    c, lu = np.array(counts["condensed"]), np.array(counts["lu"])
    assert np.abs(c - lu).max() <= 2, f"condensed vs LU block solves (Newton, GMRES) per step: {c.sum(0)} vs {lu.sum(0)}"
    if MPI.COMM_WORLD.Get_size() == 1:
        assert (c[:, 1] <= c[:, 0]).all()
