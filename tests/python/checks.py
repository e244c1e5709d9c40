# SPDX-License-Identifier: MIT
"""Checks shared by the dynamics and sliding-joint tests: finite differences of a step's
Jacobian, and a run on all ranks against the same run on one; a dynamic scene file as a
static analysis."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc


def trial_end_state(sim, steps: int, h: float, seed: int) -> PETSc.Vec:
    """Take `steps` steps of size h (off the reference state: multipliers, strains and velocities
    nonzero), prepare the next one and return a trial end state x_n + h v_n plus 1e-3 noise
    (not assembled: the caller may set values before assembling)."""
    integ = sim.integrator
    for _ in range(steps):
        assert integ.step(h).converged
    integ.prepare_step(h)
    x1 = integ.x.copy()
    x1.axpy(h, integ.v)
    rng = np.random.default_rng(seed + MPI.COMM_WORLD.Get_rank())
    lo, hi = x1.getOwnershipRange()
    x1.setValues(range(lo, hi), x1.getArray() + 1e-3 * rng.standard_normal(hi - lo))
    return x1


def step_jacobian_error(sim, x1: PETSc.Vec, eps: float = 1e-6, rows: list[int] | None = None) -> tuple[float, float]:
    """(max |J e_j - central FD of the step residual|, max |J e_j|) over all columns j, with the
    integrator's step prepared (prepare_step) and J assembled at x1. With rows: only the
    entries J[i, j] with i or j in rows (a joint's own rows and columns, on their own scale)."""
    integ = sim.integrator
    J = sim.jacobian
    integ.step_jacobian(x1, J)
    lo, hi = x1.getOwnershipRange()
    Fp, Fm, Jcol, e, mask = (x1.duplicate() for _ in range(5))
    mask.zeroEntries()
    for i in rows or []:
        if lo <= i < hi:
            mask.setValue(i, 1.0)
    mask.assemble()
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
        Fp.axpy(-1.0, Jcol)
        if rows is not None and j not in rows:  # only the given rows of this column
            Fp.pointwiseMult(Fp, mask)
            Jcol.pointwiseMult(Jcol, mask)
        scale = max(scale, Jcol.norm(PETSc.NormType.INFINITY))
        worst = max(worst, Fp.norm(PETSc.NormType.INFINITY))
    for v in (Fp, Fm, Jcol, e, mask):
        v.destroy()
    return worst, scale


def check_step_jacobian(sim, steps: int, h: float, seed: int, label: str = "") -> None:
    """The step Jacobian at a trial end state after `steps` steps of size h (trial_end_state)
    matches central finite differences of the step residual to 1e-6 of its largest entry (and
    the residual there is not zero: the test compares something)."""
    x1 = trial_end_state(sim, steps=steps, h=h, seed=seed)
    x1.assemble()
    worst, scale = step_jacobian_error(sim, x1)
    F = x1.duplicate()
    sim.integrator.step_residual(x1, F)
    assert F.norm() > 0
    assert worst <= 1e-6 * scale, f"{label}: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"


def with_em_dissipation(scene, integrator: str):
    """The scene under `integrator`'s name's energy-decaying variant ("energy-momentum, xi = 0.3"),
    or as it is."""
    if "xi" not in integrator:
        return scene
    return dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, em_dissipation=0.3))


def check_step_jacobian_and_rows(sim, rows: list[int], seed: int, label: str) -> None:
    """The step Jacobian at a trial end state after 2 steps of 0.01 against central finite
    differences, as a whole and on the given rows and columns (a joint's multipliers, a body's
    unknowns) on their own scale, where the beams' stiffness would hide their errors."""
    x1 = trial_end_state(sim, steps=2, h=0.01, seed=seed)
    x1.assemble()
    worst, scale = step_jacobian_error(sim, x1)
    assert worst <= 1e-6 * scale, f"{label}: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"
    worst, scale = step_jacobian_error(sim, x1, rows=rows)
    assert scale > 0.1 and worst <= 1e-6 * scale, f"{label}: on its rows |J - FD| = {worst:.3e}, |J| = {scale:.3e}"


def joint_multipliers(sim, count: int) -> list[int]:
    """The global indices of the multipliers of the scene's one joint ([[joint]], [[rigid_joint]])."""
    (k,) = [k for k, e in enumerate(sim.active_effects) if e.type.endswith("_joint")]
    first = sim._model.extra_offset(k)
    return list(range(first, first + count))


def drifts(records) -> dict[str, float]:
    """Largest change over a run: energy relative to the largest kinetic energy, momenta
    relative to their initial size."""
    H = np.array([r.total_energy for r in records])
    L = np.array([r.linear_momentum for r in records])
    J = np.array([r.angular_momentum for r in records])
    return {"energy": float(np.abs(H - H[0]).max() / max(r.kinetic_energy for r in records)),
            "linear": float(np.abs(L - L[0]).max() / np.linalg.norm(L[0])),
            "angular": float(np.abs(J - J[0]).max() / np.linalg.norm(J[0]))}


def joint_jacobian_error(sim, x1: PETSc.Vec, joint_dofs: list[int], eps: float = 1e-5) -> tuple[float, float]:
    """step_jacobian_error restricted to the joint's rows and columns (s, mu). The beams'
    stiffness (EA ~ 5e6) dominates the whole matrix's scale, so the joint's entries get their
    own. eps = 1e-5: the position rows' residuals (~1e3) make the roundoff of a 1e-6 difference
    ~1e-7."""
    return step_jacobian_error(sim, x1, eps, joint_dofs)


def check_joint_step_jacobian(sim, ds: float, label: str) -> None:
    """A trial end state with the sliding coordinate moved by ds from the step start (across
    knots or nodes as ds says): the step Jacobian equals central finite differences of the step
    residual, as a whole (scale: the beams' stiffness) and on the joint's own rows and columns
    (s, mu) on their own scale, where the whole-matrix check would hide a 10 % error."""
    x1 = trial_end_state(sim, steps=3, h=0.01, seed=11)
    lo, hi = x1.getOwnershipRange()
    i_s = sim.sliding_coordinate_index()
    s0 = sim.joint_states()[0].s
    if lo <= i_s < hi:
        x1.setValue(i_s, s0 + ds)
    x1.assemble()
    worst, scale = step_jacobian_error(sim, x1)
    assert scale > 1.0
    assert worst <= 1e-6 * scale, f"{label}, ds = {ds}: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"
    worst, scale = joint_jacobian_error(sim, x1, [i_s - 3, i_s - 2, i_s - 1, i_s])
    assert scale > 0.1
    assert worst <= 1e-6 * scale, f"{label}, ds = {ds}: joint |J - FD| = {worst:.3e}, |J| = {scale:.3e}"


def distributed_and_serial_records(scene) -> list[tuple]:
    """Run a dynamic scene on every rank of COMM_WORLD and alone on each rank; check that energy
    and tracked points agree to 1e-10 and return the record pairs (world, alone) for more checks.
    Meaningful under mpirun -n 2."""
    import slidebeam

    world = slidebeam.Simulation(scene, MPI.COMM_WORLD).run_dynamic().records
    alone = slidebeam.Simulation(scene, MPI.COMM_SELF).run_dynamic().records
    assert len(world) == len(alone)
    for a, b in zip(world, alone):
        assert abs(a.total_energy - b.total_energy) <= 1e-10 * max(1.0, abs(b.total_energy))
        assert np.abs(np.array(a.tracked) - np.array(b.tracked)).max() < 1e-10
    return list(zip(world, alone))


def static_scene_text(path: Path, steps: int) -> str:
    """The text of the dynamic scene file at path as a static analysis in `steps` load steps:
    [analysis] type = "static", and the keys only a dynamic analysis has (integrator, start,
    t_end, dt) dropped."""
    dynamic_only = ("integrator =", 'start = "', "t_end =", "dt =")
    text = "\n".join(line for line in path.read_text().splitlines() if not line.startswith(dynamic_only))
    return text.replace('type = "dynamic"', f'type = "static"\nsteps = {steps}') + "\n"


def upward_crossings(records, coordinate: int = 0, tracked: int = -1) -> np.ndarray:
    """The times at which a tracked point's coordinate crosses 0 upwards (linear interpolation
    between records): one per period of a swing about 0."""
    t = np.array([r.t for r in records])
    x = np.array([r.tracked[tracked][coordinate] for r in records])
    return np.array([t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
                     for i in range(len(x) - 1) if x[i] < 0 <= x[i + 1]])


def hanger_toml(carrier: str, top: tuple[float, float, float], length: float) -> str:
    """TOML of a steel hanger (2 spans, r = 1 cm) hanging straight down from `top` and sliding on
    `carrier` there: a [[beam]] "hanger" and its [[sliding_joint]]."""
    x, y, z = top
    return f"""
[[beam]]
name = "hanger"
start = [{x!r}, {y!r}, {z!r}]
end = [{x!r}, {y!r}, {z - length!r}]
d2 = [1.0, 0.0, 0.0]
spans = 2
section = {{ shape = "circle", r = 0.01, E = 2.1e11, nu = 0.3, rho = 7800.0 }}

[[sliding_joint]]
slider = "hanger"
at = "start"
carrier = "{carrier}"
"""
