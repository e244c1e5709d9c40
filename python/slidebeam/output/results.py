# SPDX-License-Identifier: MIT
"""Results on disk, as ``slidebeam run`` writes them: summary.json, history.csv,
final_configuration.csv and the XDMF series beams.xdmf/.h5 (and sliders.xdmf/.h5,
masses.xdmf/.h5).

From a script: :class:`ResultWriter` writes all of them (the XDMF series as the run goes, the rest
at its end), :func:`write_results` the files without the series after a run. Collective: every
rank calls them, rank 0 writes. Files are written whole or not at all (temporary file +
rename)."""
from __future__ import annotations

import csv
import io
import json
import os
import time
from pathlib import Path
from typing import Any

from ..run.dynamics import DynamicRecord, RunOutcome
from ..run.parallel import serial_above_cut
from ..run.simulation import Simulation, StepRecord


def _atomic_write(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def prepare_output_dir(out: Path) -> None:
    """Create the output folder and prove it is writable before any work starts."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".write_test"
        probe.write_text("ok")
        probe.unlink()
    except OSError as err:
        raise OSError(f"output folder {out} is not writable: {err.strerror or err}") from err


def history_csv(sim: Simulation, records: list[StepRecord] | list[DynamicRecord]) -> str:
    """One row per recorded step; then tracked points as <beam>@<s>.x/.y/.z, the reactions of
    supports and rigid joints as <effect>.fx/fy/fz (and .mx/my/mz where they hold a moment), the
    effects' named values (<prefix>.<name>: a sliding joint's s, ds_dt, reaction.x/y/z and gap, a
    contact's force.x/y/z and length), and (dynamic runs) each counted effect's work."""
    buf = io.StringIO()
    w = csv.writer(buf)
    track_cols = []
    for tp in sim.scene.output.track:
        body = sim.scene.body_at(tp.beam)
        name = body.name if body is not None else f"{sim.scene.beams[tp.beam].name}@{tp.at:g}"
        track_cols += [f"{name}.x", f"{name}.y", f"{name}.z"]
    first = records[0].reactions
    reaction_cols = [f"{r.effect}.{c}" for r in first
                     for c in ("fx", "fy", "fz", *(("mx", "my", "mz") if r.moment is not None else ()))]

    output_cols = sim.output_labels()

    def tail(r: StepRecord | DynamicRecord) -> list[str]:
        return [*[repr(v) for p in r.tracked for v in p],
                *[repr(v) for x in r.reactions for v in (*x.force, *(x.moment or ()))],
                *[repr(v) for v in r.outputs]]

    if sim.integrator is not None:
        from .. import _core
        from . import history

        flow_cols = sim.energy_flow_labels()
        w.writerow([*DynamicRecord.header(), *track_cols, *reaction_cols, *output_cols, *flow_cols])
        values, reasons, layout = history.table(records, len(flow_cols))  # type: ignore[arg-type]
        dissipative = [k for k, (_, role, _) in enumerate(sim.integrator.energy_flows) if role == "dissipative"]
        values[:, layout.flow_columns][:, dissipative] *= -1.0  # the dissipated energy, positive
        return buf.getvalue() + _core.csv_rows(values, layout.kinds, reasons)
    w.writerow(["step", "t", "converged", "reason", "newton_iterations", "residual_norm",
                "strain_energy", "potential_energy", *track_cols, *reaction_cols, *output_cols])
    for r in records:
        w.writerow([r.step, repr(r.t), int(r.converged), r.reason, r.newton_iterations, repr(r.residual_norm),
                    repr(r.strain_energy), repr(r.potential_energy), *tail(r)])
    return buf.getvalue()


def configuration_csv(sim: Simulation) -> str:
    """The final state sampled along every beam (output.samples_per_span points per span): centre
    line, directors, strains (minus the reference's), the spatial force and moment resultants
    and the tension, as the element has them."""
    buf = io.StringIO()
    w = csv.writer(buf)
    strain_cols = ["eps_axial", "eps_shear2", "eps_shear3", "kappa_torsion", "kappa2", "kappa3"]
    w.writerow(["beam", "s", "x", "y", "z", "d1x", "d1y", "d1z", "d2x", "d2y", "d2z", "d3x", "d3y", "d3z",
                *strain_cols, "fx", "fy", "fz", "mx", "my", "mz", "tension"])
    for b in sim.scene.beams:
        f = sim.sample_beam(b.index)
        for i, si in enumerate(f["s"]):
            row = [*f["position"][i], *f["d1"][i], *f["d2"][i], *f["d3"][i], *f["strain"][i], *f["force"][i],
                   *f["moment"][i], f["tension"][i]]
            w.writerow([b.name, repr(float(si)), *[repr(float(v)) for v in row]])
    return buf.getvalue()


def end_positions(sim: Simulation) -> dict[str, dict[str, list[float]]]:
    out = {}
    for b in sim.scene.beams:
        q = sim.evaluate(b.index, [0.0, b.geometry.length])
        out[b.name] = {"start": q[0, :3].tolist(), "end": q[1, :3].tolist()}
    return out


def body_states(sim: Simulation) -> dict[str, dict[str, list[float]]]:
    """Each rigid body's centre of mass and axes in the current state (collective)."""
    out = {}
    for b in sim.scene.bodies:
        q = sim.control_points(b.index)[0]
        out[b.name] = {"position": q[:3].tolist(), "d1": q[3:6].tolist(), "d2": q[6:9].tolist(), "d3": q[9:12].tolist()}
    return out


def _final_positions(sim: Simulation) -> dict[str, Any]:
    """The summary's final state: beam ends, and bodies (scenes with [[body]])."""
    final: dict[str, Any] = {"final_end_positions": end_positions(sim)}
    if sim.scene.bodies:
        final["final_bodies"] = body_states(sim)
    return final


def write_files(sim: Simulation, out: Path, records: list[StepRecord] | list[DynamicRecord], summary: dict[str, Any],
                rank: int) -> None:
    """history.csv, final_configuration.csv and summary.json (with the final end positions
    added). Collective (evaluation gathers), rank 0 writes. The summary is written last, so a
    summary marked complete is never beside partial files."""
    history = history_csv(sim, records)
    config = configuration_csv(sim)
    summary = {**summary, **_final_positions(sim)}
    if rank != 0:
        return
    _atomic_write(out / "history.csv", history)
    _atomic_write(out / "final_configuration.csv", config)
    _atomic_write(out / "summary.json", json.dumps(summary, indent=2) + "\n")


def _scene_file(sim: Simulation) -> str:
    f = sim.scene.file
    return f if not f or f.startswith("<") else os.path.abspath(f)


def static_summary(sim: Simulation, records: list[StepRecord], wall_time: float | None = None,
                   max_cuts: int = 8) -> dict[str, Any]:
    """summary.json of a static run (the records of ``solve_static``): whether it is complete
    and converged, a message, steps, Newton iterations, final energies, reactions, the effects'
    outputs (a sliding joint's s, reaction and gap). Collective."""
    scene = sim.scene
    last = records[-1]
    complete = sim.stopped is None and last.converged and last.t >= scene.analysis.t_end * (1 - 1e-12)
    newton_failed = sim.stopped is None and not last.converged
    if complete:
        message = "converged"
    elif not newton_failed:
        message = f"{sim.stopped}; results are marked incomplete"
    else:
        message = (f"Newton failed at load step {last.step} (t = {last.t:.6g}, after halving the increment "
                   f"{max_cuts} times): {last.reason}, residual norm {last.residual_norm:.3e}; results hold the last "
                   f"converged state and are marked incomplete")
    good = [r for r in records if r.converged]
    summary: dict[str, Any] = {
        "scene": scene.name, "scene_file": _scene_file(sim),
        "analysis": scene.analysis.type, "complete": complete, "converged": not newton_failed, "message": message,
        "stopped": sim.stopped,
        "active_effects": [e.label for e in sim.active_effects],
        "steps": good[-1].step, "steps_requested": scene.analysis.steps,
        "newton_iterations": sum(r.newton_iterations for r in records),
        "newton_iterations_per_step": [r.newton_iterations for r in records[1:]],
        "load_step_cuts": sim.load_step_cuts,
        "load_step_continuations": sim.load_step_continuations,
        "unknowns": sim.x.getSize(), "ranks": sim.x.getComm().getSize(), "wall_time_s": wall_time,
        "final_energy": {"strain": good[-1].strain_energy, "potential": good[-1].potential_energy},
        "reactions": [r.as_dict() for r in good[-1].reactions],
    }
    if good[-1].outputs:
        summary["outputs"] = output_summary(sim, good[-1].outputs)
    return summary


def output_summary(sim: Simulation, values: list[float]) -> dict[str, dict[str, float]]:
    """summary.json's `outputs`: per effect (its label) the last value of each of its outputs (the
    history's columns <label>.<name>)."""
    out: dict[str, dict[str, float]] = {}
    k = 0
    for label, names in sim.output_groups().items():
        out[label] = dict(zip(names, values[k:k + len(names)]))
        k += len(names)
    return out


def dynamic_summary(sim: Simulation, outcome: RunOutcome, wall_time: float | None = None,
                    initial_velocity: bool = True) -> dict[str, Any]:
    """summary.json of a dynamic run (the outcome of ``run_dynamic``): completeness, message,
    steps, rejected steps, Newton iterations, final energies, the largest constraint residual,
    the static start and the initial velocities' projection (``initial_velocity``: not for a
    restart), reactions and the effects' outputs (their last values, by history column: a sliding
    joint's s, ds_dt, reaction and gap). Collective."""
    scene, a = sim.scene, sim.scene.analysis
    recs = outcome.records
    last = recs[-1] if recs[-1].converged or len(recs) == 1 else recs[-2]
    newton_failed = outcome.failed and outcome.stopped is None
    summary: dict[str, Any] = {
        "scene": scene.name, "scene_file": _scene_file(sim), "analysis": "dynamic",
        "integrator": a.integrator, "complete": outcome.complete, "converged": not newton_failed,
        "message": outcome.message, "stopped": outcome.stopped, "active_effects": [e.label for e in sim.active_effects],
        "t_end": a.t_end, "t_reached": sim.t, "dt": a.dt, "dt_min": a.dt_min,
        "steps": outcome.steps, "rejected_steps": outcome.rejected_steps,
        "newton_iterations": outcome.newton_iterations,
        "jacobian_evaluations": int(sim.integrator.jacobian_evaluations),
        "unknowns": sim.x.getSize(), "ranks": sim.x.getComm().getSize(),
        # a restarted run's history took the earlier runs' time too
        "wall_time_s": None if wall_time is None else sim.earlier_wall_time + wall_time,
        "final_energy": {"kinetic": last.kinetic_energy, "strain": last.strain_energy,
                         "potential": last.potential_energy, "total": last.total_energy},
        "max_constraint_residual": max(r.constraint_residual for r in recs),
        "pivoting_lu": bool(sim.integrator.pivoting_lu) or sim.integrator.pivoting_lu_steps > 0,
        "pivoting_lu_steps": int(sim.integrator.pivoting_lu_steps),
        "warnings": list(sim.warnings),  # what the start found and corrected or left to the first step
    }
    if sim.earlier_wall_time > 0.0:
        summary["wall_time_this_run_s"] = wall_time
    if sim.settled is not None:
        summary["static_start"] = static_start_summary(sim)
    p = sim.velocity_projection
    if p is not None and initial_velocity:
        summary["initial_velocity"] = {
            "projected": p["projected"], "failed": p["failed"],
            "relative_change": p["change"] / p["size"] if p["size"] > 0 else 0.0,
            "largest_change": p["largest"], "kinetic_energy_given": p["kinetic_before"],
            "kinetic_energy": p["kinetic_after"]}
    summary["reactions"] = [r.as_dict() for r in last.reactions]
    if last.outputs:
        summary["outputs"] = output_summary(sim, last.outputs)
    if sim.x.getComm().getSize() > 1:
        summary["parallel"] = parallel_summary(sim)
    return summary


def static_start_summary(sim: Simulation) -> dict[str, Any]:
    """summary.json's account of a simulation's static start (settled)."""
    s = sim.settled
    assert s is not None
    return {"continuation_steps": s.pseudo_steps, "block_steps": s.block_steps,
            "full_system_steps": s.full_system_steps, "cut_steps": s.cut_steps, "polished": s.polished,
            "newton_iterations": s.newton_iterations, "residual_initial": s.residual0, "residual": s.residual,
            "wall_time_s": sim.settle_wall_time}


def parallel_summary(sim: Simulation) -> dict[str, Any]:
    """How a dynamic run on several ranks shared and solved its unknowns: unknowns per rank, the
    most rows of a rank coupled to another rank, how many step Jacobians were solved by one block
    application (ranks not coupled), one application plus the coupling correction (exact) and
    GMRES, whether the steps fell back to the pivoting LU, and where the static start ran.
    Collective."""
    solves = dict(sim.integrator.parallel_solves)
    return {
        "unknowns_per_rank": sim.x.getComm().tompi4py().allgather(sim.x.getLocalSize()),
        "cut_points": sim.cut_points,
        "coupled_rows": solves.pop("coupled_rows"),
        "jacobians_solved_by": {"one block application": solves["blocks"],
                                "block application and coupling correction": solves["corrected"],
                                "GMRES": solves["krylov"]},
        "pivoting_lu": bool(sim.integrator.pivoting_lu),
        "static_start": None if sim.settled is None else (
            "rank 0 alone" if sim.settled_on_rank_0 else
            f"all ranks ({sim.settled.block_steps} of {sim.settled.pseudo_steps} continuation steps on the block solve)"),
    }


def parallel_line(summary: dict[str, Any]) -> str:
    """One line on how the ranks shared and solved the run (summary["parallel"])."""
    p = summary["parallel"]
    sizes = p["unknowns_per_rank"]
    if sum(1 for n in sizes if n) == 1 and p.get("cut_points", 0) > 0:
        return (f"{len(sizes)} ranks: rank 0 owns all {sum(sizes)} unknowns, since a split would leave a rank "
                f"{p['cut_points']} control points next to another rank's (above -sb_serial_above_cut "
                f"{serial_above_cut()}: the coupling correction's set-up would cost more than the split saves)")
    solved = ", ".join(f"{n} by {how}" for how, n in p["jacobians_solved_by"].items() if n)
    line = (f"{len(sizes)} ranks: {min(sizes)}-{max(sizes)} unknowns each, coupled through up to "
            f"{p['coupled_rows']} rows of a rank; step Jacobians solved {solved or 'by the pivoting LU'}")
    if p["pivoting_lu"]:
        line += "; the steps fell back to the pivoting LU (MUMPS)"
    if p["static_start"]:
        line += f"; static start on {p['static_start']}"
    return line


def _records_and_summary(sim: Simulation, result, wall_time: float | None) -> tuple[list, dict[str, Any]]:
    if isinstance(result, RunOutcome):
        return result.records, dynamic_summary(sim, result, wall_time)
    records = list(result)
    if not records:
        raise ValueError("no records to write")
    if isinstance(records[0], DynamicRecord):  # records without their outcome: summarised from the records
        last = records[-1]
        complete = last.converged and last.t >= sim.scene.analysis.t_end * (1 - 1e-12)
        outcome = RunOutcome(records, complete, "completed" if complete else "stopped before t_end",
                             steps=last.step, rejected_steps=sum(r.rejected_steps for r in records),
                             newton_iterations=sum(r.newton_iterations for r in records))
        return records, dynamic_summary(sim, outcome, wall_time)
    return records, static_summary(sim, records, wall_time)


def _rank(sim: Simulation) -> int:
    return sim.x.getComm().getRank()


def _prepare(sim: Simulation, folder: Path) -> None:
    prepare_output_dir_on(sim.x.getComm().tompi4py(), folder)


def prepare_output_dir_on(comm, folder: Path) -> None:
    """Create the folder on rank 0 of comm (an mpi4py communicator); raise OSError on every rank
    if it is not writable (collective)."""
    error = None
    if comm.Get_rank() == 0:
        try:
            prepare_output_dir(folder)
        except OSError as err:
            error = str(err)
    error = comm.bcast(error, root=0)
    if error:
        raise OSError(error)


def write_results(sim: Simulation, result, folder: str | Path, wall_time: float | None = None) -> dict[str, Any]:
    """Write history.csv, final_configuration.csv and summary.json of a run into `folder` (made
    if needed), as ``slidebeam run`` does: `result` is what the run returned, the records of
    ``solve_static`` (or a script's own :meth:`Simulation.record` list) or the
    :class:`~slidebeam.run.dynamics.RunOutcome` of ``run_dynamic``. The final configuration is the
    current state. The XDMF series needs the states as they pass: use :class:`ResultWriter` for it.
    Returns the summary. Collective: every rank calls it, rank 0 writes."""
    folder = Path(folder)
    _prepare(sim, folder)
    records, summary = _records_and_summary(sim, result, wall_time)
    write_files(sim, folder, records, summary, _rank(sim))
    return {**summary, **_final_positions(sim)}


class ResultWriter:
    """Everything ``slidebeam run`` writes, from a script: the XDMF series (beams.xdmf/.h5 and,
    with sliding joints, sliders.xdmf/.h5, with point masses, masses.xdmf/.h5, with rigid bodies,
    bodies.xdmf/.h5, and view.py, the
    ParaView script that shows them; unless the scene says ``[output] xdmf = false``)
    recorded as the run goes, then history.csv, final_configuration.csv and summary.json.

    Create it before the run (a static scene's current state is written as the first
    record), pass :meth:`record` as the run's ``on_step`` (or call :meth:`write` after each of
    a script's own steps), and call :meth:`finish` with the run's result. As a context
    manager it closes the series if the run raises. Collective: every rank makes the same
    calls, rank 0 writes.

    Args:
        sim: the simulation whose run is written.
        folder: the output folder (made if needed).
        xdmf: write the XDMF series (default: the scene's ``output.xdmf``).
    """

    def __init__(self, sim: Simulation, folder: str | Path, xdmf: bool | None = None) -> None:
        from .xdmf import NoOutput, XdmfOutput

        self.sim = sim
        self.folder = Path(folder)
        self._t0 = time.perf_counter()
        _prepare(sim, self.folder)
        use_xdmf = sim.scene.output.xdmf if xdmf is None else xdmf
        self._series = XdmfOutput(sim, self.folder, _rank(sim)) if use_xdmf else NoOutput()
        if sim.integrator is None:
            self._series.write(sim.t)  # the reference state: step 0 of the history

    def write(self) -> None:
        """Add the current state to the XDMF series at the current time."""
        self._series.write(self.sim.t)

    def record(self, record: StepRecord | DynamicRecord) -> None:
        """``on_step`` of ``solve_static`` and ``run_dynamic``: the state of every converged
        record goes into the XDMF series."""
        if record.converged:
            self._series.write(record.t, record.joints, record.outputs)

    def close(self) -> None:
        """Write what the series holds and close its files (also done by finish)."""
        self._series.close()

    def finish(self, result) -> dict[str, Any]:
        """Close the series and write history.csv, final_configuration.csv and summary.json of
        `result` (as :func:`write_results`); returns the summary."""
        self.close()
        return write_results(self.sim, result, self.folder, wall_time=time.perf_counter() - self._t0)

    def __enter__(self) -> "ResultWriter":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
