# SPDX-License-Identifier: MIT
"""XDMF/HDF5 time series for ParaView, written with meshio.

Files in the output folder (names are stable):

- ``beams.xdmf`` + ``beams.h5``: every beam's centre line as a polyline through
  ``output.samples_per_span`` points per knot span (line cells), at the reference positions,
  with point data per recorded step: ``displacement`` (current minus reference position: ParaView's
  Warp By Vector moves the mesh), ``velocity``, ``d1``, ``d2``, ``d3``, ``strain`` (6: axial,
  shear 2, shear 3, torsion, bending about d2, about d3; minus the reference strains),
  ``force`` and ``moment`` (spatial stress resultants, the element's own), ``tension`` (the axial
  force, a scalar to colour by), ``section_d2``, ``section_d3`` (d2 and d3
  times the half extent of the section along them, sqrt(3 EI3/EA) and sqrt(3 EI2/EA): exact for
  a rectangle, from which a Ribbon or Tube filter draws the section), ``s`` (arc length) and
  ``beam_id``.
- ``sliders.xdmf`` + ``sliders.h5`` (scenes with sliding joints): one vertex per joint at the
  slider's start position, with ``displacement``, ``s``, ``ds_dt``, ``reaction`` (force of the
  carrier on the slider) and ``joint_id``.

meshio's ``TimeSeriesWriter`` opens the ``.h5`` in the current directory; ``_Series`` puts it
beside its ``.xdmf`` instead. meshio also writes the mesh as a grid of its own beside the temporal
collection and XIncludes it into every step: ParaView's legacy ``XDMFReader`` then shows that
reference grid as a second copy of everything, frozen at the first record (issue 22). ``_Series``
writes no such grid: every step's grid names the same reference ``Geometry`` and ``Topology``
datasets itself, which all three ParaView readers and meshio's ``TimeSeriesReader`` understand. The XDMF text is written at every ``flush`` by a temporary file and a
rename, so the ``.xdmf`` on disk always describes complete steps (every ``FLUSH_EVERY`` records, at checkpoints and at the end). Sampling is collective;
rank 0 writes.
"""
from __future__ import annotations

import contextlib
import copy
import os
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .simulation import Simulation

BEAMS = "beams"
SLIDERS = "sliders"
_ABANDONED: list = []  # writers whose files failed (see XdmfOutput._abandon)
_XINCLUDE = "{http://www.w3.org/2003/XInclude}include"  # as meshio writes it
FLUSH_EVERY = 100  # records between rewrites of the .xdmf text (and at the end, and checkpoints)


class OutputFailure(Exception):
    """Writing results failed (full disk, removed folder, ...)."""


def _first_line(err: Exception) -> str:
    """HDF5's messages run over several lines with buffer addresses: keep the gist."""
    full = str(err).strip()
    text = full.splitlines()[0].split(" (file write failed")[0] if full else type(err).__name__
    cause = re.search(r"error message = '([^']+)'", full)
    return f"{text} ({cause.group(1)})" if cause else text


@contextlib.contextmanager
def _h5py_stderr_silenced():
    """Once a write has failed (full disk), h5py's object destructors print a traceback for every
    temporary they free, straight to the C stderr. The failure itself arrives as an exception
    and becomes one clear message, so stderr is closed over h5py calls."""
    sys.stderr.flush()
    saved = os.dup(2)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 2)
        yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)


def _series_class():
    from meshio.xdmf.time_series import TimeSeriesWriter, write_xml

    class _Series(TimeSeriesWriter):
        """meshio's writer with the .h5 beside the .xdmf, an XDMF text that can be rewritten at any
        time, and continuation of an existing series (restart)."""

        def __init__(self, filename: Path, resume_after: float | None = None) -> None:
            super().__init__(filename)
            self.h5_filename = str(Path(filename).with_suffix(".h5"))
            self._resume_after = resume_after

        def __enter__(self):
            import h5py

            if self._resume_after is not None and self.filename.is_file() and Path(self.h5_filename).is_file():
                self._resume(h5py)
            else:
                self.h5_file = h5py.File(self.h5_filename, "w")
            return self

        def _resume(self, h5py) -> None:
            """Continue the series: keep the steps up to the restart time, append after them."""
            tree = ET.parse(self.filename)
            self.xdmf_file = tree.getroot()
            self.domain = self.xdmf_file.find("Domain")
            self.collection = self.domain.find("Grid[@CollectionType='Temporal']")
            for grid in list(self.collection):
                time = grid.find("Time")
                if time is not None and float(time.get("Value")) > self._resume_after * (1 + 1e-12) + 1e-300:
                    self.collection.remove(grid)
            self._adopt_mesh()
            self.h5_file = h5py.File(self.h5_filename, "a")
            used = [int(m.group(1)) for k in self.h5_file.keys() if (m := re.fullmatch(r"data(\d+)", k))]
            self.data_counter = max(used, default=-1) + 1

        def _adopt_mesh(self) -> None:
            """On resume: take the reference Geometry and Topology from the file. A series written
            before issue 22 keeps them in a separate ``mesh`` grid that every step XIncludes:
            that grid is dropped and the steps get their own copies, so the continued file has one
            structure throughout."""
            mesh = next((g for g in self.domain.findall("Grid") if g.get("GridType") == "Uniform"), None)
            if mesh is not None:
                self.domain.remove(mesh)
            else:
                mesh = next((g for g in self.collection if g.find("Geometry") is not None), None)
            if mesh is None:  # no step left to take it from: the caller writes it anew
                self.has_mesh = False
                return
            self._mesh_items = [mesh.find("Topology"), mesh.find("Geometry")]
            for grid in self.collection:
                self._own_mesh(grid)
            self.has_mesh = True

        def write_points_cells(self, points, cells) -> None:
            # meshio's helpers fill a detached grid: only copies of its children enter the file
            mesh = ET.Element("Grid")
            self.points(mesh, np.asarray(points))
            self.cells(cells, mesh)
            topo = mesh.find("Topology")
            # XDMF 3 (ParaView's Xdmf3 readers) requires NodesPerElement on Polyline and
            # Polyvertex topologies; meshio leaves it out
            kind = topo.get("TopologyType")
            if kind in ("Polyline", "Polyvertex") and topo.get("NodesPerElement") is None:
                topo.set("NodesPerElement", "2" if kind == "Polyline" else "1")
            self._mesh_items = [topo, mesh.find("Geometry")]
            self.has_mesh = True

        def write_data(self, t, point_data=None, cell_data=None) -> None:
            super().write_data(t, point_data, cell_data)
            self._own_mesh(self.collection[-1])

        def _own_mesh(self, grid: ET.Element) -> None:
            """Replace meshio's XInclude of the mesh grid by the reference Topology and Geometry
            (the same datasets in every step). GridType is explicit because meshio's reader
            looks for a grid marked Uniform to read the points and cells from."""
            include = grid.find(_XINCLUDE)
            if include is not None:
                grid.remove(include)
            if grid.find("Geometry") is None:
                for k, item in enumerate(self._mesh_items):
                    grid.insert(k, copy.deepcopy(item))
            grid.set("GridType", "Uniform")

        def flush(self) -> None:
            # data first: the .xdmf may only name datasets that are on disk
            self.h5_file.flush()
            tmp = self.filename.with_name(f".{self.filename.name}.tmp")
            write_xml(tmp, self.xdmf_file)
            os.replace(tmp, self.filename)

        def __exit__(self, *_):
            self.flush()
            self.h5_file.close()

    return _Series


class NoOutput:
    """Stands in for XdmfOutput when the scene says [output] xdmf = false."""

    def write(self, t: float) -> None:
        pass

    def flush(self) -> None:
        pass

    def close(self) -> None:
        pass


def bytes_per_record(scene) -> int:
    """Disk space one recorded step takes (data and XDMF text), for the check at start."""
    if not scene.output.xdmf:
        return 0
    n = sum(b.spans * scene.output.samples_per_span + 1 for b in scene.beams)
    values = n * (3 * 10 + 6 + 1) + n // 2 + len(scene.sliding_joints) * 8
    return 8 * values + 4500  # XDMF text: ~4.4 kB a record, each naming the reference mesh too


class XdmfOutput:
    """The beams (and sliders) time series of one run. All ranks call ``write`` and ``close``."""

    def __init__(self, sim: "Simulation", out: Path, rank: int, resume_after: float | None = None) -> None:
        self.sim = sim
        self.rank = rank
        self.k = sim.scene.output.samples_per_span
        self.closed = False
        self.writes = 0
        ref, self._slider_ref = self._reference_positions()
        self._ref_points = ref
        self._series: list = []
        if rank != 0:
            return
        Series = _series_class()
        try:
            beams = Series(out / f"{BEAMS}.xdmf", resume_after).__enter__()
            self._series.append(beams)
            if not (resume_after is not None and beams.has_mesh):
                beams.write_points_cells(ref, [("line", self._lines())])
            if sim.scene.sliding_joints:
                sliders = Series(out / f"{SLIDERS}.xdmf", resume_after).__enter__()
                self._series.append(sliders)
                if not (resume_after is not None and sliders.has_mesh):
                    n = len(self._slider_ref)
                    sliders.write_points_cells(self._slider_ref, [("vertex", np.arange(n).reshape(n, 1))])
        except OSError as err:
            raise OutputFailure(f"cannot write the XDMF output in {out}: {err}") from err

    # -- sampling (collective) -------------------------------------------------------------
    def _sample(self, beam: int, x, v) -> dict[str, np.ndarray]:
        return self.sim._model.sample_beam(beam, x, v, self.k)

    def _reference_positions(self) -> tuple[np.ndarray, np.ndarray]:
        """Sample points of the beams and slider points in the reference configuration (the
        mesh; displacements are measured from it, also after a restart)."""
        sim = self.sim
        ref = sim._model.x.duplicate()
        sim._model.set_reference_state(ref)
        points = np.concatenate([self._sample(b.index, ref, None)["position"] for b in sim.scene.beams])
        sliders = np.array([sim.evaluate(j.slider, j.at, ref)[0, :3] for j in sim.scene.sliding_joints])
        ref.destroy()
        return points, sliders.reshape(-1, 3)

    def _lines(self) -> np.ndarray:
        cells, first = [], 0
        for b in self.sim.scene.beams:
            n = b.spans * self.k + 1
            cells.append(np.column_stack([np.arange(first, first + n - 1), np.arange(first + 1, first + n)]))
            first += n
        return np.concatenate(cells)

    def fields(self) -> dict[str, np.ndarray]:
        """Point data of the current state (collective): what ``write`` stores."""
        sim = self.sim
        v = sim.v
        parts = [self._sample(b.index, sim.x, v) for b in sim.scene.beams]
        data = {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}
        data["displacement"] = data.pop("position") - self._ref_points
        half2, half3 = [], []
        for b, p in zip(sim.scene.beams, parts):
            sec = b.section
            n = len(p["s"])
            half2.append(np.full((n, 1), np.sqrt(3.0 * sec.EI3 / sec.EA)))
            half3.append(np.full((n, 1), np.sqrt(3.0 * sec.EI2 / sec.EA)))
        data["section_d2"] = data["d2"] * np.concatenate(half2)
        data["section_d3"] = data["d3"] * np.concatenate(half3)
        data["beam_id"] = np.concatenate([np.full(len(p["s"]), b.index, dtype=np.int32)
                                          for b, p in zip(sim.scene.beams, parts)])
        return data

    def slider_fields(self) -> dict[str, np.ndarray]:
        sim = self.sim
        joints = sim.joint_states()
        pos = np.array([sim.evaluate(j.slider, j.at)[0, :3] for j in sim.scene.sliding_joints])
        return {
            "displacement": pos - self._slider_ref,
            "s": np.array([j.s for j in joints]),
            "ds_dt": np.array([j.ds_dt for j in joints]),
            "reaction": np.array([j.reaction for j in joints]),
            "joint_id": np.arange(len(joints), dtype=np.int32),
        }

    # -- writing ---------------------------------------------------------------------------
    def write(self, t: float) -> None:
        """Append the current state at time t (collective)."""
        from .costs import output_phase

        with output_phase():
            self._write(t)

    def _write(self, t: float) -> None:
        beams = self.fields()
        sliders = self.slider_fields() if self.sim.scene.sliding_joints else None
        error = None
        if self.rank == 0:
            try:
                with _h5py_stderr_silenced():
                    self._series[0].write_data(t, point_data=beams)
                    if sliders is not None:
                        self._series[1].write_data(t, point_data=sliders)
            except Exception as err:  # h5py reports a full disk as OSError, RuntimeError or ValueError
                self._abandon()
                error = f"writing the XDMF output at t = {t:.6g} failed: {_first_line(err)}"
        self._raise_on_any_rank(error)
        self.writes += 1
        if self.writes % FLUSH_EVERY == 0:
            self.flush()

    def _raise_on_any_rank(self, error: str | None) -> None:
        """Only rank 0 writes, but every rank must stop: share its verdict."""
        from mpi4py import MPI

        comm = MPI.COMM_WORLD
        if comm.Get_size() > 1:
            error = comm.bcast(error, root=0)
        if error:
            self.closed = True
            raise OutputFailure(error)

    def _abandon(self) -> None:
        """After a failed write: touch the files no more (the .xdmf on disk keeps describing the
        steps of the last flush). HDF5 crashes when a file whose write failed is closed or its
        objects are freed, so they are kept alive until the process ends (the CLI then leaves
        without the interpreter's teardown)."""
        self.closed = True
        _ABANDONED.extend(self._series)
        self._series = []

    def flush(self) -> None:
        """Make the files on disk describe every step written so far (collective)."""
        error = None
        try:
            with _h5py_stderr_silenced():
                for s in self._series:
                    s.flush()
        except Exception as err:  # noqa: BLE001 - see write
            self._abandon()
            error = f"writing the XDMF output failed: {_first_line(err)}"
        self._raise_on_any_rank(error)

    def close(self) -> None:
        """Write the .xdmf files and close the .h5 files (collective)."""
        if self.closed:
            return
        self.closed = True
        errors = []
        for s in self._series:
            try:
                with _h5py_stderr_silenced():
                    s.__exit__(None, None, None)
            except Exception as err:  # noqa: BLE001 - see write
                errors.append(_first_line(err))
        self._series = []
        self._raise_on_any_rank("closing the XDMF output failed: " + "; ".join(errors) if errors else None)
