# SPDX-License-Identifier: MIT
"""Time steps on cables: the backtracking manifold line search, the return to the fast LU after a
fall-back, and Newton chosen by cost (docs/performance.md, "Cables")."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from petsc4py import PETSc

import slidebeam

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.skip_in_parallel  # serial paths: the fast LU and its condensed Newton


def with_options(options: dict[str, str], build):
    """build() with these PETSc options set, removed again afterwards."""
    for k, v in options.items():
        PETSc.Options().setValue(k, v)
    try:
        return build()
    finally:
        for k in options:
            PETSc.Options().delValue(k)


def shipped(path: str, t_end: float):
    """A shipped scene ending at t_end."""
    scene = slidebeam.load_scene(ROOT / path)
    return dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, t_end=t_end))


def moving_anchor(t_end: float) -> slidebeam.Simulation:
    return slidebeam.Simulation(shipped("runs/effects/moving_anchor.toml", t_end))


def run(sim: slidebeam.Simulation):
    outcome = sim.run_dynamic()
    assert outcome.complete, outcome.message
    return outcome


def test_backtracking_keeps_a_jerked_rope_from_diverging():
    """The hanging steel rope whose anchor stops after a 1 m ramp: at dt = 0.01 full Newton steps
    from the predictor made |F| grow from 1e5 to 1e48 and 288 of 544 steps were cut. Halving a
    step that makes |F| grow: no step is cut (and without it some are, so the test can fail)."""
    with_backtrack = with_options({}, lambda: run(moving_anchor(1.7)))
    assert with_backtrack.rejected_steps == 0
    without = with_options({"sb_backtrack": "false"}, lambda: run(moving_anchor(1.7)))
    assert without.rejected_steps > 0


def test_a_fall_back_returns_to_the_fast_lu():
    """Without backtracking the rope's step at t = 0.495 fails on the fast LU and is solved on the
    pivoting one; the steps after it return to the fast LU (it used to stay on SuperLU for good)."""
    sim = with_options({"sb_backtrack": "false"}, lambda: moving_anchor(0.7))
    run(sim)
    assert sim.integrator.pivoting_lu_steps >= 1
    assert not sim.integrator.pivoting_lu


def swing(t_end: float, options: dict[str, str]):
    scene = shipped("runs/cables/cable_swing.toml", t_end)

    def build():
        sim = slidebeam.Simulation(scene)
        run(sim)  # the static start first
        return sim

    return with_options(options, build)


def test_newton_by_cost_takes_fewer_jacobians_to_the_same_states():
    """The hanging cable of the cable benchmark, 150 steps: full Newton builds a Jacobian at every
    iteration; chosen by cost (the scene's [petsc] sb_newton_by_cost) modified Newton wins, with
    fewer Jacobians than steps, and the states agree to the Newton tolerance."""
    full = swing(1.5, {"sb_jacobian_reuse": "false"})
    chosen = swing(1.5, {})
    n_full, n_chosen = full.integrator.jacobian_evaluations, chosen.integrator.jacobian_evaluations
    assert n_full >= 3 * 150
    assert n_chosen < 0.7 * n_full
    assert np.allclose(chosen.x.getArray(), full.x.getArray(), rtol=0, atol=1e-8)
