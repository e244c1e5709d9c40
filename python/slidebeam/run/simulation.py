# SPDX-License-Identifier: MIT
"""A scene turned into a running model: the Python face of the C++ core.

The state, residual, Jacobian and SNES are the very PETSc objects the core uses (petsc4py
handles, no copies): scripts may read or modify them, or drive SNES themselves.
"""
from __future__ import annotations

import collections

import contextlib
import dataclasses
import time
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator, NamedTuple

import numpy as np
from petsc4py import PETSc

from .. import _core
from . import interrupts
from .dynamics import (DynamicRecord, JointState, Reaction, RunOutcome, RunState,
                       initial_velocity, run_dynamic)
from .model import EffectInfo, build_model
from .options_check import apply_scene_options
from .parallel import equilibrium_on_rank_0, statics_on_rank_0, wait_sleeping
from ..scene.parse import Scene, SceneError


class ConstraintWarning(UserWarning):
    """A scene's initial state violated its constraints and was corrected."""


class EquilibriumFailure(RuntimeError):
    """The static start of a dynamic run found no equilibrium."""


@dataclass(frozen=True)
class EquilibriumOutcome:
    """How the static start of a dynamic run ended (``Simulation.settled``)."""

    converged: bool
    pseudo_steps: int  # continuation steps
    block_steps: int  # ... solved on the parallel block path (a distributed static start)
    full_system_steps: int  # ... that needed the pivoting LU of the whole saddle-point system
    cut_steps: int  # continuation steps that failed and were retried with half the pseudo-step
    newton_iterations: int
    residual0: float  # |F| at the start
    residual: float  # |F| at the end
    polished: bool  # a final Newton solve without continuation closed it
    at_roundoff: bool  # stopped at the residual's roundoff floor
    interrupted: int  # the signal that stopped it, or 0

    @classmethod
    def of(cls, result: "_core.EquilibriumResult") -> "EquilibriumOutcome":
        return cls(*(getattr(result, f.name) for f in dataclasses.fields(cls)))


class BeamPoint(NamedTuple):
    """A point of a beam (:meth:`Simulation.point`): the centre line position phi and the
    directors d1, d2, d3, each an array of 3. ANCF cables have no directors: d1 is the tangent
    r' = dr/ds (not of unit length), d2 and d3 are None."""

    phi: np.ndarray
    d1: np.ndarray
    d2: np.ndarray | None
    d3: np.ndarray | None


@dataclass
class StepRecord:
    """One load step (static) as it goes to history.csv: ``Simulation.solve_static`` returns a
    list of them, step 0 being the state before the first step. ``tracked`` holds the
    ``[output] track`` points (x, y, z), ``joints`` every sliding joint, ``reactions`` every
    support and rigid joint, ``outputs`` the effects' named values (:meth:`Simulation.output_labels`)."""

    step: int
    t: float
    converged: bool
    reason: str
    newton_iterations: int
    residual_norm: float
    strain_energy: float
    potential_energy: float
    tracked: list[tuple[float, float, float]] = field(default_factory=list)
    joints: list[JointState] = field(default_factory=list)
    reactions: list[Reaction] = field(default_factory=list)
    outputs: list[float] = field(default_factory=list)


@contextlib.contextmanager
def _options_as(options: dict[str, str | None]) -> Iterator[None]:
    """The PETSc options database holds exactly `options` for the block, then what it held."""
    db = PETSc.Options()
    before = db.getAll()

    def hold(wanted: dict[str, str | None]) -> None:
        for name in db.getAll():
            if name not in wanted:
                db.delValue(name)
        for name, value in wanted.items():
            db.setValue(name, value)

    hold(options)
    try:
        yield
    finally:
        hold(before)


# what solve_static leaves on the simulation besides its state
_STATIC_OUTCOME = ("t", "load_step_cuts", "load_step_continuations", "stopped", "stop_signal", "stop_is_failure")


@dataclass(frozen=True)
class ContinuedSolve:
    """A load step that Newton's first attempt did not solve: the iterations of every attempt
    (Newton, the continuation, Newton's fall-backs), the final residual, whether it converged
    and by what."""
    iterations: int
    residual_norm: float
    converged: bool = True
    reason_name: str = "CONVERGED_BY_CONTINUATION"  # or the fall-backs' reason


class Simulation:
    """Model + solver of a scene: build it, then solve (``solve_static``, ``solve_step``,
    ``run_dynamic``) and look at the state (``point``, ``evaluate``, ``energies``,
    ``sample_beam``, ``joint_states``, ``reactions``). Collective: under MPI every rank makes
    the same calls. The scene's ``[petsc]`` options go into the PETSc options database first;
    options already there (the command line's) win.

    Args:
        scene: a validated scene (``load_scene`` or ``scene_from_dict``).
        comm: an mpi4py communicator (default: PETSc's world communicator).

    Attributes:
        scene: the scene.
        integrator: the C++ ``TimeIntegrator`` of a dynamic scene (None in statics).
        settled: the result of the static start (``settle``), once done.
        stopped: why the last ``solve_static`` ended early without failing (None otherwise).
        warnings: what the start found and corrected (initial velocities), and a static start
            that could not run on rank 0 alone.
        use_predictor: ``solve_static`` starts each load step from the secant predictor.
    """

    def __init__(self, scene: Scene, comm: object | None = None) -> None:
        self.scene = scene
        apply_scene_options(scene)
        # the options the model is built with: a serial copy on rank 0 (_alone_on_rank_0) is
        # built with them too, whatever the database holds by then
        self._options: dict[str, str | None] = PETSc.Options().getAll()
        self._statics_on_rank_0_option = statics_on_rank_0()
        self._equilibrium_on_rank_0_option = equilibrium_on_rank_0()
        self._model, self.effects = build_model(scene, comm)
        self._output_groups: dict[str, list[str]] | None = None
        self._output_slices: dict[int, slice] = {}  # effect index -> its values in effect_outputs()
        self._solver = _core.StaticSolver(self._model)
        self._t = 0.0
        self.use_predictor = True
        self.integrator: _core.TimeIntegrator | None = None
        self.settled: EquilibriumOutcome | None = None  # the static start, once done (settle)
        self.settled_on_rank_0 = False  # ... solved by rank 0 alone (-sb_equilibrium_on_rank_0)
        self.settle_wall_time = 0.0  # ... its wall time, seconds
        # wall time of the runs before this one that made its history (a restart's checkpoint),
        # and when this one began: a checkpoint records their sum
        self.earlier_wall_time = 0.0
        self.snap_pending = False  # sliders start off their carriers: count the first step's pull
        self.initial_snap_energy = 0.0  # ... the energy it put in (count_initial_snap)
        self.created = time.perf_counter()
        self.step_wall_times: list[float] = []  # seconds per attempted time step (run_dynamic)
        self.stopped: str | None = None  # why the last solve_static ended early without failing
        self.load_step_cuts = 0  # load steps of the last solve_static that failed and were halved
        self.load_step_continuations = 0  # ... that Newton did not solve and the continuation took on
        self.stop_signal: int | None = None  # the signal that stopped it, if one did
        self.stop_is_failure = False  # a slider left its carrier with at_carrier_end = "fail"
        self.initial_energy = 0.0  # H_0 of the energy balance (the first record of a dynamic run)
        self.warnings: list[str] = []  # what the start found and corrected (initial velocities)
        # the initial velocities' projection onto the constraints (TimeIntegrator.velocity_projection)
        self.velocity_projection: dict | None = None
        a = scene.analysis
        if a.type == "dynamic":
            self.integrator = _core.TimeIntegrator(self._model, a.integrator, beta=a.newmark_beta,
                                                   gamma=a.newmark_gamma,
                                                   alpha=a.hht_alpha if a.integrator == "hht" else 0.0,
                                                   dissipation=a.em_dissipation)
            self._start_motion()

    def _start_motion(self) -> None:
        """Start the integrator at the current state with the scene's initial velocities,
        projected onto the constraints (see TimeIntegrator.initialize); warn if they violated
        them."""
        v = self._model.x.duplicate()
        initial_velocity(self, v)
        self.integrator.initialize(0.0, self._model.x, v)
        v.destroy()
        p = self.integrator.velocity_projection
        self.velocity_projection = p if p["solved"] else None
        message = None
        if p["failed"]:
            message = ("the initial velocities could not be checked against the constraints (the constrained "
                       "mass system is singular): they are used as given, sliding rates 0")
        elif p["projected"]:
            rel = p["change"] / p["size"]
            message = (f"the initial velocities violate the constraints (supports, joints, sliders on their carriers): "
                       f"projected onto them with the mass metric, a change of {rel:.3g} of their mass norm "
                       f"(largest change of a coordinate's rate {p['largest']:.3g}); kinetic energy "
                       f"{p['kinetic_before']:.6g} -> {p['kinetic_after']:.6g}")
        if message and message not in self.warnings:
            self.warnings.append(message)
            warnings.warn(message, ConstraintWarning, stacklevel=3)
        # an equilibrium start closes the gaps before the balance begins: the state to check is its
        if self.scene.analysis.start != "equilibrium" or self.settled is not None:
            self._warn_of_initial_gaps()

    def _warn_of_initial_gaps(self) -> None:
        """Warn where a slider starts off its carrier (within the joint's tolerance, or the model
        would not have been built): the first step pulls it on, and the work that takes is no
        effect's, so it shows in energy_balance_error. Gaps at roundoff of the coordinates pass."""
        gaps = [j.gap for j in self.joints_of(list(self._model.effect_outputs(self.t, self.x)))]
        if not gaps:
            return
        extent = max(float(np.abs(self.control_points(b.name)[:, :3]).max()) for b in self.scene.beams)
        roundoff = 1e-12 * max(1.0, extent)
        off = sum(g > roundoff for g in gaps)
        if off == 0:
            return
        k = int(np.argmax(gaps))
        message = (f"{off} of {len(gaps)} sliding joint(s) start off their carriers, by up to {gaps[k]:.3g} m "
                   f"([[sliding_joint]] #{k + 1}): the first step pulls the sliders on")
        if message not in self.warnings:
            self.warnings.append(message)
            warnings.warn(message, ConstraintWarning, stacklevel=4)
        self.snap_pending = True

    def count_initial_snap(self) -> None:
        """After the first step of a start with sliders off their carriers (_warn_of_initial_gaps):
        the energy the step's pull put in is no effect's work, so it is the step's balance error
        (under energy-momentum nothing else is). Say how much, and start the balance from after
        it (initial_energy), so that energy_balance_error measures the run, not the drawing.
        Collective."""
        if not self.snap_pending:
            return
        self.snap_pending = False
        assert self.integrator is not None
        e = self._potential_energies()
        kinetic, _, _ = self.integrator.motion()
        work, dissipated = self._work_and_dissipation()
        self.initial_snap_energy = kinetic + e["strain"] + e["potential"] - self.initial_energy - work + dissipated
        self.initial_energy += self.initial_snap_energy
        message = (f"the first step's pull of the sliders onto their carriers changed the energy by "
                   f"{self.initial_snap_energy:.3g} J: the energy balance counts from after it")
        self.warnings.append(message)
        warnings.warn(message, ConstraintWarning, stacklevel=3)

    def settle(self) -> EquilibriumOutcome:
        """Start a dynamic run from static equilibrium: solve for the equilibrium under the loads
        at t = 0 (pseudo-transient continuation, robust for mechanisms and slack cables), with
        each slider held or free as its scene says, then restart the integrator there at rest
        (plus the scene's initial velocities). Raises EquilibriumFailure if no equilibrium is
        reached; the state is then the last one of the continuation.

        On several ranks it runs on all ranks: its continuation steps on the time steps' block
        solve (``settled.block_steps`` counts them; a plain Newton polish, where a stalled
        continuation needs one, on MUMPS). With -sb_equilibrium_on_rank_0, rank 0 solves it
        alone with the serial solver, on a model of its own, bit for bit the serial run's, and
        hands the state to every rank."""
        assert self.integrator is not None, "settle() starts dynamic runs"
        started = time.perf_counter()
        self.settled_on_rank_0 = self._distributed_and(self._equilibrium_on_rank_0_option)
        result = self._settle_alone() if self.settled_on_rank_0 else None
        if result is None:  # one rank, the option off, or rank 0 cannot hold the whole model
            self.settled_on_rank_0 = False
            result = self._settle_with(self._model)
        self.settled = result
        self.settle_wall_time = time.perf_counter() - started
        if not result.converged:
            raise EquilibriumFailure(
                f"the static start found no equilibrium: residual {result.residual:.3e} (from {result.residual0:.3e}) "
                f"after {result.pseudo_steps} continuation steps and {result.newton_iterations} Newton iterations")
        self._start_motion()
        return result

    def _settle_with(self, model: "_core.Model") -> EquilibriumOutcome:
        """The static start on a model (this simulation's, or rank 0's serial copy of it)."""
        solver = _core.EquilibriumSolver(model)
        held = list(model.held_at_start())  # the effects say which unknowns stay and which stay bounded
        solver.set_held(held)
        solver.set_bounds(*model.unknown_bounds(held))
        return EquilibriumOutcome.of(solver.solve(0.0, self.scene.analysis.dt))

    def _distributed_and(self, option: bool) -> bool:
        """True if the model is distributed over several ranks and option (-sb_statics_on_rank_0
        or -sb_equilibrium_on_rank_0 as it was when the simulation was built) holds
        (collective)."""
        comm = self._model.x.getComm().tompi4py()
        if comm.Get_size() == 1 or not option:
            return False
        return comm.allreduce(1 if self._model.x.getLocalSize() > 0 else 0) > 1

    def _settle_alone(self) -> EquilibriumOutcome | None:
        """The static start solved on rank 0 by a serial model of the same scene (see
        _alone_on_rank_0); None if rank 0 cannot hold the model."""
        from mpi4py import MPI

        def serial_model():
            model, _ = build_model(self.scene, MPI.COMM_SELF)
            return model, model.x

        return self._alone_on_rank_0("the static start", serial_model, self._settle_with)

    def _solve_static_alone(self, on_step: Callable[[StepRecord], None] | None,
                            max_cuts: int) -> list[StepRecord] | None:
        """solve_static on rank 0 by a serial simulation of the same scene (see
        _alone_on_rank_0), its outcome then this simulation's; None if rank 0 cannot hold the
        model. on_step is called on rank 0 as the load steps are taken, on the other ranks with
        the same records once they are all taken."""
        from mpi4py import MPI

        def serial_simulation():
            sim = Simulation(self.scene, MPI.COMM_SELF)
            return sim, sim.x

        def solve(sim: Simulation):
            sim.t, sim.use_predictor = self.t, self.use_predictor
            records = sim.solve_static(on_step, max_cuts)
            return records, {name: getattr(sim, name) for name in _STATIC_OUTCOME}

        outcome = self._alone_on_rank_0("the static solve", serial_simulation, solve)
        if outcome is None:
            return None
        records, state = outcome
        for name, value in state.items():
            setattr(self, name, value)
        if on_step and self._model.x.getComm().tompi4py().Get_rank() != 0:
            for rec in records[1:]:
                on_step(rec)
        return records

    def _alone_on_rank_0(self, what: str, build: Callable[[], tuple[Any, PETSc.Vec]],
                         work: Callable[[Any], Any]) -> Any:
        """work(serial) on rank 0 alone, where build() gives a serial copy of this model (the
        numbering depends on the scene alone, so the unknowns are the same) and its state
        vector, set from this model's state; the other ranks sleep meanwhile (rather than poll
        MPI, which would keep their cores busy). The serial state and work's result (which
        must pickle) then go to every rank (collective). None, with a warning, if rank 0's node
        has not the memory for the whole model: the caller solves it distributed."""
        comm = self._model.x.getComm().tompi4py()
        x = self._model.x
        scatter, whole = PETSc.Scatter.toZero(x)
        scatter.scatter(x, whole, addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        outcome: Any = None
        failure: str | None = None
        error: Exception | None = None
        too_big: str | None = None
        try:
            if comm.Get_rank() == 0:
                serial = None
                try:
                    with _options_as(self._options):
                        serial, serial_x = build()
                except SceneError as exc:  # not on one node: distributed after all
                    too_big = str(exc)
                if serial is not None:
                    try:
                        serial_x.setArray(whole.getArray(readonly=True))
                        outcome = work(serial)
                        whole.setArray(serial_x.getArray(readonly=True))
                    except Exception as exc:  # the other ranks must learn of it, not wait forever
                        error, failure, outcome = exc, f"{type(exc).__name__}: {exc}", None
                comm.Ibarrier().Wait()
            else:
                wait_sleeping(comm)
            outcome, failure, too_big = comm.bcast((outcome, failure, too_big), root=0)
            if error is not None:
                raise error
            if too_big is not None:
                self.warnings.append(f"{what} runs on all ranks: rank 0 alone cannot hold the model ({too_big})")
                return None
            if failure is not None:
                raise RuntimeError(f"{what} failed on rank 0: {failure}")
            scatter.scatter(whole, x, addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.REVERSE)
        finally:
            scatter.destroy()
            whole.destroy()
        return outcome

    @property
    def t(self) -> float:
        """Current (pseudo-)time."""
        return self.integrator.time if self.integrator is not None else self._t

    @t.setter
    def t(self, value: float) -> None:
        if self.integrator is not None:
            raise AttributeError("the time of a dynamic simulation advances only by stepping")
        self._t = value

    # -- PETSc objects shared with the core ------------------------------------------------
    @property
    def x(self) -> PETSc.Vec:
        """Global unknowns: per control point phi, d1, d2, d3, then 6 multipliers; then extras.
        In a dynamic simulation, the integrator's state at the current time."""
        return self.integrator.x if self.integrator is not None else self._model.x

    @property
    def v(self) -> PETSc.Vec | None:
        """Velocity (dynamic simulations; zero at multipliers)."""
        return self.integrator.v if self.integrator is not None else None

    @property
    def snes(self) -> PETSc.SNES:
        """The SNES of the solves: the load steps' (options prefix ``sb_static_``), or in a
        dynamic simulation the time steps' (``sb_ts_``); petsc4py, shared with the core."""
        return self.integrator.snes if self.integrator is not None else self._solver.snes

    @property
    def jacobian(self) -> PETSc.Mat:
        """The Jacobian the SNES of :attr:`snes` assembles (the step Jacobian when dynamic)."""
        return self.integrator.jacobian if self.integrator is not None else self._model.jacobian

    @property
    def residual_vector(self) -> PETSc.Vec:
        """The vector the residuals are assembled into (shared with the core; the SNES of
        :attr:`snes` evaluates into it too)."""
        return self._model.residual_vector

    @property
    def prescribed_rows(self) -> list[int]:
        """Global indices of unknowns fixed by supports, owned by this rank."""
        return list(self._model.prescribed_rows)

    @property
    def active_effects(self) -> list[EffectInfo]:
        """Every effect of the model (supports, loads, joints, gravity, ...) in model order,
        each with its ``type`` and ``label`` (as in history.csv's column names)."""
        return list(self.effects)

    # -- evaluation ------------------------------------------------------------------------
    def static_residual(self, t: float | None = None, x: PETSc.Vec | None = None) -> PETSc.Vec:
        """The residual of static equilibrium F(x; t): internal minus external forces and the
        constraints (no inertia), at the current time and state unless t or x are given,
        assembled into :attr:`residual_vector` and returned (collective). Zero at a converged
        load step; in a dynamic scene it is the out-of-balance force, not the time step's
        residual (see :meth:`step_residual`)."""
        self._model.assemble_residual(self.t if t is None else t, x or self.x, self.residual_vector)
        return self.residual_vector

    def residual(self, t: float | None = None, x: PETSc.Vec | None = None) -> PETSc.Vec:
        """The static residual F(x; t): the same as :meth:`static_residual`, in static and
        dynamic scenes alike."""
        return self.static_residual(t, x)

    def step_residual(self) -> PETSc.Vec:
        """The residual of the last time step at the current state (dynamic scenes): what that
        step's Newton solve drove to zero, inertia included, so that its norm is the step's
        ``residual_norm``. Assembled into :attr:`residual_vector` and returned (collective).
        Raises RuntimeError before the first step (or after a restart) and ValueError in a
        static scene."""
        if self.integrator is None:
            raise ValueError("step_residual() needs a dynamic scene; the static residual is static_residual()")
        self.integrator.last_step_residual(self.residual_vector)
        return self.residual_vector

    def assemble_jacobian(self, t: float | None = None, x: PETSc.Vec | None = None) -> PETSc.Mat:
        """Assemble the static J(x; t) into the model's own matrix and return it."""
        self._model.assemble_jacobian(self.t if t is None else t, x or self.x, self._model.jacobian)
        return self._model.jacobian

    def energies(self) -> dict[str, float]:
        """The energies of the current state in J (collective): ``strain`` (the beams),
        ``potential`` (conservative external loads, gravity; each effect's part as its registry
        spec says), ``kinetic`` (dynamic scenes: 1/2 v^T M v; 0 in statics) and ``total``, their
        sum: the H of the energy balance in history.csv."""
        e = self._potential_energies()
        kinetic = self.integrator.kinetic_energy() if self.integrator is not None else 0.0
        return {**e, "kinetic": kinetic, "total": e["strain"] + e["potential"] + kinetic}

    def _potential_energies(self) -> dict[str, float]:
        """Strain and potential energy (see energies)."""
        from ..scene.effect_tables import effect_specs

        specs = effect_specs()
        e = self._model.effect_energies(self.t, self.x)
        kind = [specs[info.type].stored if info.type in specs else "" for info in self.effects]
        return {"strain": sum(v for k, v in zip(kind, e) if k == "strain"),
                "potential": sum(v for k, v in zip(kind, e) if k == "potential")}

    def control_points(self, beam: int | str, x: PETSc.Vec | None = None) -> np.ndarray:
        """(n_cp, 12) coordinates phi, d1, d2, d3 of a beam's control points (ANCF cable: (n_nodes,
        6), r and r') in the current state, or in x (collective)."""
        return self._model.beam_coordinates(self._beam(beam), self.x if x is None else x)

    def point(self, beam: int | str, s: float, x: PETSc.Vec | None = None) -> BeamPoint:
        """The position and directors of a beam at arc length s (m, from its start), in the
        current state or in x, as a :class:`BeamPoint` (phi, d1, d2, d3) (collective)."""
        q = self.evaluate(beam, float(s), x)[0]
        if q.shape[0] == 6:  # ANCF cable: r, r'
            return BeamPoint(q[:3].copy(), q[3:].copy(), None, None)
        return BeamPoint(q[:3].copy(), q[3:6].copy(), q[6:9].copy(), q[9:].copy())

    def evaluate(self, beam: int | str, s: np.ndarray | float, x: PETSc.Vec | None = None) -> np.ndarray:
        """The interpolated coordinates at arc lengths s (a number or a sequence, m from the
        beam's start), in the current state or in x (collective): an array with one row per arc
        length, always 2-D, so a single s gives shape (1, 12). Columns 0-2: the centre line phi,
        3-5: d1, 6-8: d2, 9-11: d3. ANCF cables: (len(s), 6), columns 0-2 the position r, 3-5
        the tangent r'. For one point with named fields see :meth:`point`."""
        b = self._beam(beam)
        q = self.control_points(b, x)
        spec = self.scene.beams[b]
        s_arr = np.atleast_1d(np.asarray(s, dtype=float))
        if spec.formulation == "ancf":
            le = spec.geometry.length / spec.spans
            out = np.zeros((len(s_arr), 6))
            for i, si in enumerate(s_arr):
                e = min(max(int(np.floor(si / le)), 0), spec.spans - 1)
                S, dS, _ = _core.hermite_basis(min(max(si - e * le, 0.0), le), le)
                blocks = [q[e, :3], q[e, 3:], q[e + 1, :3], q[e + 1, 3:]]  # the Hermite basis order
                out[i, :3] = sum(w * y for w, y in zip(S, blocks))
                out[i, 3:] = sum(w * y for w, y in zip(dS, blocks))
            return out
        out = np.zeros((len(s_arr), 12))
        for i, si in enumerate(s_arr):
            span, N, _, _ = _core.bspline_basis(spec.spans, min(max(si / spec.geometry.length, 0.0), 1.0))
            out[i] = np.asarray(N) @ q[span : span + 3]
        return out

    def centreline(self, beam: int | str, samples_per_span: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Arc lengths and (phi, d1, d2, d3) sampled along a beam."""
        b = self._beam(beam)
        spec = self.scene.beams[b]
        k = samples_per_span or self.scene.output.samples_per_span
        s = np.linspace(0.0, spec.geometry.length, spec.spans * k + 1)
        return s, self.evaluate(b, s)

    def sample_beam(self, beam: int | str, samples_per_span: int | None = None) -> dict[str, np.ndarray]:
        """Fields along a beam at samples_per_span points per span (and its end), in the current
        state (collective): s, position, velocity, d1, d2, d3 (n x 3 each), strain (n x 6: axial,
        shear 2, shear 3, torsion, bending about d2, about d3, minus the reference strains), force
        and moment (spatial stress resultants, n x 3) and tension (the axial force, n). The
        resultants are the element's own: with assumed strains, the knots' membrane and shear
        strains interpolated."""
        k = samples_per_span or self.scene.output.samples_per_span
        return dict(self._model.sample_beam(self._beam(beam), self.x, self.v, k))

    # -- solving ---------------------------------------------------------------------------
    def solve_step(self, t: float, attempts: str = "all") -> _core.SolveResult:
        """Newton solve of the static equilibrium at (pseudo-)time t from the current state
        (loads scale with t as the scene's time functions say; t = 1 is the full load unless
        ``analysis.t_end`` says otherwise). The state is left at the solution, or at the last
        iterate if the solve failed (see ``result.converged``). ``attempts``: "all", "first"
        (Newton on the director manifold alone) or "fallbacks" (what follows it on the whole
        system)."""
        self.t = t
        return self._solver.solve(t, attempts)

    def record(self, step: int, result: _core.SolveResult | ContinuedSolve | None) -> StepRecord:
        """The history record of the current state as load step `step` solved with `result`
        (None: the initial state), e.g. to collect the records of a script's own load steps
        for :func:`slidebeam.write_results`."""
        e = self._potential_energies()
        tracked = self.tracked_points()
        outputs = self.effect_outputs()
        return StepRecord(
            step=step, t=self.t,
            converged=True if result is None else bool(result.converged),
            reason="initial" if result is None else result.reason_name,
            newton_iterations=0 if result is None else result.iterations,
            residual_norm=0.0 if result is None else result.residual_norm,
            strain_energy=e["strain"], potential_energy=e["potential"], tracked=tracked,
            joints=self.joints_of(outputs), reactions=self.reactions(), outputs=outputs,
        )

    def solve_static(self, on_step: Callable[[StepRecord], None] | None = None,
                     max_cuts: int = 8) -> list[StepRecord]:
        """Load stepping to t_end in ``analysis.steps`` equal increments. Returns the history:
        one :class:`StepRecord` per load step, the initial state first; ``on_step`` is called
        with each as it is taken.

        The steps are the core's LoadStepper's (src/time/load_stepper.hpp): each starts from a
        secant predictor (the last two converged states extrapolated, linearly but for the
        director triads, which turn on by their last rotation), then Newton on the director
        manifold, the pseudo-transient continuation where that fails, Newton's fall-backs last.
        A step that fails is retried from the last converged state in halves, down to
        1/2**max_cuts of the increment; if that fails too, the state is left at the last
        converged one and the failed attempt is the last record. A slider solved beyond its
        carrier's end stops the run at the last load step.

        On several ranks (-sb_statics_on_rank_0, the default) rank 0 solves it alone with the
        serial solver, on a simulation of its own, and hands the records and the state to every
        rank (the distributed static solve, MUMPS on the whole system, costs 2-4 times the
        serial one). ``on_step`` then runs on rank 0 as the steps are taken and on the other
        ranks once they are all taken: it must not call collective operations of this
        simulation (set the option false for that).
        """
        if self._distributed_and(self._statics_on_rank_0_option):
            records = self._solve_static_alone(on_step, max_cuts)
            if records is not None:
                return records
        a = self.scene.analysis
        records = [self.record(0, None)]
        stepper = _core.LoadStepper(self._model, self._solver, a.t_end, a.steps, max_cuts)
        stepper.set_predictor(self.use_predictor)
        stepper.set_continuation_bounds(*self._model.unknown_bounds())
        step = 0
        while not stepper.done:
            adv = stepper.advance()
            self.load_step_cuts, self.load_step_continuations = stepper.cuts, stepper.continuations
            result = ContinuedSolve(adv.result.iterations, adv.result.residual_norm) if adv.by_continuation else (
                ContinuedSolve(adv.result.iterations, adv.result.residual_norm, adv.result.converged,
                               adv.result.reason_name)
                if adv.continued else adv.result)
            if adv.status == "event":  # back at the last load step, inside every indicator
                self.t = stepper.time
                self.stopped = self._model.event_message(
                    adv.event, adv.event_index, adv.event_value,
                    f"in load step {step + 1} (t = {adv.t:.6g}); results hold load step {step} (t = {stepper.time:.6g})")
                self.stop_is_failure = self._model.event_fails_run(adv.event, adv.event_index)
                break
            if adv.status == "accepted":
                self.t = adv.t
                step += 1
                rec = self.record(step, result)
                records.append(rec)
                if on_step:
                    on_step(rec)
                signum = interrupts.requested()
                if signum:
                    self.stop_signal = signum
                    self.stopped = (f"interrupted by {interrupts.describe(signum)} after load step {step} "
                                    f"(t = {stepper.time:.6g})")
                    break
                continue
            if adv.status == "failed":  # the last converged state, recorded at the failed step's time
                self.t = adv.t
                fail = self.record(step + 1, result)
                self.t = stepper.time
                records.append(fail)
                if on_step:
                    on_step(fail)
                break
        return records

    def first_control_point(self, beam: int | str) -> int:
        """Global index of a beam's first control point."""
        return self._model.beam_first_cp(self._beam(beam))

    def control_point_unknowns(self, cp: int) -> tuple[int, int]:
        """(global index of the first unknown, number of coordinates) of control point cp: its
        coordinates are the unknowns first .. first + count - 1 (multipliers follow). IndexError
        for a point the model does not have."""
        return tuple(self._model.cp_unknowns(cp))

    def output_labels(self) -> list[str]:
        """History column names of the effects' named values: <effect label>.<name> (a contact's
        force.x/y/z and length in contact, buoyancy's force and submerged length)."""
        return [f"{label}.{name}" for label, names in self.output_groups().items() for name in names]

    def output_groups(self) -> dict[str, list[str]]:
        """The effects that have outputs, by the prefix the history gives their columns: the
        effect's own (OutputSource::output_prefix, a sliding joint's <slider>_on_<carrier>,
        numbered _1, _2, ... where several share it) or its label (#2 a second entry): the names
        of their values, in the order of effect_outputs()."""
        if self._output_groups is None:
            names = list(self._model.output_names())
            effects = list(dict.fromkeys(k for k, _ in names))
            prefix = {k: self._model.output_prefix(k) or self.active_effects[k].label for k in effects}
            shared = collections.Counter(prefix.values())
            seen: collections.Counter[str] = collections.Counter()
            for k in effects:
                if shared[prefix[k]] > 1:
                    seen[prefix[k]] += 1
                    prefix[k] = f"{prefix[k]}_{seen[prefix[k]]}"
            self._output_groups, self._output_slices, first = {}, {}, 0
            for k in effects:
                group = [name for e, name in names if e == k]
                self._output_groups[prefix[k]] = group
                self._output_slices[k] = slice(first, first + len(group))
                first += len(group)
        return self._output_groups

    def output_slice(self, effect: int) -> slice:
        """Where the values of effect number ``effect`` (in active_effects) lie in
        effect_outputs() and in a record's ``outputs``."""
        self.output_groups()
        return self._output_slices[effect]

    def effect_history(self) -> list[float]:
        """What effects keep from one step to the next besides the unknowns (where friction holds
        each point of a beam on a contact), whole on every rank (collective): a checkpoint's."""
        return list(self._model.effect_history())

    def set_effect_history(self, values: list[float]) -> None:
        """Replace the effects' history with values from :meth:`effect_history`."""
        self._model.set_effect_history([float(v) for v in values])

    def effect_outputs(self) -> list[float]:
        """The values named by :meth:`output_labels` in the current state (collective): in a
        dynamic run over the last step (rates and a joint's force over it), else at the state."""
        if not self.output_groups():
            return []
        if self.integrator is not None:
            return list(self.integrator.effect_outputs())
        return list(self._model.effect_outputs(self.t, self.x))

    def tracked_points(self) -> list[tuple[float, float, float]]:
        """Positions (x, y, z) of the scene's ``[output] track`` points in the current state."""
        # a body is tracked at its centre of mass
        return [tuple(float(v) for v in (self.evaluate(tp.beam, tp.at)[0, :3] if self.scene.body_at(tp.beam) is None
                                         else self.control_points(tp.beam)[0, :3]))
                for tp in self.scene.output.track]

    def elimination_order(self) -> list[int]:
        """Permutation of the unknowns (new position -> old index) the serial factorisation uses:
        sliders before carriers, multipliers next to the coordinates they constrain, the points of
        beams joined into loops (a net) in minimum-degree order."""
        return list(self._model.elimination_order())

    @property
    def cut_points(self) -> int:
        """The most control points a rank holds next to another rank's in the split of the
        model over all ranks (0: owned by one rank from the start, -sb_serial_below). Above
        -sb_serial_above_cut rank 0 owns the model alone."""
        return int(self._model.cut_points)

    def sliding_joint_effects(self) -> list[int]:
        """Model effect index of every [[sliding_joint]], in scene order."""
        return [i for i, e in enumerate(self.active_effects) if e.type == "sliding_joint"]

    def sliding_coordinate_index(self, joint: int = 0) -> int:
        """Global index of the sliding coordinate s of [[sliding_joint]] number `joint` (its three
        multipliers come just before it)."""
        return self._model.extra_offset(self.sliding_joint_effects()[joint]) + 3

    def joint_states(self) -> list[JointState]:
        """s, ds/dt, reaction and gap (the slider point's distance from the carrier's centre line,
        the joint's constraint residual) of every sliding joint in the current state, from the
        joints' outputs (collective; statics: ds/dt = 0). ds/dt is the mean rate over the last
        time step, the reaction the force of the carrier on the slider in the global frame over
        it (the step's mean force under the midpoint-type schemes); before a step, at the state."""
        return self.joints_of(self.effect_outputs())

    def joints_of(self, outputs: list[float]) -> list[JointState]:
        """The sliding joints' states in a record's outputs (s, ds_dt, reaction.x/y/z, gap)."""
        self.output_groups()
        states = []
        for k in self.sliding_joint_effects():
            s, rate, fx, fy, fz, gap = (float(v) for v in outputs[self._output_slices[k]])
            states.append(JointState(s, rate, (fx, fy, fz), gap))
        return states

    def reactions(self, over_last_step: bool = False) -> list[Reaction]:
        """What every support and rigid joint exerts on the structure (collective): in
        equilibrium at the current state, or (over_last_step, dynamic scenes) over the last time
        step, inertia included."""
        if over_last_step and self.integrator is not None:
            raw = self.integrator.reactions()
        else:
            raw = self._model.static_reactions(self.t, self.x)
        return [Reaction(self.active_effects[k].label, tuple(f), None if m is None else tuple(m)) for k, f, m in raw]

    def record_dynamic(self, step: int, result: _core.SolveResult | None, dt: float,
                       rejected: int) -> DynamicRecord:
        """Energies, momenta, constraint residual, tracked points, sliding joints and the effects'
        outputs of the current state."""
        assert self.integrator is not None
        e = self._potential_energies()
        kinetic, lin, ang = self.integrator.motion()
        flows = self.integrator.energy_flows
        work, dissipated = self._work_and_dissipation()
        total = kinetic + e["strain"] + e["potential"]
        if step == 0 and result is None:
            self.initial_energy = total
        outputs = self.effect_outputs()
        return DynamicRecord(
            step=step, t=self.t, dt=dt,
            converged=True if result is None else bool(result.converged),
            reason="initial" if result is None else result.reason_name,
            newton_iterations=0 if result is None else result.iterations,
            residual_norm=0.0 if result is None else result.residual_norm,
            kinetic_energy=kinetic, strain_energy=e["strain"],
            potential_energy=e["potential"], linear_momentum=tuple(lin), angular_momentum=tuple(ang),
            constraint_residual=self.integrator.constraint_residual(), rejected_steps=rejected,
            tracked=self.tracked_points(), joints=self.joints_of(outputs),
            reactions=self.reactions(over_last_step=result is not None and bool(result.converged)),
            outputs=outputs, work=work, dissipated=dissipated,
            energy_balance_error=abs(total - self.initial_energy - work + dissipated),
            flows=[w for _, _, w in flows],
        )

    def _work_and_dissipation(self) -> tuple[float, float]:
        """W and D of the energy balance so far: the counted effects' work, dissipative effects'
        (their work negated) apart."""
        assert self.integrator is not None
        flows = self.integrator.energy_flows
        work = sum(w for _, role, w in flows if role != "dissipative")
        dissipated = 0.0 - sum(w for _, role, w in flows if role == "dissipative")
        return work, dissipated

    def energy_flow_labels(self) -> list[str]:
        """History column names of the effects whose work is counted (dynamic runs):
        <label>.work, or <label>.dissipated for damping and friction (then positive)."""
        if self.integrator is None:
            return []
        return [f"{self.active_effects[k].label}.{'dissipated' if role == 'dissipative' else 'work'}"
                for k, role, _ in self.integrator.energy_flows]

    def run_dynamic(self, on_step: Callable[[DynamicRecord], None] | None = None, state: RunState | None = None,
                    on_checkpoint: Callable[[RunState], None] | None = None) -> RunOutcome:
        """Integrate a dynamic scene to ``analysis.t_end`` with step control (see
        :func:`slidebeam.run.dynamics.run_dynamic`), first settling into equilibrium if the scene says
        ``analysis.start = "equilibrium"``. Returns a :class:`~slidebeam.run.dynamics.RunOutcome`: its
        ``records`` are the history (one :class:`~slidebeam.run.dynamics.DynamicRecord` every
        ``output.every`` steps and at the end), ``complete`` says whether t_end was reached and
        ``message`` why not. ``on_step`` is called with every record as it is taken; ``state``
        (from :func:`slidebeam.output.checkpoint.read_checkpoint`) resumes a run."""
        if self.integrator is None:
            raise ValueError("run_dynamic needs [analysis] type = \"dynamic\"")
        if state is None and self.scene.analysis.start == "equilibrium" and self.settled is None:
            self.settle()
        return run_dynamic(self, on_step, state, on_checkpoint)

    def _beam(self, beam: int | str) -> int:
        return self.scene.beam_index(beam) if isinstance(beam, str) else int(beam)
