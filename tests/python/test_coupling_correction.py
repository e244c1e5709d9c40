# SPDX-License-Identifier: MIT
"""The exact parallel solve on coupled ranks (src/solvers/coupling_correction.hpp): block Jacobi's
one application plus the correction on the ranks' interface unknowns solves the step's linear
system exactly, in one KSP iteration; -sb_schwarz_exact auto switches to it once GMRES is slow.
Meaningful under mpirun -n 2."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI
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
    8-13 iterations per solve there (the blocks float on M/h^2 alone)."""
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


def test_the_correction_solves_coupled_ranks_exactly_in_one_application():
    """With the correction the step's KSP is preonly, one iteration per solve, and a random
    right-hand side is solved as exactly as MUMPS solves it; the run equals the serial one to
    1e-10."""
    scene = slidebeam.load_scene(SLIDER, ["analysis.t_end=0.03"])
    with petsc_options(sb_schwarz_exact="always"):
        sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
        counts = iterations(sim)
        assert sim.run_dynamic().complete
        ksp = sim.snes.getKSP()
        assert ksp.getType() == PETSc.KSP.Type.PREONLY
        assert counts and set(counts) == {1}
        assert_solved_exactly(ksp)
        distributed_and_serial_records(scene)


def test_without_the_correction_gmres_iterates():
    scene = slidebeam.load_scene(SLIDER, ["analysis.t_end=0.03"])
    with petsc_options(sb_schwarz_exact="never"):
        sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
        counts = iterations(sim)
        assert sim.run_dynamic().complete
        assert sim.snes.getKSP().getType() == PETSc.KSP.Type.GMRES
        assert counts and min(counts) >= 1


def test_auto_switches_to_the_correction_once_gmres_is_slow(tmp_path):
    """-sb_schwarz_exact auto (the default) lets GMRES iterate until a solve takes more than
    -sb_schwarz_exact_after iterations; from the next Jacobian on every solve is one
    application. The rope's steps end where the serial ones do (1e-10)."""
    scene = long_rope(tmp_path)
    with petsc_options(sb_schwarz_exact="never"):
        sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
        gmres = iterations(sim)
        assert sim.run_dynamic().complete
        assert max(gmres) > 4
    with petsc_options(sb_schwarz_exact_after="4"):
        sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
        auto = iterations(sim)
        assert sim.run_dynamic().complete
        assert sim.snes.getKSP().getType() == PETSc.KSP.Type.PREONLY
        first_slow = next(i for i, n in enumerate(auto) if n > 4)
        assert auto[:first_slow + 1] == gmres[:first_slow + 1]
        assert set(auto[first_slow + 1:]) == {1} and len(auto) > first_slow + 3
        assert_solved_exactly(sim.snes.getKSP())
        distributed_and_serial_records(scene)


def test_auto_leaves_a_large_interface_to_gmres(tmp_path):
    """A rank whose interface has more unknowns than -sb_schwarz_exact_max_interface would pay
    one block solve per interface unknown at every Jacobian: auto keeps GMRES there."""
    scene = long_rope(tmp_path)
    with petsc_options(sb_schwarz_exact_after="4", sb_schwarz_exact_max_interface="10"):
        sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
        counts = iterations(sim)
        assert sim.run_dynamic().complete
        assert sim.snes.getKSP().getType() == PETSc.KSP.Type.GMRES
        assert max(counts) > 4
