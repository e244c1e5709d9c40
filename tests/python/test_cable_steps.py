# SPDX-License-Identifier: MIT
"""Time steps on cables: the backtracking manifold line search, the return to the fast LU after a
fall-back, and Newton chosen by cost (docs/performance.md, "Cables")."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import slidebeam
from conftest import petsc_options

ROOT = Path(__file__).resolve().parents[2]


def shipped(path: str, t_end: float, *sets: str) -> slidebeam.Simulation:
    """A shipped scene ending at t_end (and other scene values set), with the PETSc options set now."""
    return slidebeam.Simulation(slidebeam.load_scene(ROOT / path, [f"analysis.t_end={t_end}", *sets]))


def run(sim: slidebeam.Simulation):
    outcome = sim.run_dynamic()
    assert outcome.complete, outcome.message
    return outcome


def test_backtracking_keeps_a_jerked_rope_from_diverging():
    """The hanging steel rope whose anchor stops after a 1 m ramp at t = 1 s, stepped at 5 ms up
    to the stop, then one step of 20 ms across it: full Newton steps from the predictor make |F|
    grow and the step fails (in a step of the scene's 10 ms they sent |F| from 1e5 to 1e48 on one
    build). Retried with a line search that halves the steps that make |F| grow, it converges.
    Serial and distributed alike (the block path's line search). Whole runs at 10-12.5 ms are no
    test of it: whether some step there fails, with the line search or without, depends on
    roundoff (from none to 288 cut steps on builds that differ in roundoff only)."""

    def step_across_the_stop(backtrack: str) -> bool:
        with petsc_options(sb_backtrack=backtrack):
            sim = shipped("runs/effects/moving_anchor.toml", 1.0, "analysis.dt=0.005")
        run(sim)
        return sim.integrator.step(0.02).converged

    assert step_across_the_stop("true")
    assert not step_across_the_stop("false")


def test_a_fall_back_returns_to_the_fast_solve():
    """After a step solved on the pivoting LU the steps return to the fast solve (they used to stay
    on SuperLU, and on several ranks on MUMPS, for good), with the options the run started with
    (backtracking off here): serially the condensed LU, distributed the block path. The fall-back
    is the one a checkpoint restores (that a failing fast LU falls back:
    test_dynamics.py::test_seed_strains_fall_back_to_a_pivoting_lu); whole runs of the jerked rope
    are no test of it, since which of their steps fail on the fast LU depends on roundoff."""
    with petsc_options(sb_backtrack="false"):
        sim = shipped("runs/effects/moving_anchor.toml", 0.1)
    run(sim)
    integ = sim.integrator
    serial = sim.snes.getComm().getSize() == 1
    solves = integ.parallel_solves
    integ.restore(integ.time, integ.h_prev, True)
    assert integ.pivoting_lu
    assert integ.step(0.01).converged and integ.pivoting_lu_steps == 1
    assert integ.step(0.01).converged and integ.pivoting_lu_steps == 1
    assert not integ.pivoting_lu
    # the condensed manifold Newton again, or block Jacobi with the coupling correction
    assert sim.snes.getKSP().getPC().getType() == ("shell" if serial else "bjacobi")
    if not serial:  # the block path's solves counted on from those before the fall-back
        assert integ.parallel_solves["corrected"] > solves["corrected"] > 0


@pytest.mark.skip_in_parallel  # the serial fast LU
def test_a_zero_pivot_costs_one_step_on_the_pivoting_lu():
    """D3, the right-angle cantilever, tumbles freely after its pulse at the scene's dt = 0.25:
    near t = 4 s Newton diverges from the predictor and its iterate meets a zero pivot in the
    condensed LU (at the rigid joint's multipliers). Without backtracking the step is cut, solved
    on the pivoting LU, and the next step is back on the fast one: the condensed factor had kept
    that zero pivot's error through its later numeric factorisations, so every return failed at
    once and the pivoting stretches doubled (9 of the first 24 steps on SuperLU, 107 of the whole
    run's 123). With it (the default) the step is retried from the predictor with backtracking,
    as any other failed step: its set-up had left the PC's failed reason standing, so the retry
    failed at its first solve, and a linear solver's failure was never retried so."""
    runs = {}
    for backtrack in ("false", "true"):
        with petsc_options(sb_backtrack=backtrack):
            sim = shipped("runs/right_angle_cantilever.toml", 6.0)
        outcome = run(sim)
        integ = sim.integrator
        assert not integ.pivoting_lu and sim.snes.getKSP().getPC().getType() == "shell"
        runs[backtrack] = (outcome.rejected_steps, integ.pivoting_lu_steps)
    # (measured: one cut and one step on SuperLU without backtracking, none with it; which
    # iterate meets the pivot depends on roundoff, so the bounds leave room)
    assert runs["false"][1] <= 2 and runs["true"] == (0, 0), runs


def swing(t_end: float, **options: str) -> slidebeam.Simulation:
    with petsc_options(**options):
        sim = shipped("runs/cables/cable_swing.toml", t_end)
        run(sim)  # the static start first
    return sim


@pytest.mark.skip_in_parallel  # the serial step's Newton (counts differ on the block path)
def test_newton_by_cost_takes_fewer_jacobians_to_the_same_states():
    """The hanging cable of the cable benchmark, 150 steps: full Newton builds a Jacobian at every
    iteration; chosen by cost (the scene's [petsc] sb_newton_by_cost) modified Newton wins, with
    fewer Jacobians, and the states agree to the Newton tolerance."""
    full = swing(1.5, sb_jacobian_reuse="false")
    chosen = swing(1.5)
    n_full, n_chosen = full.integrator.jacobian_evaluations, chosen.integrator.jacobian_evaluations
    assert n_full >= 3 * 150
    assert n_chosen < 0.7 * n_full
    assert np.allclose(chosen.x.getArray(), full.x.getArray(), rtol=0, atol=1e-8)
