# SPDX-License-Identifier: MIT
"""Checkpoint and restart of a dynamic run.

A checkpoint (``checkpoint.h5`` in the output folder) holds the integrator's vectors, gathered
to rank 0 and written by h5py as PETSc's HDF5 viewer writes them, read back with the viewer (x: coordinates, sliding coordinates and multipliers; v; a; v_prev and
sliding_rate, the predictor's memory) and, in the group ``slidebeam``, the time, the last step
size, the linear-solver state, the step controller (current dt, counters) and the records so
far (``history``: the table of :mod:`slidebeam.output.history`, exact, with ``history_reasons`` and the
``history_layout``). Restarting from it continues the run as if it had not stopped: the same predictor, the
same step sizes, so the same Newton iterates and the same history (to roundoff). Writing a checkpoint makes the run
that goes on build a fresh Jacobian at its next step, as the restarted one does, so that this
holds with Jacobian reuse too.

The file is written whole (a temporary file, then a rename), so a checkpoint on disk is always
complete. Vectors are loaded by global index, so a run may restart on another number of ranks.
"""
from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import TYPE_CHECKING, Callable

from ..run.parallel import run_comm

if TYPE_CHECKING:  # imported lazily: petsc4py must not be initialised before the CLI passes its options
    from ..run.dynamics import DynamicRecord, RunState
    from ..run.simulation import Simulation

# 3: the records as a table (slidebeam.output.history), a sliding joint's values among the
# effects' outputs; 2: the same with them apart; 1: as JSON (2 and 1 still read, without sliding joints)
FORMAT = 3
VECTORS = ("x", "v", "a", "v_prev", "sliding_rate")


class CheckpointError(Exception):
    """A checkpoint that cannot be used with this scene (or read at all)."""


def _vectors(sim: "Simulation") -> dict:
    integ = sim.integrator
    return {name: getattr(integ, name) for name in VECTORS}


def write_checkpoint(sim: "Simulation", state: "RunState", path: Path,
                     before_commit: Callable[[], None] | None = None) -> None:
    """Write the run's state to path (collective; rank 0 writes the attributes). The file is
    written under a temporary name and renamed at the end; before_commit (collective), if given,
    runs just before the rename, and the rename happens even if it raises."""
    from petsc4py import PETSc

    comm = run_comm()
    integ = sim.integrator
    tmp = path.with_name(f".{path.name}.tmp")
    gathered = {}
    for name, vec in _vectors(sim).items():  # to rank 0, which writes them as PETSc's HDF5 viewer would
        scatter, whole = PETSc.Scatter.toZero(vec)
        scatter.scatter(vec, whole, addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        if comm.Get_rank() == 0:
            gathered[name] = whole.getArray(readonly=True).copy()
        scatter.destroy()
        whole.destroy()
    effect_history = sim.effect_history()  # collective
    if comm.Get_rank() == 0:
        import h5py
        import numpy as np

        from . import history

        with h5py.File(tmp, "w") as f:
            for name, values in gathered.items():
                f.create_dataset(name, data=values)
            f.create_dataset("effect_history", data=np.asarray(effect_history, dtype=float))
            g = f.create_group("slidebeam")
            meta = {
                "format": FORMAT, "scene": sim.scene.name, "unknowns": sim.x.getSize(),
                "t": integ.time, "h_prev": integ.h_prev, "pivoting_lu": bool(integ.pivoting_lu),
                "segment_start": integ.time_segment[0], "segment_steps": integ.time_segment[1],
                "energy_flows": json.dumps([w for _, _, w in integ.energy_flows]),
                "initial_energy": sim.initial_energy,
                "integrator": sim.scene.analysis.integrator,
                "dt": state.dt, "step": state.step, "rejected": state.rejected,
                "rejected_since_record": state.rejected_since_record, "newton": state.newton,
                "wall_time_s": sim.earlier_wall_time + time.perf_counter() - sim.created,
            }
            for key, value in meta.items():
                g.attrs[key] = value
            values, reasons, layout = history.table(state.records, len(integ.energy_flows))
            g.create_dataset("history", data=values)
            g.create_dataset("history_reasons", data=np.array(reasons, dtype=h5py.string_dtype()))
            g.attrs["history_layout"] = json.dumps(layout.as_dict())
            # the scene as run (file + overrides), so that a restart runs the same scene
            g.attrs["scene_file"] = sim.scene.file
            g.attrs["overrides"] = json.dumps(list(sim.scene.overrides))
            g.attrs["scene_data"] = json.dumps(sim.scene.data, default=str)
    try:
        if before_commit is not None:
            before_commit()
    finally:
        if comm.Get_rank() == 0:
            os.replace(tmp, path)
        comm.Barrier()
    # A restart starts with a fresh Jacobian; so does the run that goes on, so that both take the
    # same Newton iterates (with Jacobian reuse, old Jacobians would otherwise make them differ).
    integ.forget_jacobian()


def scene_of_checkpoint(path: Path) -> tuple[list[str], dict] | None:
    """(the --set overrides, the effective scene) of the run that wrote a checkpoint, or None
    if it does not keep them (collective: rank 0 reads)."""
    from mpi4py import MPI

    found = None
    if MPI.COMM_WORLD.Get_rank() == 0:
        try:
            import h5py

            with h5py.File(path, "r") as f:
                g = f.get("slidebeam")
                if g is not None and "overrides" in g.attrs:
                    found = (json.loads(g.attrs["overrides"]), json.loads(g.attrs["scene_data"]))
        except OSError:
            found = None  # read_checkpoint reports an unreadable file
    return MPI.COMM_WORLD.bcast(found, root=0)


def scene_differences(before: dict, after: dict, prefix: str = "") -> list[tuple[str, object, object]]:
    """(dotted key, value before, value after) for every value that differs between two raw
    scenes (keys as --set spells them: beam.0.spans)."""
    out: list[tuple[str, object, object]] = []
    if isinstance(before, dict) and isinstance(after, dict):
        for key in sorted(set(before) | set(after), key=str):
            out += scene_differences(before.get(key), after.get(key), f"{prefix}{key}.")
        return out
    if isinstance(before, list) and isinstance(after, list) and len(before) == len(after) and \
            any(isinstance(v, dict) for v in before + after):
        for i, (a, b) in enumerate(zip(before, after)):
            out += scene_differences(a, b, f"{prefix}{i}.")
        return out
    if json.dumps(before, default=str) != json.dumps(after, default=str):
        out.append((prefix.rstrip("."), before, after))
    return out


def _record(d: dict) -> "DynamicRecord":
    from ..run.dynamics import DynamicRecord, Reaction

    d = dict(d)
    d["linear_momentum"] = tuple(d["linear_momentum"])
    d["angular_momentum"] = tuple(d["angular_momentum"])
    d["tracked"] = [tuple(p) for p in d["tracked"]]
    d["joints"] = []  # the caller makes them from the outputs
    d["reactions"] = [Reaction(r["effect"], tuple(r["force"]), None if r.get("moment") is None else tuple(r["moment"]))
                      for r in d.get("reactions", [])]
    return DynamicRecord(**d)


def read_checkpoint(sim: "Simulation", path: Path) -> "RunState":
    """Load a checkpoint into the simulation's integrator and return the run state to resume
    (collective). Raises CheckpointError if the file does not fit the scene."""
    from petsc4py import PETSc

    if not Path(path).is_file():
        raise CheckpointError(f"checkpoint {path} does not exist")
    meta: dict = {}
    error = None
    if run_comm().Get_rank() == 0:
        try:
            import h5py

            with h5py.File(path, "r") as f:
                if "slidebeam" not in f or any(v not in f for v in VECTORS):
                    raise CheckpointError(f"{path} is not a slidebeam checkpoint")
                meta = {k: (v.item() if hasattr(v, "item") else v) for k, v in f["slidebeam"].attrs.items()}
                if "effect_history" in f:
                    meta["effect_history"] = f["effect_history"][()]
                if "history" in f["slidebeam"]:
                    meta["history"] = f["slidebeam/history"][()]
                    meta["history_reasons"] = [r.decode() for r in f["slidebeam/history_reasons"][()]]
        except CheckpointError as err:
            error = str(err)
        except OSError as err:
            error = f"cannot read checkpoint {path}: {err}"
    error, meta = run_comm().bcast((error, meta), root=0)
    if error:
        raise CheckpointError(error)
    if meta["unknowns"] != sim.x.getSize():
        raise CheckpointError(f"checkpoint {path} holds {meta['unknowns']} unknowns (scene '{meta['scene']}'), "
                              f"this scene has {sim.x.getSize()}: restart with the scene that wrote it")
    if meta["integrator"] != sim.scene.analysis.integrator:
        raise CheckpointError(f"checkpoint {path} was written by the {meta['integrator']} integrator, the scene "
                              f"asks for {sim.scene.analysis.integrator}")
    viewer = PETSc.Viewer().createHDF5(str(path), mode=PETSc.Viewer.Mode.READ, comm=sim.x.getComm())
    for name, vec in _vectors(sim).items():
        vec.setName(name)
        vec.load(viewer)
    viewer.destroy()
    sim.integrator.restore(float(meta["t"]), float(meta["h_prev"]), bool(meta["pivoting_lu"]),
                           float(meta.get("segment_start", meta["t"])), int(meta.get("segment_steps", 0)))
    held = [float(v) for v in meta.get("effect_history", [])]
    if len(held) != len(sim.effect_history()):
        raise CheckpointError(f"checkpoint {path} holds {len(held)} values of the effects' history (friction's "
                              f"anchors), this scene has {len(sim.effect_history())}: restart with the scene that "
                              f"wrote it")
    sim.set_effect_history(held)
    sim.earlier_wall_time = float(meta.get("wall_time_s", 0.0))
    if "energy_flows" in meta:
        sim.integrator.set_energy_flows(json.loads(meta["energy_flows"]))
        sim.initial_energy = float(meta["initial_energy"])
    from ..run.dynamics import RunState

    if "history" in meta:
        from . import history

        records = history.records(meta["history"], meta["history_reasons"],
                                  history.Layout.from_dict(json.loads(meta["history_layout"])))
    else:  # format 1
        records = [_record(r) for r in json.loads(meta["records"])]
    outputs = len(sim.output_labels())
    if any(len(r.outputs) != outputs for r in records):
        raise CheckpointError(f"checkpoint {path} cannot be resumed by this version of slidebeam: its records hold "
                              f"{len(records[0].outputs)} effect outputs, the scene has {outputs} (an earlier "
                              f"version kept the sliding joints' apart); run the scene again from its start")
    for r in records:
        r.joints = sim.joints_of(r.outputs)
    return RunState(records, float(meta["dt"]), int(meta["step"]), int(meta["rejected"]),
                    int(meta["rejected_since_record"]), int(meta["newton"]))
