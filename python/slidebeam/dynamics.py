# SPDX-License-Identifier: MIT
"""Time stepping of a dynamic scene: initial rigid motion, the step loop with step-size cuts
on Newton failure, and the per-step record that goes to history.csv.

The numerics (one SNES solve per step, the four integrators) live in the C++ core
(``_core.TimeIntegrator``); this module is the policy around it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable

import numpy as np
from petsc4py import PETSc

if TYPE_CHECKING:
    from .simulation import Simulation

BLOCK = 18  # unknowns per control point: phi, d1, d2, d3, then 6 multipliers


@dataclass(frozen=True)
class JointState:
    """A sliding joint after a step: sliding coordinate s on the carrier, its mean rate over the
    step, and the reaction force the carrier exerts on the slider (the multipliers; under the
    midpoint-type schemes the step's mean force)."""

    s: float
    ds_dt: float
    reaction: tuple[float, float, float]


@dataclass
class DynamicRecord:
    """One time step as it goes to history.csv."""

    step: int
    t: float
    dt: float
    converged: bool
    reason: str
    newton_iterations: int
    residual_norm: float
    kinetic_energy: float
    strain_energy: float
    potential_energy: float
    linear_momentum: tuple[float, float, float]
    angular_momentum: tuple[float, float, float]
    constraint_residual: float
    rejected_steps: int = 0
    tracked: list[tuple[float, float, float]] = field(default_factory=list)
    joints: list[JointState] = field(default_factory=list)

    @property
    def total_energy(self) -> float:
        return self.kinetic_energy + self.strain_energy + self.potential_energy

    @staticmethod
    def header() -> list[str]:
        return ["step", "t", "dt", "converged", "reason", "newton_iterations", "rejected_steps", "residual_norm",
                "kinetic_energy", "strain_energy", "potential_energy", "total_energy",
                "linear_momentum.x", "linear_momentum.y", "linear_momentum.z",
                "angular_momentum.x", "angular_momentum.y", "angular_momentum.z", "constraint_residual"]

    def row(self) -> list[object]:
        return [self.step, repr(self.t), repr(self.dt), int(self.converged), self.reason, self.newton_iterations,
                self.rejected_steps, repr(self.residual_norm), repr(self.kinetic_energy), repr(self.strain_energy),
                repr(self.potential_energy), repr(self.total_energy), *[repr(v) for v in self.linear_momentum],
                *[repr(v) for v in self.angular_momentum], repr(self.constraint_residual)]


def initial_velocity(sim: "Simulation", v: PETSc.Vec) -> None:
    """Rigid initial motion of each beam: phi_dot = v + w x (phi - c), d_i_dot = w x d_i, with
    the beam's ``velocity`` v and ``angular_velocity`` w about its ``rotation_center`` c (default:
    the beam's first point). Beams joined together and spinning as one body need the same c."""
    lo, hi = v.getOwnershipRange()
    arr = v.getArray()
    arr[:] = 0.0
    for beam in sim.scene.beams:
        vel, omega = np.asarray(beam.velocity), np.asarray(beam.angular_velocity)
        if not (vel.any() or omega.any()):
            continue
        q = sim.control_points(beam.index)
        origin = (np.asarray(beam.rotation_center) if beam.rotation_center is not None
                  else sim.evaluate(beam.index, 0.0)[0, :3])
        first = sim.first_control_point(beam.index)
        for c in range(q.shape[0]):
            base = BLOCK * (first + c)
            if not lo <= base < hi:
                continue
            rates = [vel + np.cross(omega, q[c, :3] - origin)] + [np.cross(omega, q[c, 3 * k:3 * k + 3]) for k in (1, 2, 3)]
            arr[base - lo:base - lo + 12] = np.concatenate(rates)
    v.setArray(arr)


@dataclass
class RunOutcome:
    records: list[DynamicRecord]  # every output.every-th step, the last one and a failed attempt
    complete: bool                # reached t_end
    message: str
    steps: int                    # accepted steps
    rejected_steps: int           # failed attempts (retried with a smaller step)
    newton_iterations: int        # over all attempts
    failed: bool = False          # stopped by an error (not: reached t_end, or a scene-requested stop)


def _carrier_end(sim: "Simulation", joints: list[JointState], step: int) -> tuple[str, str] | None:
    """(behaviour, message) if a slider has left its carrier, else None."""
    for j, state in zip(sim.scene.sliding_joints, joints):
        length = sim.scene.beams[j.carrier].geometry.length
        if -1e-12 * length <= state.s <= length * (1 + 1e-12):
            continue
        slider, carrier = sim.scene.beams[j.slider].name, sim.scene.beams[j.carrier].name
        end = "start" if state.s < 0 else "end"
        return j.at_carrier_end, (f"the slider of beam '{slider}' reached the {end} of carrier '{carrier}' "
                                  f"(s = {state.s:.6g}, carrier length {length:g}) at step {step}, "
                                  f"t = {sim.t:.6g}; run stopped (at_carrier_end = '{j.at_carrier_end}')")
    return None


def run_dynamic(sim: "Simulation", on_step: Callable[[DynamicRecord], None] | None = None) -> RunOutcome:
    """Step from t = 0 to t_end with the scene's integrator.

    A step whose Newton solve fails (or produces NaN/Inf) is retried from the last good state
    with half the step, down to ``dt_min``; after a success the step grows back (doubling) to
    ``dt``. If even ``dt_min`` fails, the run stops with the last good state kept. Records are
    taken every ``output.every`` steps and at the end.
    """
    a = sim.scene.analysis
    integ = sim.integrator
    assert a.dt is not None and a.dt_min is not None
    every = max(1, sim.scene.output.every)
    records = [sim.record_dynamic(0, None, 0.0, 0)]
    if on_step:
        on_step(records[0])
    dt, step, rejected, rejected_since_record, newton = a.dt, 0, 0, 0, 0
    t_end = a.t_end
    message = "completed"
    complete, failed = True, False
    while integ.time < t_end * (1 - 1e-12):
        h = min(dt, t_end - integ.time)
        if t_end - (integ.time + h) < 1e-9 * a.dt:  # land exactly on t_end
            h = t_end - integ.time
        result = integ.step(h)
        newton += result.iterations
        if result.converged:  # the core already counts NaN/Inf in F or x as a failure
            step += 1
            last = integ.time >= t_end * (1 - 1e-12)
            joints = sim.joint_states() if sim.scene.sliding_joints else []
            ended = _carrier_end(sim, joints, step) if joints else None
            if step % every == 0 or last or ended:
                rec = sim.record_dynamic(step, result, h, rejected_since_record, joints)
                rejected_since_record = 0
                records.append(rec)
                if on_step:
                    on_step(rec)
            if ended:
                behaviour, message = ended
                return RunOutcome(records, False, message, step, rejected, newton, failed=behaviour == "fail")
            dt = min(2 * dt, a.dt)
            continue
        rejected += 1
        rejected_since_record += 1
        if h / 2 < a.dt_min * (1 - 1e-12):
            # the failed attempt, with the values of the last good state that is kept
            fail = sim.record_dynamic(step + 1, result, h, rejected_since_record)
            fail.converged = False
            records.append(fail)
            if on_step:
                on_step(fail)
            complete = False
            failed = True
            message = (f"Newton failed at step {step + 1} (t = {integ.time:.6g} -> {integ.time + h:.6g}, "
                       f"dt = {h:.3g}, minimum dt_min = {a.dt_min:.3g}): {result.reason_name}, "
                       f"residual norm {result.residual_norm:.3e}; results hold the last good state "
                       f"(t = {integ.time:.6g}) and are marked incomplete")
            break
        dt = h / 2
    return RunOutcome(records, complete, message, step, rejected, newton, failed)
