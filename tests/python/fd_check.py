# SPDX-License-Identifier: MIT
"""Finite-difference check of a dynamic step's Jacobian (shared by the dynamics and sliding tests)."""
from __future__ import annotations

from petsc4py import PETSc


def step_jacobian_error(sim, x1: PETSc.Vec, eps: float = 1e-6) -> tuple[float, float]:
    """(max |J e_j - central FD of the step residual|, max |J e_j|) over all columns j, with the
    integrator's step prepared (prepare_step) and J assembled at x1."""
    integ = sim.integrator
    J = sim.jacobian
    integ.step_jacobian(x1, J)
    lo, hi = x1.getOwnershipRange()
    Fp, Fm, Jcol, e = x1.duplicate(), x1.duplicate(), x1.duplicate(), x1.duplicate()
    worst = scale = 0.0
    for j in range(x1.getSize()):
        e.zeroEntries()
        if lo <= j < hi:
            e.setValue(j, 1.0)
        e.assemble()
        xp = x1.copy()
        xp.axpy(eps, e)
        integ.step_residual(xp, Fp)
        xp.axpy(-2 * eps, e)
        integ.step_residual(xp, Fm)
        xp.destroy()
        J.mult(e, Jcol)
        Fp.axpy(-1.0, Fm)
        Fp.scale(1.0 / (2 * eps))
        scale = max(scale, Jcol.norm(PETSc.NormType.INFINITY))
        Fp.axpy(-1.0, Jcol)
        worst = max(worst, Fp.norm(PETSc.NormType.INFINITY))
    for v in (Fp, Fm, Jcol, e):
        v.destroy()
    return worst, scale
