# SPDX-License-Identifier: MIT
"""The exact parallel solve on coupled ranks (src/solvers/coupling_correction.hpp): block Jacobi's
one application plus the correction on the ranks' interface unknowns solves the step's linear
system exactly, in one KSP iteration: with director beams the condensed system, so that a
parallel step takes the serial step's Newton iterations at any step size. Meaningful under
mpirun -n 2."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI
import numpy as np
from petsc4py import PETSc

import slidebeam
from checks import distributed_and_serial_records
from test_condensation import petsc_options

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.skipif(MPI.COMM_WORLD.Get_size() != 2, reason="two ranks: mpirun -n 2")

# one carrier cut across by the even split of control points, its slider on the same rank
SLIDER = ROOT / "runs" / "hard" / "slider_skips_spans.toml"


def long_rope(tmp_path: Path) -> slidebeam.Scene:
    """A 200-span rope with one hanger, cut once between the ranks: GMRES on block Jacobi needs
    8-13 iterations per solve there (each block is held by its stiffness and c0 M alone)."""
    out = tmp_path / "rope.toml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--carriers", "1", "--spans", "200",
                    "--hangers", "1", "--start", "reference", "--t-end", "0.005", "--dt", "1e-3", "--out", str(out)],
                   check=True, capture_output=True)
    return slidebeam.load_scene(out)


def iterations(sim: slidebeam.Simulation) -> list[int]:
    """The KSP iterations of every solve of sim's time steps, recorded from now on."""
    counts: list[int] = []

    def monitor(_ksp, it, _rnorm):
        if it == 0:
            counts.append(0)
        counts[-1] = it

    sim.snes.getKSP().setMonitor(monitor)
    return counts


def relative_true_residuals(ksp: PETSc.KSP) -> tuple[float, float]:
    """|b - A x| / |b| for a random b, x from ksp and from MUMPS on the whole system."""
    A = ksp.getOperators()[0]
    b = A.createVecLeft()
    b.setRandom()

    def residual(solver: PETSc.KSP) -> float:
        x, r = b.duplicate(), b.duplicate()
        solver.solve(b, x)
        A.mult(x, r)
        r.axpy(-1.0, b)
        return r.norm() / b.norm()

    mumps = PETSc.KSP().create(A.getComm())
    mumps.setOperators(A)
    mumps.setType("preonly")
    mumps.getPC().setType("lu")
    mumps.getPC().setFactorSolverType("mumps")
    mumps.setOptionsPrefix("check_")
    # threshold pivoting at 0.5: with MUMPS's default 0.01 the factorisation breaks down on
    # the rope's saddle-point system (and so does SuperLU_dist's)
    with petsc_options(check_mat_mumps_cntl_1="0.5", check_mat_mumps_icntl_14="200"):
        mumps.setFromOptions()
        mumps.setUp()
    return residual(ksp), residual(mumps)


def assert_solved_exactly(ksp: PETSc.KSP) -> None:
    """As exactly as a direct solve: the true residual within 10x MUMPS's (both at roundoff
    times the condition number)."""
    ours, mumps = relative_true_residuals(ksp)
    assert ours <= 10 * mumps + 1e-14, (ours, mumps)


def run(scene: slidebeam.Scene, comm, **options: str):
    """The run's outcome, the KSP iterations of its solves and the simulation."""
    with petsc_options(**options):
        sim = slidebeam.Simulation(scene, comm)
        counts = iterations(sim)
        outcome = sim.run_dynamic()
    return outcome, counts, sim


def test_with_the_correction_a_parallel_step_is_the_serial_step():
    """The rail of slider_skips_spans cut across at 10x its step (dt = 0.1): one application per
    solve, and every step takes the serial run's Newton iterations (give or take the last one: the
    ranks sum their Jacobian entries in another order, and the residual of a hard step may fall
    below the tolerance an iteration earlier) to the same state (1e-10); GMRES on block Jacobi,
    whose steps carry Newton's multipliers, has steps rejected there."""
    scene = slidebeam.load_scene(SLIDER, ["analysis.t_end=0.3", "analysis.dt=0.1"])
    serial, _, _ = run(scene, MPI.COMM_SELF)
    exact, counts, sim = run(scene, MPI.COMM_WORLD, sb_schwarz_exact="true")
    assert sim.snes.getKSP().getType() == PETSc.KSP.Type.PREONLY and set(counts) == {1}
    assert exact.complete and exact.rejected_steps == serial.rejected_steps == 0
    assert len(exact.records) == len(serial.records)
    assert all(abs(a.newton_iterations - b.newton_iterations) <= 1 for a, b in zip(exact.records, serial.records))
    for a, b in zip(exact.records, serial.records):
        assert abs(a.total_energy - b.total_energy) <= 1e-10 * max(1.0, abs(b.total_energy))
        assert np.abs(np.array(a.tracked) - np.array(b.tracked)).max() < 1e-10
    gmres, counts, _ = run(scene, MPI.COMM_WORLD, sb_schwarz_exact="false")
    assert gmres.rejected_steps > 0


def test_the_correction_of_the_full_system_solves_it_as_exactly_as_mumps():
    """Without the condensation (-sb_condense_directors false) the blocks solve the full
    saddle-point system, and so does the correction: a random right-hand side is solved as
    exactly as MUMPS solves it."""
    scene = slidebeam.load_scene(SLIDER, ["analysis.t_end=0.03"])
    outcome, counts, sim = run(scene, MPI.COMM_WORLD, sb_schwarz_exact="true", sb_condense_directors="false")
    assert outcome.complete and set(counts) == {1}
    with petsc_options(sb_condense_directors="false"):
        assert_solved_exactly(sim.snes.getKSP())


def test_the_correction_is_taken_unless_the_interface_is_large(tmp_path):
    """By default the correction where few rows couple the ranks (a rope cut once: 24 per side),
    GMRES where many do (here: a limit of 10) or with -sb_schwarz_exact false."""
    scene = long_rope(tmp_path)
    outcome, counts, sim = run(scene, MPI.COMM_WORLD)
    assert outcome.complete and sim.snes.getKSP().getType() == PETSc.KSP.Type.PREONLY and set(counts) == {1}
    outcome, counts, sim = run(scene, MPI.COMM_WORLD, sb_schwarz_exact_max_interface="10")
    assert outcome.complete and sim.snes.getKSP().getType() == PETSc.KSP.Type.GMRES and max(counts) > 4
    outcome, counts, sim = run(scene, MPI.COMM_WORLD, sb_schwarz_exact="false")
    assert outcome.complete and sim.snes.getKSP().getType() == PETSc.KSP.Type.GMRES and max(counts) > 4
    distributed_and_serial_records(scene)


def test_a_block_that_fails_under_the_correction_fails_the_step_on_every_rank():
    """On this small scene with every effect (12 and 6 interface unknowns) the first step fails
    on 2 ranks with any linear solve (GMRES too) and is retried; under the correction one rank's
    block meets a zero pivot on the way. Every rank's Newton must fail
    there (one application reports the failure on its own rank only; before, the other rank
    went on and the run hung), and the run completes."""
    from test_damping import with_damping
    from test_dynamics import everything_scene

    scene = with_damping(everything_scene("energy-momentum", "full"), retardation_time=0.02, mass_proportional=0.3)
    outcome, _, sim = run(scene, MPI.COMM_WORLD)
    assert outcome.complete
    # retried from its predictor with backtracking on the block path, which solves it here (the
    # retry used to fail at its first solve on the failure block Jacobi had kept, and MUMPS took
    # the step); the run ends on the block path either way
    assert sim.integrator.pivoting_lu_steps <= 1 and not sim.integrator.pivoting_lu
    assert sim.snes.getKSP().getPC().getType() == PETSc.PC.Type.BJACOBI
