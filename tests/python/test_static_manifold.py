# SPDX-License-Identifier: MIT
"""Statics on the director constraint manifold (issue 18, item 4; solvers/manifold_newton.hpp):
the static solver and the equilibrium start take Newton steps on the 6 unknowns per director
point (condensed LU, directors rotated, multipliers from the force rows), from a predictor that
turns the directors on by their last rotation, and stop at the residual's roundoff level.
Figures in docs/verification.md, "Statics on the constraint manifold"."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI

import slidebeam
from test_condensation import petsc_options

ROOT = Path(__file__).resolve().parents[2]


def load_steps(scene: slidebeam.Scene, **opts: str) -> tuple[slidebeam.Simulation, list]:
    with petsc_options(**opts):
        sim = slidebeam.Simulation(scene)
    return sim, sim.solve_static()


def test_rollup_takes_at_most_four_newton_iterations_per_load_step():
    """runs/rollup.toml (64 spans, 20 steps of 18 degrees at the tip): 7 or 8 iterations per
    load step with linear director updates, 3 or 4 on the manifold. Every step is converged
    to its roundoff level, and the circle closes as before."""
    sim, records = load_steps(slidebeam.load_scene(ROOT / "runs" / "rollup.toml"))
    its = [r.newton_iterations for r in records[1:]]
    assert sim.load_step_cuts == 0 and len(its) == 20 and records[-1].t == 1.0
    assert max(its) <= 4, its
    assert max(r.residual_norm for r in records[1:]) < 1e-8
    tip = np.array(records[-1].tracked[0])
    assert np.linalg.norm(tip) < 0.11  # 64 spans, full quadrature: 0.0972 from the clamp


def test_no_load_step_is_taken_for_converged_above_roundoff():
    """The 45-degree bend, the elastica and the right-angle cantilever loaded statically: every
    load step ends with |F| at its roundoff level. (The stagnation test alone took a residual of
    1.0 on the bend, 7e-4 on the elastica and 2e-3 on the cantilever for converged: |F| that
    failed once to fall, at 1e-6 of a large initial residual.)"""
    # Newton iterations per load step: the slender assumed-strain elastica takes up to 13 on its
    # first steps (20 degrees of tip rotation each; its axial strain is the centre line's,
    # 1/2 (phi'.phi' - 1), whose linearisation meets EA = 1e7 EI: docs/verification.md)
    cases = (("bend45.toml", [], 1e-5, 10), ("elastica.toml", [], 1e-6, 13),
             ("right_angle_cantilever.toml", ['analysis.type="static"', "analysis.t_end=1.0", "analysis.steps=10"], 1e-7, 10))
    for name, sets, bound, max_its in cases:
        sim, records = load_steps(slidebeam.load_scene(ROOT / "runs" / name, sets))
        assert sim.load_step_cuts == 0 and records[-1].converged, name
        worst = max(r.residual_norm for r in records[1:])
        assert worst < bound, (name, worst)
        assert max(r.newton_iterations for r in records[1:]) <= max_its, name


SLENDER = [(q, n, P) for q in ("full", "reduced", "assumed_strain") for n in (8, 16, 32) for P in (1.0, 10.0)]


@pytest.mark.parametrize("quadrature,spans,load", SLENDER)
def test_slender_elastica_converges_without_load_step_cuts(quadrature, spans, load):
    """The cantilever elastica at EA/EI = 1e7 as the convergence table solves it (40 load
    steps): no load step is cut, and none takes more than 8 iterations. Before, full quadrature
    at 32 spans and P L^2/EI = 1 cut 5 load steps, and reduced quadrature at 32 spans failed:
    the first load step's residual floor lay above 1e-6 of its initial residual, so Newton could
    not stop until its iteration limit."""
    scene = slidebeam.load_scene(ROOT / "runs" / "elastica.toml", [
        f"beam.0.spans={spans}", f"beam.0.quadrature={quadrature}", "beam.0.section.EA=1e7",
        "beam.0.section.kGA=1e7", f"load.0.value=[0,{load},0]", "analysis.steps=40"])
    sim, records = load_steps(scene)
    assert records[-1].converged and records[-1].t == 1.0
    assert sim.load_step_cuts == 0 and len(records) == 41
    assert max(r.newton_iterations for r in records[1:]) <= 8


@pytest.mark.parametrize("scene_file,sets,tol,iteration_ratio", [
    ("bend45.toml", ["beam.0.spans=9"], 1e-9, 1.0),
    ("rollup.toml", ["beam.0.spans=32", "analysis.steps=10"], 1e-9, 1.0),
    # the assumed-strain elastica: its axial strain 1/2 (phi'.phi' - 1) has no directors, and
    # its linearisation (EA = 1e7 EI) sets the pace of both (measured: 166 against 165)
    ("elastica.toml", [], 1e-7, 1.05),
])
def test_condensed_static_solve_equals_the_full_one(scene_file, sets, tol, iteration_ratio):
    """Newton on the manifold (condensed LU, rotated directors; in parallel the full system's
    solve with the same update) and plain Newton on the full saddle-point system
    (-sb_condense_directors false) reach the same equilibria: the control points of the last
    load step and the tracked points, strain energy and clamp reaction (from the multipliers) of
    every one to tol of their size. Each solve stops once |F| is at its roundoff level, so the
    two differ by what the condition number makes of roundoff: 1e-9 on the bend and the roll-up,
    1e-7 on the slender elastica (EA/EI = 1e7: its tip, 0.93 from the clamp, by 4e-8). With fewer
    Newton iterations on the manifold where the directors set the pace."""
    scene = slidebeam.load_scene(ROOT / "runs" / scene_file, sets)
    sims, recs = {}, {}
    for mode in ("true", "false"):  # under mpirun: distributed, not on rank 0 alone
        sims[mode], recs[mode] = load_steps(scene, sb_condense_directors=mode, sb_statics_on_rank_0="false")
    assert sims["true"].load_step_cuts == 0 and sims["false"].load_step_cuts == 0
    assert [r.t for r in recs["true"]] == [r.t for r in recs["false"]]
    q_c, q_f = sims["true"].control_points(0), sims["false"].control_points(0)
    assert np.abs(q_c - q_f).max() <= tol * max(1.0, np.abs(q_f).max())
    for a, b in zip(recs["true"], recs["false"]):
        p_a, p_b = np.array(a.tracked), np.array(b.tracked)
        assert np.abs(p_a - p_b).max() < tol * max(1.0, np.abs(p_b).max())
        assert abs(a.strain_energy - b.strain_energy) <= tol * max(1.0, abs(b.strain_energy))
        for ra, rb in zip(a.reactions, b.reactions):
            r_a = np.concatenate([ra.force, ra.moment or []])
            r_b = np.concatenate([rb.force, rb.moment or []])
            assert np.abs(r_a - r_b).max() < tol * max(1.0, np.abs(r_b).max())
    its = {mode: sum(r.newton_iterations for r in recs[mode]) for mode in recs}
    assert its["true"] < iteration_ratio * its["false"], its


@pytest.mark.parametrize("scene_file,bound", [("hanging_rope.toml", 28), ("zip_line.toml", 54)])
def test_equilibrium_start_on_the_manifold(scene_file, bound):
    """start = "equilibrium" of the cable scenes: about as many Newton iterations as with linear
    director updates (24 and 50 against 24 and 49; 43 and 68 with linear updates before the
    continuation's step control was tuned), the same equilibrium (coordinates to 1e-8 of their
    size)."""
    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / scene_file, ["output.xdmf=false"])
    q, result = {}, {}
    for mode in ("true", "false"):
        with petsc_options(sb_condense_directors=mode):
            sim = slidebeam.Simulation(scene)
        result[mode] = sim.settle()
        assert result[mode].converged
        q[mode] = np.concatenate([np.ravel(sim.control_points(b.name)) for b in scene.beams])
    assert result["true"].newton_iterations <= bound, result["true"].newton_iterations
    assert np.abs(q["true"] - q["false"]).max() <= 1e-8 * max(1.0, np.abs(q["false"]).max())


def test_a_stalled_continuation_is_finished_by_plain_newton():
    """The static start's continuation runs to the tolerance by itself (the hanging rope: 9
    steps, no plain Newton polish). Stopped close to equilibrium (here after 7 steps, |F| at 3e-6
    of its start), a plain Newton solve on the pivoting LU finishes it: converged, polished, the
    same equilibrium to 1e-8."""
    from slidebeam import _core

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "hanging_rope.toml", ["output.xdmf=false"])
    full_sim = slidebeam.Simulation(scene)
    full = full_sim.settle()
    assert full.converged and not full.polished and full.pseudo_steps > 7
    sim = slidebeam.Simulation(scene)
    cut = _core.EquilibriumSolver(sim._model).solve(0.0, scene.analysis.dt, 1e-10, 7)
    assert cut.pseudo_steps == 7 and cut.polished and cut.converged, (cut.pseudo_steps, cut.polished)
    assert cut.residual <= 1e-8 * cut.residual0  # the roundoff floor (the full continuation ends at 1.3e-9)
    q, q_full = sim.control_points(0, sim._model.x), full_sim.control_points(0)
    assert np.abs(q - q_full).max() <= 1e-8 * np.abs(q_full).max()


def test_a_failed_continuation_step_is_cut_not_solved_on_the_full_system():
    """A continuation step the condensed LU does not solve is retried with half the pseudo-step,
    not on the pivoting LU of the whole saddle-point system (whose cost grows much faster than
    the system's). The hanging rope from a first pseudo-step of 1 s (the scene's is 1e-3): its
    first steps fail and are cut, none needs the full system, and the start ends at the same
    equilibrium as from the scene's own step."""
    from slidebeam import _core

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "hanging_rope.toml", ["output.xdmf=false"])
    ref = slidebeam.Simulation(scene)
    default = ref.settle()
    assert default.cut_steps == 0 and default.full_system_steps == 0, default
    sim = slidebeam.Simulation(scene)
    big = _core.EquilibriumSolver(sim._model).solve(0.0, 1.0, 1e-10, 200)
    assert big.converged and big.cut_steps >= 1 and big.full_system_steps == 0, (big.cut_steps, big.full_system_steps)
    q, q_ref = sim.control_points(0, sim._model.x), ref.control_points(0)
    assert np.abs(q - q_ref).max() <= 1e-8 * np.abs(q_ref).max()


def test_the_predictor_turns_directors_on_by_their_last_rotation():
    """Model.extrapolate: a triad turned by R from x_prev to x_last is turned by R^alpha again
    (exactly, where the linear extrapolation projected back fell short by O(angle^3)); every
    other unknown is extrapolated linearly."""
    if MPI.COMM_WORLD.Get_size() > 1:
        pytest.skip("a serial check of the kernel")
    scene = slidebeam.load_scene(ROOT / "runs" / "rollup.toml", ["beam.0.spans=4"])
    sim = slidebeam.Simulation(scene)
    model = sim._model
    x_prev = sim.x.copy()
    n = x_prev.getSize()
    rng = np.random.default_rng(3)

    def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
        a = axis / np.linalg.norm(axis)
        K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K

    x_last = x_prev.copy()
    xp, xl = x_prev.getArray(), x_last.getArray()
    turns = {}
    for cp in range(sim.first_control_point(0), sim.first_control_point(0) + 6):
        q0, _ = sim.control_point_unknowns(cp)
        xl[q0:q0 + 3] += rng.standard_normal(3)
        R = rotation(rng.standard_normal(3), 0.3 + 0.1 * cp)
        D = xp[q0 + 3:q0 + 12].reshape(3, 3).T
        xl[q0 + 3:q0 + 12] = (R @ D).T.reshape(-1)
        xl[q0 + 12:q0 + 18] += rng.standard_normal(6)
        turns[q0] = R
    x_last.setArray(xl)
    for alpha in (1.0, 0.5):
        x = sim.x.duplicate()
        model.extrapolate(x, x_last, x_prev, alpha)
        xa = x.getArray()
        prescribed = set(sim.prescribed_rows)
        for q0, R in turns.items():
            if q0 + 3 in prescribed:
                continue  # the clamp's point
            linear = xl + alpha * (xl - xp)
            assert np.abs(xa[q0:q0 + 3] - linear[q0:q0 + 3]).max() < 1e-12
            assert np.abs(xa[q0 + 12:q0 + 18] - linear[q0 + 12:q0 + 18]).max() < 1e-12
            w, V = np.linalg.eig(R)  # R^alpha from its axis and angle
            angle = math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2)))
            axis = np.real(V[:, np.argmin(np.abs(w - 1))])
            if np.dot(np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]), axis) < 0:
                axis = -axis
            D_last = xl[q0 + 3:q0 + 12].reshape(3, 3).T
            expected = rotation(axis, alpha * angle) @ D_last
            assert np.abs(xa[q0 + 3:q0 + 12].reshape(3, 3).T - expected).max() < 1e-12
        assert n == x.getSize()
