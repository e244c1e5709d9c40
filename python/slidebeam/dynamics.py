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
    ``reactions`` as in :class:`~slidebeam.simulation.StepRecord`."""

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


class _Snapshot:
    """The integrator's state at t_n (taken before each step), to take a step again with another
    size: buffers allocated once, filled by take()."""

    def __init__(self, sim: "Simulation") -> None:
        from .checkpoint import VECTORS

        self._integ = sim.integrator
        self._vecs = {name: getattr(self._integ, name) for name in VECTORS}
        self.copies = {name: vec.duplicate() for name, vec in self._vecs.items()}
        self._time: tuple = ()

    def take(self) -> None:
        integ = self._integ
        for name, vec in self._vecs.items():
            vec.copy(self.copies[name])
        self._time = (integ.time, integ.h_prev, bool(integ.pivoting_lu), *integ.time_segment)
        self._flows = [w for _, _, w in integ.energy_flows]

    def restore(self) -> None:
        for name, vec in self._vecs.items():
            self.copies[name].copy(vec)
        t, h_prev, pivoting, seg_start, seg_steps = self._time
        self._integ.restore(t, h_prev, pivoting, seg_start, seg_steps)
        self._integ.set_energy_flows(self._flows)

    def destroy(self) -> None:
        for vec in self.copies.values():
            vec.destroy()


def carrier_end(sim: "Simulation", joints: list[JointState]) -> tuple[int, float] | None:
    """(joint, the end's s) of the first sliding joint whose slider is beyond an end of its
    carrier, else None."""
    for k, (j, state) in enumerate(zip(sim.scene.sliding_joints, joints)):
        length = sim.scene.beams[j.carrier].geometry.length
        if state.s < -1e-12 * length:
            return k, 0.0
        if state.s > length * (1 + 1e-12):
            return k, length
    return None


def carrier_end_message(sim: "Simulation", joint: int, s: float, when: str) -> str:
    j = sim.scene.sliding_joints[joint]
    slider, carrier = sim.scene.beams[j.slider].name, sim.scene.beams[j.carrier].name
    end = "start" if s <= 0 else "end"
    return (f"the slider of beam '{slider}' reached the {end} of carrier '{carrier}' (s = {s:.9g}) {when}; "
            f"run stopped (at_carrier_end = '{j.at_carrier_end}')")


# An arrival at a carrier end is accepted within this fraction of the carrier's length
ARRIVAL_TOLERANCE = 1e-9


def _arrive(sim: "Simulation", snapshot: _Snapshot, h: float, joint: int, s_end: float, s_out: float,
            st: RunState) -> tuple[object | None, float]:
    """Take the step that ended beyond a carrier end again, shortened so that the slider arrives
    at the end (Illinois regula falsi on the step size, from the state at t_n). Returns the
    accepted step's result and size, with the slider on the carrier within ARRIVAL_TOLERANCE of
    its length from the end, or the closest inside try; (None, 0) if no try stayed inside (the
    state at t_n is kept)."""
    integ = sim.integrator
    k = sim.sliding_joint_effects()[joint]
    length = sim.scene.beams[sim.scene.sliding_joints[joint].carrier].geometry.length
    s0 = float(sim._model.extra_values(k, snapshot.copies["x"])[3])
    inward = 1.0 if s0 <= s_end else -1.0  # distance to the end is inward * (s_end - s)

    h_in, d_in = 0.0, inward * (s_end - s0)        # d >= 0 on the carrier
    h_out, d_out = h, inward * (s_end - s_out)     # < 0 beyond the end
    best: float | None = None
    side = 0
    for _ in range(16):
        snapshot.restore()
        h_try = h_in + (h_out - h_in) * d_in / (d_in - d_out)
        h_try = min(max(h_try, h_in + 1e-4 * (h_out - h_in)), h_out - 1e-4 * (h_out - h_in))
        result = integ.step(h_try)
        st.newton += result.iterations
        st.rejected += 0 if result.converged else 1
        d = inward * (s_end - float(sim._model.extra_values(k, integ.x)[3])) if result.converged else -1.0
        if d >= 0:
            best = h_try
            if d <= ARRIVAL_TOLERANCE * length:
                return result, h_try
            h_in, d_in = h_try, d
            d_out *= 0.5 if side == 1 else 1.0  # Illinois: the same side twice halves the other end
            side = 1
        else:
            h_out, d_out = h_try, (d if result.converged else 0.5 * d_out)
            d_in *= 0.5 if side == -1 else 1.0
            side = -1
    snapshot.restore()
    if best is None:
        return None, 0.0
    result = integ.step(best)
    st.newton += result.iterations
    return result, best


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
    assert a.dt is not None and a.dt_min is not None
    if state is None:
        state = RunState([sim.record_dynamic(0, None, 0.0, 0)], a.dt)
        if on_step:
            on_step(state.records[0])
    st = state
    st.dt = min(st.dt, a.dt)  # a restart may ask for smaller steps

    def outcome(complete: bool, message: str, failed: bool = False, extra: list[DynamicRecord] | None = None):
        return RunOutcome(st.records + (extra or []), complete, message, st.step, st.rejected, st.newton, failed, st)

    snapshot = _Snapshot(sim) if sim.scene.sliding_joints else None
    try:
        return _step_loop(sim, st, on_step, on_checkpoint, outcome, snapshot)
    finally:
        if snapshot is not None:
            snapshot.destroy()


def _step_loop(sim: "Simulation", st: RunState, on_step, on_checkpoint, outcome, snapshot) -> RunOutcome:
    a = sim.scene.analysis
    integ = sim.integrator
    every = max(1, sim.scene.output.every)
    ckpt_every = sim.scene.output.checkpoint_every
    t_end = a.t_end
    last_accepted: tuple[object, float] | None = None  # (result, h) of the last accepted step, if not recorded

    def interrupted(signum: int) -> RunOutcome:
        if last_accepted is not None:  # the last good state goes to the history
            rec = sim.record_dynamic(st.step, last_accepted[0], last_accepted[1], st.rejected_since_record)
            st.rejected_since_record = 0
            st.records.append(rec)
            if on_step:
                on_step(rec)
        reason = f"interrupted by {interrupts.describe(signum)}"
        res = outcome(False, f"{reason} at t = {integ.time:.6g} (step {st.step}); results hold the state at "
                             f"t = {integ.time:.6g} and are marked incomplete")
        res.stopped, res.signal = reason, signum
        return res

    while t_end - integ.time > 1e-9 * a.dt:
        # The step is dt unless less remains; a remainder within roundoff of dt is taken as dt,
        # so that a run stopped at t_end and restarted takes exactly the steps of one that went on.
        remaining = t_end - integ.time
        h = st.dt if remaining >= st.dt * (1 - 1e-9) else remaining
        if snapshot is not None:
            snapshot.take()
        t_step = time.perf_counter()
        result = integ.step(h)
        sim.step_wall_times.append(time.perf_counter() - t_step)
        st.newton += result.iterations
        if result.converged:  # the core already counts NaN/Inf in F or x as a failure
            joints = sim.joint_states(gaps=False, reactions=False) if sim.scene.sliding_joints else []
            ended = carrier_end(sim, joints) if joints else None
            if ended:
                # end the run with the slider at the carrier end: the step again, shortened
                joint, s_end = ended
                result, h = _arrive(sim, snapshot, h, joint, s_end, joints[joint].s, st)
                if result is None:  # no shortened step stayed on the carrier: t_n is the arrival
                    if last_accepted is not None:
                        st.records.append(sim.record_dynamic(st.step, last_accepted[0], last_accepted[1],
                                                             st.rejected_since_record))
                        if on_step:
                            on_step(st.records[-1])
                    joints = sim.joint_states(gaps=False, reactions=False)
                else:
                    st.step += 1
                    joints = sim.joint_states(gaps=False, reactions=False)
                    st.records.append(sim.record_dynamic(st.step, result, h, st.rejected_since_record, joints))
                    if on_step:
                        on_step(st.records[-1])
                st.rejected_since_record = 0
                j = sim.scene.sliding_joints[joint]
                message = carrier_end_message(sim, joint, joints[joint].s,
                                              f"at t = {integ.time:.9g} (step {st.step}, a shortened last step)")
                res = outcome(False, message, failed=j.at_carrier_end == "fail")
                res.stopped = message
                return res
            st.step += 1
            if st.step == 1:
                sim.count_initial_snap()
            last = t_end - integ.time <= 1e-9 * a.dt
            if st.step % every == 0 or last:
                rec = sim.record_dynamic(st.step, result, h, st.rejected_since_record, joints)
                st.rejected_since_record = 0
                st.records.append(rec)
                last_accepted = None
                if on_step:
                    on_step(rec)
            else:
                last_accepted = (result, h)
            st.dt = min(2 * st.dt, a.dt)
            signum = interrupts.requested()
            if signum:
                return interrupted(signum)
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
        signum = interrupts.requested()
        if signum:
            return interrupted(signum)
    return outcome(True, "completed")
