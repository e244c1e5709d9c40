# SPDX-License-Identifier: MIT
"""Time stepping of a dynamic scene: initial rigid motion, the run loop (records, checkpoints,
signals, how the run ended) and the per-step record that goes to history.csv.

The numerics (one SNES solve per step, the four integrators: ``_core.TimeIntegrator``) and the
step control (step sizes, cuts on Newton failure, events such as a slider reaching its
carrier's end: ``_core.Stepper``) live in the C++ core; this module calls it once per step.
"""
from __future__ import annotations

import math

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable

import numpy as np
from petsc4py import PETSc

from .. import _core
from . import interrupts

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
    """One time step as it goes to history.csv (``RunOutcome.records``); step 0 is the initial
    state. Energies in J, momenta in the global frame; ``tracked``, ``joints`` and
    ``reactions`` as in :class:`~slidebeam.run.simulation.StepRecord`."""

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
    outputs: list[float] = field(default_factory=list)  # the effects' named values (Simulation.output_labels)
    # The energy balance since the start: work put in from outside W (loads that vary or do not
    # derive from a potential, drives), energy dissipated D (damping, friction), and
    # |H - H_0 - W + D|: the Newton tolerance under energy-momentum, the numerical dissipation
    # of the other schemes.
    work: float = 0.0
    dissipated: float = 0.0
    energy_balance_error: float = 0.0
    flows: list[float] = field(default_factory=list)  # per counted effect (Simulation.energy_flow_labels)

    @property
    def total_energy(self) -> float:
        return self.kinetic_energy + self.strain_energy + self.potential_energy

    @staticmethod
    def header() -> list[str]:
        return ["step", "t", "dt", "converged", "reason", "newton_iterations", "rejected_steps", "residual_norm",
                "kinetic_energy", "strain_energy", "potential_energy", "total_energy",
                "work", "dissipated", "energy_balance_error",
                "linear_momentum.x", "linear_momentum.y", "linear_momentum.z",
                "angular_momentum.x", "angular_momentum.y", "angular_momentum.z", "constraint_residual"]

    def row(self) -> list[object]:
        return [self.step, repr(self.t), repr(self.dt), int(self.converged), self.reason, self.newton_iterations,
                self.rejected_steps, repr(self.residual_norm), repr(self.kinetic_energy), repr(self.strain_energy),
                repr(self.potential_energy), repr(self.total_energy), repr(self.work), repr(self.dissipated),
                repr(self.energy_balance_error), *[repr(v) for v in self.linear_momentum],
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
    movers = [(b.index, b.velocity, b.angular_velocity, b.rotation_center) for b in sim.scene.beams]
    movers += [(b.index, b.velocity, b.angular_velocity, b.position) for b in sim.scene.bodies]
    for index, velocity, angular_velocity, center in movers:
        vel, omega = np.asarray(velocity), np.asarray(angular_velocity)
        if not (vel.any() or omega.any()):
            continue
        q = sim.control_points(index)
        origin = np.asarray(center) if center is not None else sim.evaluate(index, 0.0)[0, :3]
        first = sim.first_control_point(index)
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
    """What ``Simulation.run_dynamic`` returns: the history records and how the run ended."""

    records: list[DynamicRecord]  # every output.every-th step, the last one and a failed attempt
    complete: bool                # reached t_end
    message: str                  # "completed", or why the run ended before t_end
    steps: int                    # accepted steps
    rejected_steps: int           # failed attempts (retried with a smaller step)
    newton_iterations: int        # over all attempts
    failed: bool = False          # stopped by an error (not: reached t_end, or a scene-requested stop)
    state: RunState | None = None  # where the run stands (for a checkpoint)
    stopped: str | None = None    # why a run that did not fail ended before t_end (carrier end, signal)
    signal: int | None = None     # the signal (SIGINT, SIGTERM) that stopped it


def error_control_args(sim: "Simulation") -> dict[str, float]:
    """Stepper.set_error_control's arguments for the scene's [analysis] adapt: atol defaults to
    rtol times the longest beam's length; the scheme's error constant C is 1/12 for
    energy-momentum and midpoint, |beta - 1/12| / 2 for Newmark and HHT (time/error_control.hpp)."""
    a = sim.scene.analysis
    assert a.adapt is not None
    length = max((b.geometry.length for b in sim.scene.beams), default=1.0)
    atol = a.adapt.atol if a.adapt.atol is not None else a.adapt.rtol * length
    constant = 1.0 / 12.0
    if a.integrator in ("newmark", "hht"):
        constant = abs(a.newmark_beta - 1.0 / 12.0) / 2.0
    return dict(rtol=a.adapt.rtol, atol=atol, dt_max=a.adapt.dt_max, span=a.t_end, constant=constant)


def run_dynamic(sim: "Simulation", on_step: Callable[[DynamicRecord], None] | None = None,
                state: RunState | None = None,
                on_checkpoint: Callable[[RunState], None] | None = None) -> RunOutcome:
    """Step from the current time to t_end with the scene's integrator.

    The core's Stepper (src/time/stepper.hpp) chooses the steps: a step whose Newton solve fails
    (or produces NaN/Inf) is retried from the last good state with half the step, down to
    ``dt_min``; after a success the step grows back (doubling) to ``dt``. If even ``dt_min``
    fails, the run stops with the last good state kept. A slider that passes its carrier's end
    ends the run with a last step shortened to the arrival (an event: the effect says what happened
    and whether the run stops or fails). Records are taken every
    ``output.every`` steps, or at the first step that reaches each multiple of ``output.interval``,
    and at the end. ``state`` resumes a run (restart; the integrator
    already holds its vectors); ``on_checkpoint`` is called every ``output.checkpoint_every``
    accepted steps.
    """
    a = sim.scene.analysis
    assert a.dt is not None and a.dt_min is not None
    if state is None:
        state = RunState([sim.record_dynamic(0, None, 0.0, 0)], a.dt)
        if on_step:
            on_step(state.records[0])
    st = state
    if a.adapt is None:
        st.dt = min(st.dt, a.dt)  # a restart may ask for smaller steps

    def outcome(complete: bool, message: str, failed: bool = False, extra: list[DynamicRecord] | None = None):
        return RunOutcome(st.records + (extra or []), complete, message, st.step, st.rejected, st.newton, failed, st)

    stepper = _core.Stepper(sim._model, sim.integrator, a.dt_max_step, a.dt_min)
    stepper.dt = st.dt
    if a.adapt is not None:
        stepper.set_error_control(**error_control_args(sim))
    return _step_loop(sim, stepper, st, on_step, on_checkpoint, outcome)


def _next_multiple(t: float, interval: float) -> float:
    """The first multiple of interval after t (a t within roundoff of a multiple is on it)."""
    return (math.floor(t / interval + 1e-9) + 1) * interval


def _step_loop(sim: "Simulation", stepper: "_core.Stepper", st: RunState, on_step, on_checkpoint,
               outcome) -> RunOutcome:
    a = sim.scene.analysis
    integ = sim.integrator
    every = max(1, sim.scene.output.every)
    interval = sim.scene.output.interval  # > 0: records by time instead of every
    next_record = _next_multiple(integ.time, interval) if interval > 0 else math.inf
    ckpt_every = sim.scene.output.checkpoint_every
    t_end = a.t_end
    last_accepted: tuple[object, float] | None = None  # (result, h) of the last accepted step, if not recorded

    def record_last_accepted() -> None:
        if last_accepted is not None:  # the last good state goes to the history
            rec = sim.record_dynamic(st.step, last_accepted[0], last_accepted[1], st.rejected_since_record)
            st.rejected_since_record = 0
            st.records.append(rec)
            if on_step:
                on_step(rec)

    def interrupted(signum: int) -> RunOutcome:
        record_last_accepted()
        reason = f"interrupted by {interrupts.describe(signum)}"
        res = outcome(False, f"{reason} at t = {integ.time:.6g} (step {st.step}); results hold the state at "
                             f"t = {integ.time:.6g} and are marked incomplete")
        res.stopped, res.signal = reason, signum
        return res

    while t_end - integ.time > 1e-9 * a.dt:
        adv = stepper.advance(t_end)
        sim.step_wall_times.append(adv.wall_time)
        st.newton += adv.newton_iterations
        st.rejected += adv.rejected_attempts
        st.dt = stepper.dt
        result, h = adv.result, adv.h
        if adv.status == "event":  # an indicator crossed (a slider passed its carrier's end): the run ends there
            effect, index, _ = stepper.events[adv.event]
            if adv.event_step_taken:
                st.step += 1
                st.records.append(sim.record_dynamic(st.step, result, h, st.rejected_since_record))
                if on_step:
                    on_step(st.records[-1])
            else:  # no shortened step stayed inside: t_n is the arrival
                record_last_accepted()
            st.rejected_since_record = 0
            message = sim._model.event_message(effect, index, adv.event_value,
                                               f"at t = {integ.time:.9g} (step {st.step}, a shortened last step)")
            res = outcome(False, message, failed=sim._model.event_fails_run(effect, index))
            res.stopped = message
            return res
        if adv.status == "accepted":
            st.step += 1
            if st.step == 1:
                sim.count_initial_snap()
            last = t_end - integ.time <= 1e-9 * a.dt
            due = integ.time >= next_record - 1e-9 * interval if interval > 0 else st.step % every == 0
            if due or last:
                if interval > 0:
                    next_record = _next_multiple(integ.time, interval)
                rec = sim.record_dynamic(st.step, result, h, st.rejected_since_record)
                st.rejected_since_record = 0
                st.records.append(rec)
                last_accepted = None
                if on_step:
                    on_step(rec)
            else:
                last_accepted = (result, h)
            signum = interrupts.requested()
            if signum:
                return interrupted(signum)
            if on_checkpoint and ckpt_every and st.step % ckpt_every == 0 and not last:
                on_checkpoint(st)
                stepper.restart_error_estimate()  # goes on as a restart from the checkpoint would
            continue
        st.rejected_since_record += 1  # a cut or the failure
        if adv.status == "failed":
            # the failed attempt, with the values of the last good state that is kept
            fail = sim.record_dynamic(st.step + 1, result, h, st.rejected_since_record)
            fail.converged = False
            if on_step:
                on_step(fail)
            what, cause = "Newton failed", f"{result.reason_name}, residual norm {result.residual_norm:.3e}"
            if adv.local_error > 1.0:
                what, cause = "the error control failed", f"the local error stayed {adv.local_error:.3g} times the tolerance"
            message = (f"{what} at step {st.step + 1} (t = {integ.time:.6g} -> {integ.time + h:.6g}, dt = {h:.3g}, "
                       f"minimum dt_min = {a.dt_min:.3g}): {cause}; results hold the last good state "
                       f"(t = {integ.time:.6g}) and are marked incomplete")
            return outcome(False, message, failed=True, extra=[fail])
        signum = interrupts.requested()  # a cut: the next advance tries half the step
        if signum:
            return interrupted(signum)
    return outcome(True, "completed")
