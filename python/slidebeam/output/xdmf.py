# SPDX-License-Identifier: MIT
"""XDMF/HDF5 time series for ParaView (and meshio).

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
  ``beam_id``. ``/mesh`` has the attribute ``beam_names`` (in ``beam_id`` order).
- ``guides.xdmf`` + ``guides.h5`` (scenes with guides): one vertex per guide at its drawn point,
  with ``displacement`` (a guide on a body moves), ``s`` and ``ds_dt`` (the rope's arc length at
  the guide, its rate), ``reaction`` (the force of the rope on the guide) and ``guide_id``;
  ``/mesh`` has the attribute ``guide_names``.
- ``sliders.xdmf`` + ``sliders.h5`` (scenes with sliding joints): one vertex per joint at the
  slider's start position, with ``displacement``, ``s``, ``ds_dt``, ``reaction`` (force of the
  carrier on the slider) and ``joint_id``; ``/mesh`` has the attribute ``joint_names`` (the
  history's column prefixes, <slider>_on_<carrier>).
- ``masses.xdmf`` + ``masses.h5`` (scenes with point masses): one vertex per point mass at its
  reference position, with ``displacement``, ``velocity``, ``mass`` and ``mass_id``; ``/mesh``
  has the attribute ``mass_names`` (the effects' labels, as summary.json's ``active_effects``:
  ``point_mass[hanger@end]``).
- ``bodies.xdmf`` + ``bodies.h5`` (scenes with rigid bodies): one vertex per body at its centre
  of mass in the drawing, with ``displacement``, ``velocity``, its axes ``d1``, ``d2``, ``d3``
  (for glyphs), ``mass`` and ``body_id``; ``/mesh`` has the attribute ``body_names``.
- ``view.py``: a ParaView script that opens the series (:mod:`slidebeam.output.paraview_script`).

In the ``.h5``: ``/mesh/points``, ``/mesh/cells`` and the fields that never change (``s``,
``beam_id``, ``joint_id``, ``mass``, ``mass_id``) under ``/mesh``, written once; every other field one dataset per
record, ``/<field>/<record>``. Every step's grid names the reference mesh itself (issue 22:
a separate mesh grid showed twice in ParaView's legacy reader) and its datasets by plain HDF
DataItems. Not one extendable dataset per field read through hyperslabs: meshio's
``TimeSeriesReader`` reads no hyperslabs, ParaView 5.11's Xdmf3 readers skip them and its legacy
reader reads them in single precision; one dataset per record is what all of them read.

Sampling is collective; rank 0 writes. Its ``slidebeam._core.RecordWriter`` (one per series) takes
a copy of each record and writes it on a thread of its own: creating the HDF5 objects of a record
costs more than a small scene's time step. Every ``FLUSH_EVERY`` records (or ``PENDING_BYTES`` of
data), the writer flushes the ``.h5`` and then appends the new steps to the ``.xdmf``, over its
closing tags in one write, so the ``.xdmf`` on disk always describes complete steps whose data is
on disk. At checkpoints and at the end the run waits for the writers; at a checkpoint each
series also moves on to a new data file (``beams.1.h5``, ...: see :class:`Series`).
"""
from __future__ import annotations

import copy
import glob
import os
import re
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..run.parallel import run_comm

if TYPE_CHECKING:
    from ..run.dynamics import JointState
    from ..run.simulation import Simulation

BEAMS = "beams"
SLIDERS = "sliders"
GUIDES = "guides"
MASSES = "masses"
BODIES = "bodies"
FLOATS_PER_BODY = 15  # displacement, velocity, d1, d2, d3
VIEW_SCRIPT = "view.py"
_XINCLUDE = "{http://www.w3.org/2003/XInclude}include"  # as meshio wrote it (series before issue 22)
FLUSH_EVERY = 100  # records between writes of the data and the .xdmf text (and at checkpoints, the end)
PENDING_BYTES = 16 << 20  # ... or sooner, so that records waiting to be written stay below twice this
COMPACT_BYTES = 32 << 10  # datasets up to this size live in their object header: one write each
_HEAD = (b'<?xml version="1.0"?>\n<Xdmf Version="3.0"><Domain>'
         b'<Grid Name="TimeSeries" GridType="Collection" CollectionType="Temporal">')
_TAIL = b"</Grid></Domain></Xdmf>\n"
_ATTRIBUTE_TYPE = {1: "Scalar", 3: "Vector", 6: "Tensor6"}
_RECORD_PATH = re.compile(r":/[^/<]+/(\d+)<")  # ...h5:/<field>/<record>< in a step's DataItems
_RECORD_FILE = re.compile(r">([^<>:]+):/[^/<]+/\d+<")  # >file.h5:/<field>/<record>< : the record's file


class OutputFailure(Exception):
    """Writing results failed (full disk, removed folder, ...)."""


def _first_line(err: Exception) -> str:
    """HDF5's messages run over several lines with buffer addresses: keep the gist."""
    full = str(err).strip()
    text = full.splitlines()[0].split(" (file write failed")[0] if full else type(err).__name__
    cause = re.search(r"error message = '([^']+)'", full)
    return f"{text} ({cause.group(1)})" if cause else text


def _read_document(xdmf: Path) -> ET.Element:
    """The .xdmf's XML. A run killed in the middle of appending steps may leave the last ones
    cut short: the document then ends after the last complete step."""
    text = xdmf.read_bytes()
    try:
        return ET.fromstring(text)
    except ET.ParseError:
        end = len(text)
        for _ in range(3):  # the cut may fall in a step or in the closing tags after it
            end = text.rfind(b"</Grid>", 0, end)
            if end < 0:
                break
            try:
                return ET.fromstring(text[:end + len(b"</Grid>")] + _TAIL)
            except ET.ParseError:
                continue
        raise


def _data_item(h5_name: str, path: str, shape: tuple[int, ...], dtype: np.dtype) -> str:
    kind = "Int" if dtype.kind in "iu" else "Float"
    dims = " ".join(str(d) for d in shape)
    return (f'<DataItem DataType="{kind}" Dimensions="{dims}" Format="HDF" Precision="{dtype.itemsize}">'
            f"{h5_name}:{path}</DataItem>")


def _vertices(n: int) -> np.ndarray:
    """Polyvertex cells of n points, one cell per point."""
    return np.arange(n).reshape(n, 1)


def _attribute(name: str, item: str, shape: tuple[int, ...]) -> str:
    width = shape[1] if len(shape) > 1 else 1
    return f'<Attribute Name="{name}" AttributeType="{_ATTRIBUTE_TYPE[width]}" Center="Node">{item}</Attribute>'


class Series:
    """One time series (rank 0): ``<name>.xdmf`` and ``<name>.h5`` beside it. ``points`` and
    ``cells`` are the reference mesh (``topology``: "Polyline" or "Polyvertex"), ``constants``
    the point data that never changes, ``names`` string lists stored as attributes of ``/mesh``
    (labels for readers). ``resume_after``: continue the series on disk, keeping its steps up to
    that time (restart).

    Records go into segments: ``<name>.h5`` (with the mesh) until the first checkpoint, then
    ``<name>.1.h5``, ``<name>.2.h5``, ... from one checkpoint to the next (:meth:`new_segment`).
    A segment is closed before its checkpoint is written and never opened for writing again, so
    a run killed at any moment (HDF5 files are not crash-safe: a group's index can be left
    half-rewritten) cannot damage the records a restart keeps; the restart deletes the segments
    written after its checkpoint."""

    def __init__(self, xdmf: Path, points: np.ndarray, cells: np.ndarray, topology: str,
                 constants: dict[str, np.ndarray], resume_after: float | None = None,
                 names: dict[str, list[str]] | None = None) -> None:
        import h5py

        from .. import _core

        self.xdmf = Path(xdmf)
        self.h5_path = self.xdmf.with_suffix(".h5")
        self.next_record = 0
        self._written: list[str] = []  # steps handed to the writer, not yet in the .xdmf
        self._times: dict[int, float] = {}  # record -> time, to name the one whose writing failed
        self._fields: dict[str, np.ndarray] | None = None  # the first record: every record's fields
        self._template: tuple[list[str], list[str]] | None = None  # the step's text around {t}, split at {r}
        resume = resume_after is not None and self.xdmf.is_file() and self.h5_path.is_file()
        kept = self._kept_steps(resume_after) if resume else []
        self.segment = self._resume_segments(kept) if resume else self._remove_segments(keep=set())
        with h5py.File(self.h5_path, "a" if resume else "w") as h5:
            self._mesh = self._write_mesh(h5, points, cells, topology, constants, names or {})
        self._open_writer()
        self._has_text = bool(kept)  # the .xdmf exists, or the writer has steps to create it with
        if kept:  # the .xdmf as it was up to the restart time, in this structure
            self._create_text(kept)
        else:  # created by the writer with the first steps
            self._writer.set_text_file(str(self.xdmf), 0, _TAIL, _HEAD)

    def _open_writer(self) -> None:
        """A record writer on the current segment's data file (created empty beyond the first)."""
        import h5py

        from .. import _core

        path = self.segment_path(self.segment)
        if self.segment > 0:
            h5py.File(path, "w").close()
        self._writer = _core.RecordWriter(str(path), COMPACT_BYTES)
        self._segment_records = 0
        self._template = None  # the steps name the segment's file

    def segment_path(self, k: int) -> Path:
        """The data file of segment k (0: ``<name>.h5``, which holds the mesh too)."""
        return self.h5_path if k == 0 else self.xdmf.with_name(f"{self.xdmf.stem}.{k}.h5")

    def _segments_on_disk(self) -> dict[int, Path]:
        found = {}
        for path in self.xdmf.parent.glob(f"{glob.escape(self.xdmf.stem)}.*.h5"):
            k = path.name[len(self.xdmf.stem) + 1:-len(".h5")]
            if k.isdigit() and int(k) > 0:
                found[int(k)] = path
        return found

    def _remove_segments(self, keep: set[str]) -> int:
        """Delete the segment files (beyond the first) not named in keep; the highest kept."""
        last = 0
        for k, path in self._segments_on_disk().items():
            if path.name in keep:
                last = max(last, k)
            else:
                path.unlink()
        return last

    # -- resume ------------------------------------------------------------------------------
    def _kept_steps(self, resume_after: float) -> list[str]:
        """The steps on disk up to resume_after, as XDMF text. A series written before issue 22
        keeps its mesh in a separate grid that every step XIncludes: the steps get copies of
        its Topology and Geometry, so the continued file has one structure throughout."""
        domain = _read_document(self.xdmf).find("Domain")
        collection = domain.find("Grid[@CollectionType='Temporal']")
        mesh = next((g for g in domain.findall("Grid") if g.get("GridType") == "Uniform"), None)
        kept = []
        for grid in collection:
            time = grid.find("Time")
            if time is not None and float(time.get("Value")) > resume_after * (1 + 1e-12) + 1e-300:
                continue
            include = grid.find(_XINCLUDE)
            if include is not None:
                grid.remove(include)
            if mesh is not None and grid.find("Geometry") is None:
                for k, item in enumerate((mesh.find("Topology"), mesh.find("Geometry"))):
                    grid.insert(k, copy.deepcopy(item))
            grid.set("GridType", "Uniform")  # meshio's reader takes the mesh from a Uniform grid
            grid.tail = None
            kept.append(ET.tostring(grid, encoding="unicode"))
        return kept

    def _resume_segments(self, kept: list[str]) -> int:
        """New records follow the kept steps, in a segment of their own: the one after the last
        the kept steps use. Segments written after the checkpoint are deleted. Records after
        the kept ones in a kept segment (a restart from an earlier checkpoint than the last;
        the segment was closed whole) are removed from it."""
        import h5py

        used = [int(m) for text in kept for m in _RECORD_PATH.findall(text)]
        self.next_record = max(used, default=-1) + 1
        files = {m for text in kept for m in _RECORD_FILE.findall(text)}
        last = self._remove_segments(keep=files)
        def later(h5) -> list[str]:
            return [f"{name}/{key}" for name, group in h5.items() if name != "mesh" and hasattr(group, "keys")
                    for key in group.keys() if key.isdigit() and int(key) >= self.next_record]

        for k in range(last + 1):
            path = self.segment_path(k)
            if not path.is_file():
                continue
            with h5py.File(path, "r") as h5:  # opened for writing only if it must change
                drop = later(h5)
            if drop:
                with h5py.File(path, "a") as h5:
                    for dataset in drop:
                        del h5[dataset]
        return last + 1 if files else 0

    # -- structure ---------------------------------------------------------------------------
    def _write_mesh(self, h5, points: np.ndarray, cells: np.ndarray, topology: str,
                    constants: dict[str, np.ndarray], names: dict[str, list[str]]) -> str:
        """Write the reference mesh, the constant fields and the names (unless a resumed file has
        them: a restart never writes into the data files before its checkpoint, not even an
        attribute); return the XDMF text every step carries for them."""
        import h5py

        if "mesh" not in h5:
            group = h5.create_group("mesh")
            group["points"] = points
            group["cells"] = cells
            for name, values in constants.items():
                group[name] = values
            for key, values in names.items():
                group.attrs.create(key, values, dtype=h5py.string_dtype())
        h5 = self.h5_path.name
        text = (f'<Topology TopologyType="{topology}" NumberOfElements="{len(cells)}" '
                f'NodesPerElement="{cells.shape[1]}">{_data_item(h5, "/mesh/cells", cells.shape, cells.dtype)}'
                f'</Topology><Geometry GeometryType="XYZ">'
                f'{_data_item(h5, "/mesh/points", points.shape, points.dtype)}</Geometry>')
        consts = "".join(_attribute(name, _data_item(h5, f"/mesh/{name}", v.shape, v.dtype), v.shape)
                         for name, v in constants.items())
        return text + "{steps}" + consts

    def _step_template(self, data: dict[str, np.ndarray]) -> tuple[list[str], list[str]]:
        """A step's grid with {t} and {r} (record) to fill in: the same for every record of the
        segment; its text before and after {t}, each split at {r}."""
        h5 = self.segment_path(self.segment).name
        fields = "".join(_attribute(name, _data_item(h5, f"/{name}/{{r}}", v.shape, v.dtype), v.shape)
                         for name, v in data.items())
        mesh, consts = self._mesh.split("{steps}")
        before, after = f'<Grid GridType="Uniform">{mesh}<Time Value="{{t}}" />{fields}{consts}</Grid>'.split("{t}")
        return before.split("{r}"), after.split("{r}")

    # -- writing -----------------------------------------------------------------------------
    def add(self, t: float, data: dict[str, np.ndarray]) -> None:
        """Hand a record to the writer (one dataset per field and record)."""
        if self._fields is None:
            self._fields = data
        self._writer.add(self.next_record, data)
        self.added(t)

    @property
    def writer(self):
        """The record writer (``_core.RecordWriter``): a record handed to it directly as
        ``next_record`` is then announced with :meth:`added`."""
        return self._writer

    def added(self, t: float) -> None:
        """Record ``next_record``, at time t, is with the writer (its fields as the first record's)."""
        if self._template is None:
            self._template = self._step_template(self._fields)
        before, after = self._template
        r = str(self.next_record)
        self._written.append(r.join(before) + repr(float(t)) + r.join(after))
        self._times[self.next_record] = float(t)
        self.next_record += 1
        self._segment_records += 1

    def new_segment(self) -> None:
        """Wait until the .xdmf describes every record so far, close their data file and write
        the records that follow into a new one (at a checkpoint, before it is written). Nothing
        to do if the segment holds no record yet."""
        if self._segment_records == 0:
            return
        self.flush(wait=True)
        error = self._writer.close()
        if error:
            raise OutputFailure(error)
        self.segment += 1
        self._open_writer()
        self._writer.set_text_file(str(self.xdmf), self.xdmf.stat().st_size - len(_TAIL), _TAIL)

    def flush(self, wait: bool, backlog: int = 0) -> None:
        """Make the .xdmf describe the records handed over so far, once their data is on disk:
        the writer flushes the .h5 and then appends their steps to the .xdmf. ``wait``: return
        when that is done; else at once, unless more than ``backlog`` records wait to be written
        (memory). Raises OutputFailure if writing (this or an earlier flush) failed."""
        wait = wait or self._writer.pending > backlog
        if self._written:
            self._writer.append_text("".join(self._written).encode())
            self._has_text = True
        self._written = []
        if wait:
            self._wait()
        elif self._writer.error:
            self._raise(self._writer.error)

    def _create_text(self, steps: list[str]) -> None:
        text = _HEAD + "".join(steps).encode()
        tmp = self.xdmf.with_name(f".{self.xdmf.name}.tmp")
        tmp.write_bytes(text + _TAIL)
        os.replace(tmp, self.xdmf)
        self._writer.set_text_file(str(self.xdmf), len(text), _TAIL)

    def _wait(self) -> None:
        error = self._writer.wait()
        if error:
            self._raise(error)
        self._times.clear()

    def _raise(self, error: str) -> None:
        t = self._times.get(self._writer.failed_record)
        raise OutputFailure(error if t is None else f"at t = {t:.6g}: {error}")

    def abandon(self) -> None:
        """Close the .h5 after a failure, writing nothing more."""
        self._writer.close()

    def close(self) -> None:
        self.flush(wait=True)
        if not self._has_text:  # no record at all: a series without steps
            self._create_text([])
        error = self._writer.close()
        if error:
            raise OutputFailure(error)


class NoOutput:
    """Stands in for XdmfOutput when the scene says [output] xdmf = false."""

    def write(self, t: float, joints: list[JointState] | None = None) -> None:
        pass

    def flush(self, wait: bool = True) -> None:
        pass

    def checkpoint(self) -> None:
        pass

    def close(self) -> None:
        pass


# Bytes of one record, measured on the seed scenes (scripts/bench_output.py): the values, the
# HDF5 object of each field (header and link), and the step's XDMF text
FLOATS_PER_SAMPLE = 34  # displacement, velocity, d1-d3, strain (6), force, moment, tension, section_d2/d3
FLOATS_PER_SLIDER = 8  # displacement, s, ds_dt, reaction
FLOATS_PER_GUIDE = 8  # displacement, s, ds_dt, reaction
FLOATS_PER_MASS = 6  # displacement, velocity
BYTES_PER_DATASET = 500
XDMF_BYTES_PER_FIELD = 150
XDMF_BYTES_PER_STEP = 1000


def bytes_per_record(scene) -> int:
    """Disk space one recorded step takes (data and XDMF text), for the checks at the start."""
    if not scene.output.xdmf:
        return 0
    n = sum(b.spans * scene.output.samples_per_span + 1 for b in scene.beams)
    size = 8 * FLOATS_PER_SAMPLE * n + 11 * (BYTES_PER_DATASET + XDMF_BYTES_PER_FIELD) + XDMF_BYTES_PER_STEP
    if scene.sliding_joints:
        size += 8 * FLOATS_PER_SLIDER * len(scene.sliding_joints) + 4 * (BYTES_PER_DATASET + XDMF_BYTES_PER_FIELD)
        size += XDMF_BYTES_PER_STEP
    guides = len(scene.entries("guide"))
    if guides:
        size += 8 * FLOATS_PER_GUIDE * guides + 4 * (BYTES_PER_DATASET + XDMF_BYTES_PER_FIELD) + XDMF_BYTES_PER_STEP
    masses = len(scene.entries("point_mass"))
    if masses:
        size += 8 * FLOATS_PER_MASS * masses + 2 * (BYTES_PER_DATASET + XDMF_BYTES_PER_FIELD) + XDMF_BYTES_PER_STEP
    if scene.bodies:
        size += 8 * FLOATS_PER_BODY * len(scene.bodies) + 5 * (BYTES_PER_DATASET + XDMF_BYTES_PER_FIELD)
        size += XDMF_BYTES_PER_STEP
    return size


@dataclass(frozen=True)
class PointMass:
    """A ``[[point_mass]]`` as the masses series shows it."""

    label: str  # the effect's label, as in summary.json's active_effects: "point_mass[hanger@end]"
    beam: int
    s: float  # arc length on the beam
    mass: float


def point_masses(sim: "Simulation") -> list[PointMass]:
    """The scene's point masses in file order, labelled as the model labels them (a second mass
    at the same point is "...#2")."""
    labels = [e.label for e in sim.active_effects if e.type == "point_mass"]
    entries = sim.scene.entries("point_mass")
    return [PointMass(label, int(e.num["beam"]), float(e.num["s"]), float(e.num["mass"]))
            for label, e in zip(labels, entries, strict=True)]


class XdmfOutput:
    """The beams (and sliders, point masses) time series of one run, and the ParaView script
    that shows them (view.py). All ranks call ``write``, ``flush`` and ``close``."""

    def __init__(self, sim: "Simulation", out: Path, rank: int, resume_after: float | None = None) -> None:
        self.sim = sim
        self.rank = rank
        self.k = sim.scene.output.samples_per_span
        self._beam_indices = [b.index for b in sim.scene.beams]
        self.closed = False
        self.writes = 0
        self._held = 0  # records since the last flush
        self._flush_every = FLUSH_EVERY
        self._last_t = 0.0
        ref, s = self._reference()
        self._ref_points = ref
        self._half2, self._half3 = self._section_halves()
        self._slider_points = [(j.slider, j.at) for j in sim.scene.sliding_joints]
        self._slider_rows = self._end_rows(self._slider_points)
        self._slider_ref = self._positions(self._slider_points, self._slider_rows, ref, self._ref_x)
        # guides: their outputs (s, ds_dt, reaction, gap, point) in the effects' outputs
        self._guide_slices = [sim.output_slice(k) for k, e in enumerate(sim.active_effects) if e.type == "guide"]
        guides = [e for e in sim.scene.effects if e.type == "guide"]
        self._guide_names = [e.text["name"] for e in guides]
        self._guide_ref = np.array([e.vec["point"] for e in guides]).reshape(-1, 3)
        self._masses = point_masses(sim)
        self._mass_points = [(m.beam, m.s) for m in self._masses]
        self._mass_rows = self._end_rows(self._mass_points)
        self._mass_ref = self._positions(self._mass_points, self._mass_rows, ref, self._ref_x)
        self._ref_x.destroy()
        self._bodies = list(sim.scene.bodies)
        self._body_ref = np.array([b.position for b in self._bodies]).reshape(-1, 3)
        from .. import _core

        self._sampler = _core.BeamSeriesSampler(self._beam_indices, self.k, ref, self._half2.ravel(), self._half3.ravel())
        self._series: dict[str, Series] = {}  # by name; emptied when the output is abandoned
        if rank != 0:
            return
        try:
            self._open_series(out, ref, s, resume_after)
        except OSError as err:
            raise OutputFailure(f"cannot write the XDMF output in {out}: {err}") from err
        try:
            self._write_view_script(out, ref)
        except OSError as err:
            raise OutputFailure(f"cannot write the ParaView script {out / VIEW_SCRIPT}: {err}") from err

    def _open_series(self, out: Path, ref: np.ndarray, s: np.ndarray, resume_after: float | None) -> None:
        beams = self.sim.scene.beams
        ids = np.concatenate([np.full(b.spans * self.k + 1, b.index, dtype=np.int32) for b in beams])
        self._series[BEAMS] = Series(out / f"{BEAMS}.xdmf", ref, self._lines(), "Polyline", {"s": s, "beam_id": ids},
                                     resume_after, names={"beam_names": [b.name for b in beams]})
        if self._slider_points:
            n = len(self._slider_ref)
            self._series[SLIDERS] = Series(out / f"{SLIDERS}.xdmf", self._slider_ref, _vertices(n), "Polyvertex",
                                           {"joint_id": np.arange(n, dtype=np.int32)}, resume_after,
                                           names={"joint_names": list(self.sim.scene.sliding_joint_labels)})
        if self._guide_slices:
            n = len(self._guide_slices)
            self._series[GUIDES] = Series(out / f"{GUIDES}.xdmf", self._guide_ref, _vertices(n), "Polyvertex",
                                          {"guide_id": np.arange(n, dtype=np.int32)}, resume_after,
                                          names={"guide_names": self._guide_names})
        if self._masses:
            n = len(self._masses)
            constants = {"mass": np.array([m.mass for m in self._masses]), "mass_id": np.arange(n, dtype=np.int32)}
            self._series[MASSES] = Series(out / f"{MASSES}.xdmf", self._mass_ref, _vertices(n), "Polyvertex",
                                          constants, resume_after, names={"mass_names": [m.label for m in self._masses]})
        if self._bodies:
            n = len(self._bodies)
            constants = {"mass": np.array([b.mass for b in self._bodies]), "body_id": np.arange(n, dtype=np.int32)}
            self._series[BODIES] = Series(out / f"{BODIES}.xdmf", self._body_ref, _vertices(n), "Polyvertex",
                                          constants, resume_after, names={"body_names": [b.name for b in self._bodies]})

    def _write_view_script(self, out: Path, ref: np.ndarray) -> None:
        """view.py beside the series: ParaView opens the run with one command."""
        from .paraview_script import ViewConfig, up_direction, view_script

        halves = np.concatenate([self._half2, self._half3])
        gravity = self.sim.scene.entries("gravity")
        config = ViewConfig(scene=self.sim.scene.name, series=tuple(self._series),
                            section_half=float(halves.max()) if halves.size else 0.0,
                            extent=float(np.linalg.norm(ref.max(axis=0) - ref.min(axis=0))) if len(ref) else 0.0,
                            up=up_direction(gravity[0].vec["g"] if gravity else None), folder=str(out.resolve()))
        tmp = out / f".{VIEW_SCRIPT}.tmp"
        tmp.write_text(view_script(config))
        os.replace(tmp, out / VIEW_SCRIPT)

    # -- sampling (collective) -------------------------------------------------------------
    def _sample(self, x, v) -> dict[str, np.ndarray]:
        """Every beam's samples, one array per field over all beams (beam order)."""
        return self.sim._model.sample_beams(self._beam_indices, x, v, self.k)

    def _reference(self) -> tuple[np.ndarray, np.ndarray]:
        """Sample points of the beams in the reference configuration (the mesh; displacements are
        measured from it, also after a restart) and their arc lengths."""
        self._ref_x = self.sim._model.x.duplicate()
        self.sim._model.set_reference_state(self._ref_x)
        ref = self._sample(self._ref_x, None)
        return ref["position"], ref["s"]

    def _section_halves(self) -> tuple[np.ndarray, np.ndarray]:
        """Per sample point, the half extent of the section along d2 and along d3."""
        half2, half3 = [], []
        for b in self.sim.scene.beams:
            sec, n = b.section, b.spans * self.k + 1
            half2.append(np.full((n, 1), np.sqrt(3.0 * sec.EI3 / sec.EA)))
            half3.append(np.full((n, 1), np.sqrt(3.0 * sec.EI2 / sec.EA)))
        return np.concatenate(half2), np.concatenate(half3)

    def _end_rows(self, points: Sequence[tuple[int, float]]) -> list[int | None]:
        """Per beam point (beam, arc length), the sample point it is (a beam end), or None (a
        point inside the beam: evaluated apart)."""
        first, firsts = 0, {}
        for b in self.sim.scene.beams:
            firsts[b.index] = first
            first += b.spans * self.k + 1
        rows: list[int | None] = []
        for beam, s in points:
            b = self.sim.scene.beams[beam]
            rows.append(firsts[b.index] if s == 0.0 else
                        firsts[b.index] + b.spans * self.k if s == b.geometry.length else None)
        return rows

    def _positions(self, points: Sequence[tuple[int, float]], rows: list[int | None], samples: np.ndarray,
                   x=None) -> np.ndarray:
        """Positions of beam points (beam, arc length) in the state x (default: the current one):
        a beam end is its sample point, any other point is evaluated on its beam. Collective:
        every rank holds the same points, so all evaluate the same beams in the same order."""
        pos = np.empty((len(points), 3))
        inside: dict[int, list[int]] = {}
        for i, ((beam, _), row) in enumerate(zip(points, rows)):
            if row is None:
                inside.setdefault(beam, []).append(i)
            else:
                pos[i] = samples[row]
        for beam, which in inside.items():  # one gather of the beam's coordinates for all its points
            pos[which] = self.sim.evaluate(beam, [points[i][1] for i in which], x)[:, :3]
        return pos

    def _velocities(self, points: Sequence[tuple[int, float]]) -> np.ndarray:
        """Velocities of beam points (collective; zero in a static run). The beam's coordinates
        are interpolated linearly, so their rates interpolate the same way: _positions in v."""
        if self.sim.v is None:
            return np.zeros((len(points), 3))
        return self._positions(points, [None] * len(points), np.empty((0, 3)), self.sim.v)

    def _lines(self) -> np.ndarray:
        cells, first = [], 0
        for b in self.sim.scene.beams:
            n = b.spans * self.k + 1
            cells.append(np.column_stack([np.arange(first, first + n - 1), np.arange(first + 1, first + n)]))
            first += n
        return np.concatenate(cells)

    def fields(self) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Point data of the current state that changes from record to record (collective), and
        the sample points' positions."""
        return self._sampler.fields(self.sim._model, self.sim.x, self.sim.v)

    def slider_fields(self, position: np.ndarray, joints: list[JointState] | None = None) -> dict[str, np.ndarray]:
        """The sliders' point data; ``joints``: the sliding joints' states if the caller has them
        (a record), else they are computed (collective)."""
        joints = self.sim.joint_states() if joints is None else joints
        state = np.array([(j.s, j.ds_dt, *j.reaction) for j in joints]).reshape(-1, 5)
        current = self._positions(self._slider_points, self._slider_rows, position)
        return {"displacement": current - self._slider_ref, "s": state[:, 0], "ds_dt": state[:, 1],
                "reaction": state[:, 2:]}

    def guide_fields(self, outputs: list[float] | None = None) -> dict[str, np.ndarray]:
        """The guides' point data from the effects' outputs (a record's, else computed: collective):
        the guide's point (it moves with its body), the rope's s there, its rate, and the force of
        the rope on the guide (the history's reaction columns)."""
        values = np.asarray(self.sim.effect_outputs() if outputs is None else outputs, dtype=float)
        state = np.array([values[where] for where in self._guide_slices]).reshape(-1, 9)
        return {"displacement": state[:, 6:9] - self._guide_ref, "s": state[:, 0], "ds_dt": state[:, 1],
                "reaction": state[:, 2:5]}

    def mass_fields(self, position: np.ndarray) -> dict[str, np.ndarray]:
        """The point masses' point data (collective); ``position``: the sample points' positions."""
        current = self._positions(self._mass_points, self._mass_rows, position)
        return {"displacement": current - self._mass_ref, "velocity": self._velocities(self._mass_points)}

    def body_fields(self) -> dict[str, np.ndarray]:
        """The bodies' point data (collective): centre of mass, its velocity and the body's axes."""
        q = np.array([self.sim.control_points(b.index)[0] for b in self._bodies])
        v = np.array([self.sim.control_points(b.index, self.sim.v)[0, :3] for b in self._bodies])
        return {"displacement": q[:, :3] - self._body_ref, "velocity": v, "d1": q[:, 3:6], "d2": q[:, 6:9],
                "d3": q[:, 9:12]}

    # -- writing ---------------------------------------------------------------------------
    def write(self, t: float, joints: list[JointState] | None = None, outputs: list[float] | None = None) -> None:
        """Append the current state at time t (collective); ``joints`` as for slider_fields,
        ``outputs`` (the effects' outputs of the record) as for guide_fields."""
        from ..run.costs import output_phase

        with output_phase():
            self._write(t, joints, outputs)

    def _write(self, t: float, joints: list[JointState] | None, outputs: list[float] | None) -> None:
        beams = self._series.get(BEAMS)
        if self.writes == 0:  # every rank holds the same arrays: the same flush points everywhere
            data, position = self.fields()
        else:  # sampled into the writer's record
            data = None
            position = self._sampler.record(self.sim._model, self.sim.x, self.sim.v,
                                            None if beams is None else beams.writer, -1 if beams is None else beams.next_record)
        points = {SLIDERS: self.slider_fields(position, joints) if self._slider_points else {},
                  GUIDES: self.guide_fields(outputs) if self._guide_slices else {},
                  MASSES: self.mass_fields(position) if self._masses else {},
                  BODIES: self.body_fields() if self._bodies else {}}
        if data is not None:
            size = sum(v.nbytes for fields in (data, *points.values()) for v in fields.values())
            self._flush_every = max(1, min(FLUSH_EVERY, PENDING_BYTES // max(1, size)))
        if beams is not None:
            if data is not None:
                beams.add(t, data)
            else:
                beams.added(t)
        for name, fields in points.items():
            if fields and name in self._series:
                self._series[name].add(t, fields)
        self._last_t = t
        self.writes += 1
        self._held += 1
        if self._held >= self._flush_every:
            self.flush(wait=False)

    def _raise_on_any_rank(self, error: str | None) -> None:
        """Only rank 0 writes, but every rank must stop: share its verdict."""
        comm = run_comm()
        if comm.Get_size() > 1:
            error = comm.bcast(error, root=0)
        if error:
            self.closed = True
            raise OutputFailure(error)

    def _abandon(self) -> None:
        """After a failed write: write no more (the .xdmf on disk keeps describing the steps of
        the last flush) and close the files, whose failure is already reported."""
        self.closed = True
        for s in self._series.values():
            s.abandon()
        self._series = {}

    def flush(self, wait: bool = True) -> None:
        """Make the .xdmf files describe the records so far (collective). ``wait``: return once
        they do (a checkpoint, the end of the run; the .h5 files are not written meanwhile); else
        the writers do it while the run goes on."""
        error = None
        self._held = 0
        try:
            for s in self._series.values():
                s.flush(wait, backlog=2 * self._flush_every)
        except OutputFailure as err:  # the record that failed names its time
            self._abandon()
            error = f"writing the XDMF output failed {err}" if str(err).startswith("at t =") else \
                f"writing the XDMF output at t = {self._last_t:.6g} failed: {err}"
        except OSError as err:  # the .xdmf text
            self._abandon()
            error = f"writing the XDMF output at t = {self._last_t:.6g} failed: {_first_line(err)}"
        self._raise_on_any_rank(error)

    def checkpoint(self) -> None:
        """Before a checkpoint is written (collective): bring the .xdmf files up to date and close
        the data files of their records; the records that follow go into new files
        (:meth:`Series.new_segment`), which a run killed later may leave damaged but a restart
        from this checkpoint deletes."""
        self.flush()
        error = None
        try:
            for s in self._series.values():
                s.new_segment()
        except (OutputFailure, OSError) as err:
            self._abandon()
            error = f"writing the XDMF output at t = {self._last_t:.6g} failed: {_first_line(err)}"
        self._raise_on_any_rank(error)

    def close(self) -> None:
        """Write what is held, the .xdmf files, and close the .h5 files (collective)."""
        if self.closed:
            return
        self.flush()
        self.closed = True
        errors = []
        for s in self._series.values():
            try:
                s.close()
            except (OutputFailure, OSError) as err:
                errors.append(_first_line(err))
        self._series = {}
        self._raise_on_any_rank("closing the XDMF output failed: " + "; ".join(errors) if errors else None)
