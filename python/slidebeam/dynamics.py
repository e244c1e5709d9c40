# SPDX-License-Identifier: MIT
"""Time stepping of a dynamic scene: initial rigid motion, the step loop with step-size cuts
on Newton failure, and the per-step record that goes to history.csv.

The numerics (one SNES solve per step, the four integrators) live in the C++ core
(``_core.TimeIntegrator``); this module is the policy around it.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable

import numpy as np
from petsc4py import PETSc

if TYPE_CHECKING:
    from .simulation import Simulation

@dataclass(frozen=True)
class Reaction:
    """The force (and moment: clamps, rails, rigid joints) a support or joint exerts on the beam
    it holds (a rigid joint: on its first beam), in the global frame, the moment about the held
    point (a rail: about its start). Statics: in equilibrium; a time step: over the step, so that
    with the loads the reactions balance the step's change of momentum."""

    effect: str  # the effect's label, e.g. clamp[rod@start]
    force: tuple[float, float, float]
    moment: tuple[float, float, float] | None = None

    def as_dict(self) -> dict[str, object]:
        d: dict[str, object] = {"effect": self.effect, "force": list(self.force)}
        if self.moment is not None:
            d["moment"] = list(self.moment)
        return d


@dataclass(frozen=True)
class JointState:
    """A sliding joint after a step: sliding coordinate s on the carrier, its mean rate over the
    step, and the reaction force the carrier exerts on the slider (the multipliers; under the
    midpoint-type schemes the step's mean force)."""

    s: float
    ds_dt: float
    reaction: tuple[float, float, float]
    gap: float = 0.0  # distance of the slider point from the carrier's centre line at s


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
    reactions: list[Reaction] = field(default_factory=list)

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
    the beam's first point). Beams joined together and spinning as one body need the same c.
    Every control point's first coordinate 3-block is a point (phi; ANCF: r), the others are
    directions (d_i; ANCF: r'), which only turn."""
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
            base, nq = sim.control_point_unknowns(first + c)
            if not lo <= base < hi:
                continue
            rates = [vel + np.cross(omega, q[c, :3] - origin)] + [np.cross(omega, q[c, 3 * k:3 * k + 3])
                                                                  for k in range(1, nq // 3)]
            arr[base - lo:base - lo + nq] = np.concatenate(rates)
    v.setArray(arr)


@dataclass
class RunState:
    """Where a run stands besides the integrator's vectors: what a checkpoint keeps."""

    records: list[DynamicRecord]  # the recorded good steps so far
    dt: float                     # the current step size (below analysis.dt after cuts)
    step: int = 0                 # accepted steps
    rejected: int = 0
    rejected_since_record: int = 0
    newton: int = 0


@dataclass
class RunOutcome:
    records: list[DynamicRecord]  # every output.every-th step, the last one and a failed attempt
    complete: bool                # reached t_end
    message: str
    steps: int                    # accepted steps
    rejected_steps: int           # failed attempts (retried with a smaller step)
    newton_iterations: int        # over all attempts
    failed: bool = False          # stopped by an error (not: reached t_end, or a scene-requested stop)
    state: RunState | None = None  # where the run stands (for a checkpoint)


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


def run_dynamic(sim: "Simulation", on_step: Callable[[DynamicRecord], None] | None = None,
                state: RunState | None = None,
                on_checkpoint: Callable[[RunState], None] | None = None) -> RunOutcome:
    """Step from the current time to t_end with the scene's integrator.

    A step whose Newton solve fails (or produces NaN/Inf) is retried from the last good state
    with half the step, down to ``dt_min``; after a success the step grows back (doubling) to
    ``dt``. If even ``dt_min`` fails, the run stops with the last good state kept. Records are
    taken every ``output.every`` steps and at the end. ``state`` resumes a run (restart; the
    integrator already holds its vectors); ``on_checkpoint`` is called every
    ``output.checkpoint_every`` accepted steps.
    """
    a = sim.scene.analysis
    integ = sim.integrator
    assert a.dt is not None and a.dt_min is not None
    every = max(1, sim.scene.output.every)
    ckpt_every = sim.scene.output.checkpoint_every
    if state is None:
        state = RunState([sim.record_dynamic(0, None, 0.0, 0)], a.dt)
        if on_step:
            on_step(state.records[0])
    st = state
    st.dt = min(st.dt, a.dt)  # a restart may ask for smaller steps
    t_end = a.t_end

    def outcome(complete: bool, message: str, failed: bool = False, extra: list[DynamicRecord] | None = None):
        return RunOutcome(st.records + (extra or []), complete, message, st.step, st.rejected, st.newton, failed, st)

    while t_end - integ.time > 1e-9 * a.dt:
        # The step is dt unless less remains; a remainder within roundoff of dt is taken as dt,
        # so that a run stopped at t_end and restarted takes exactly the steps of one that went on.
        remaining = t_end - integ.time
        h = st.dt if remaining >= st.dt * (1 - 1e-9) else remaining
        t_step = time.perf_counter()
        result = integ.step(h)
        sim.step_wall_times.append(time.perf_counter() - t_step)
        st.newton += result.iterations
        if result.converged:  # the core already counts NaN/Inf in F or x as a failure
            st.step += 1
            last = t_end - integ.time <= 1e-9 * a.dt
            joints = sim.joint_states(gaps=False) if sim.scene.sliding_joints else []
            ended = _carrier_end(sim, joints, st.step) if joints else None
            if st.step % every == 0 or last or ended:
                rec = sim.record_dynamic(st.step, result, h, st.rejected_since_record, joints)
                st.rejected_since_record = 0
                st.records.append(rec)
                if on_step:
                    on_step(rec)
            st.dt = min(2 * st.dt, a.dt)
            if ended:
                behaviour, message = ended
                return outcome(False, message, failed=behaviour == "fail")
            if on_checkpoint and ckpt_every and st.step % ckpt_every == 0 and not last:
                on_checkpoint(st)
            continue
        st.rejected += 1
        st.rejected_since_record += 1
        if h / 2 < a.dt_min * (1 - 1e-12):
            # the failed attempt, with the values of the last good state that is kept
            fail = sim.record_dynamic(st.step + 1, result, h, st.rejected_since_record)
            fail.converged = False
            if on_step:
                on_step(fail)
            message = (f"Newton failed at step {st.step + 1} (t = {integ.time:.6g} -> {integ.time + h:.6g}, "
                       f"dt = {h:.3g}, minimum dt_min = {a.dt_min:.3g}): {result.reason_name}, "
                       f"residual norm {result.residual_norm:.3e}; results hold the last good state "
                       f"(t = {integ.time:.6g}) and are marked incomplete")
            return outcome(False, message, failed=True, extra=[fail])
        st.dt = h / 2
    return outcome(True, "completed")
