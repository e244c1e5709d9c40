# SPDX-License-Identifier: MIT
"""A run folder read back for plots and pictures: summary.json, history.csv and the XDMF series
(beams, sliders, point masses), without PETSc or MPI.

The series are read the way ParaView reads them: each step of the ``.xdmf`` names, per field, the
data file and dataset that hold it (``beams.h5:/tension/17``; after checkpoints ``beams.1.h5``,
...), so a run that was restarted or is still running reads as written."""
from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .xdmf import _read_document


class RunFolderError(Exception):
    """A folder that is not a slidebeam run, or lacks the file a plot needs."""


@dataclass
class Series:
    """One XDMF time series: the reference mesh, constant point data and, per recorded time, where
    each changing field is stored. ``names``: labels of the ids (beams or point masses) when the
    data file has them."""

    path: Path
    times: np.ndarray
    points: np.ndarray
    cells: np.ndarray
    constants: dict[str, np.ndarray]
    names: list[str]
    _where: list[dict[str, tuple[str, str]]] = field(repr=False)
    _files: dict[str, Any] = field(default_factory=dict, repr=False)

    @property
    def fields(self) -> list[str]:
        return list(self._where[0]) if self._where else []

    def field(self, name: str, record: int) -> np.ndarray:
        """Point data ``name`` of record ``record`` (an index into ``times``)."""
        where = self._where[record]
        if name not in where:
            raise RunFolderError(f"{self.path}: no field {name!r} (it has {', '.join(where)})")
        file, dataset = where[name]
        return np.asarray(self._file(file)[dataset])

    def positions(self, record: int) -> np.ndarray:
        """The points' current positions: reference plus displacement."""
        return self.points + self.field("displacement", record)

    def field_over_time(self, name: str, records: list[int] | None = None) -> np.ndarray:
        """(records, points, ...) array of a field."""
        records = list(range(len(self.times))) if records is None else records
        return np.stack([self.field(name, r) for r in records])

    def _file(self, name: str):
        import h5py

        if name not in self._files:
            self._files[name] = h5py.File(self.path.parent / name, "r", locking=False)
        return self._files[name]

    def close(self) -> None:
        for f in self._files.values():
            f.close()
        self._files.clear()


def _data_location(item) -> tuple[str, str]:
    file, _, dataset = (item.text or "").strip().partition(":")
    return file, dataset


def read_series(xdmf: Path, id_name: str, names_attribute: str) -> Series:
    """The series of ``xdmf`` (its ``/mesh`` read from the first data file); ``id_name`` the
    constant field numbering the objects, ``names_attribute`` the mesh attribute naming them."""
    import h5py

    root = _read_document(xdmf)
    steps = [g for g in root.iter("Grid") if g.get("GridType") == "Uniform"]
    times, where = [], []
    for grid in steps:
        time = grid.find("Time")
        if time is None:
            continue
        times.append(float(time.get("Value", "nan")))
        where.append({a.get("Name", ""): _data_location(a.find("DataItem")) for a in grid.findall("Attribute")})
    mesh_file = xdmf.with_suffix(".h5")
    if not mesh_file.is_file():
        raise RunFolderError(f"{mesh_file} is missing (it holds the mesh of {xdmf.name})")
    with h5py.File(mesh_file, "r", locking=False) as h5:
        mesh = h5["mesh"]
        points, cells = np.asarray(mesh["points"]), np.asarray(mesh["cells"])
        constants = {k: np.asarray(mesh[k]) for k in mesh if k not in ("points", "cells")}
        raw = mesh.attrs.get(names_attribute)
        names = [n.decode() if isinstance(n, bytes) else str(n) for n in raw] if raw is not None else []
    changing = [{k: v for k, v in w.items() if not v[1].startswith("/mesh/")} for w in where]
    ids = constants.get(id_name)
    count = int(ids.max()) + 1 if ids is not None and ids.size else 0
    if len(names) != count:
        names = [f"{id_name.removesuffix('_id')} {k}" for k in range(count)]
    return Series(xdmf, np.array(times), points, cells, constants, names, changing)


@dataclass
class Run:
    """A run folder: its summary, history and (when written) XDMF series."""

    folder: Path
    summary: dict[str, Any]
    history: dict[str, np.ndarray]
    beams: Series | None
    sliders: Series | None
    masses: Series | None
    bodies: Series | None = None
    guides: Series | None = None

    @property
    def label(self) -> str:
        return str(self.summary.get("scene") or self.folder.name)

    @property
    def dynamic(self) -> bool:
        return "total_energy" in self.history

    def columns(self, suffix: str) -> list[str]:
        """History columns that end in ``suffix``, in file order."""
        return [k for k in self.history if k.endswith(suffix)]

    def close(self) -> None:
        for s in (self.beams, self.sliders, self.masses, self.bodies, self.guides):
            if s is not None:
                s.close()


def read_history(folder: Path) -> dict[str, np.ndarray]:
    """Columns of a run's history.csv as float arrays (text columns are skipped)."""
    path = Path(folder) / "history.csv"
    if not path.is_file():
        raise RunFolderError(f"{path} does not exist (is {folder} a slidebeam run folder?)")
    with path.open() as f:
        rows = list(csv.DictReader(f))
    out: dict[str, np.ndarray] = {}
    for key in rows[0] if rows else []:
        try:
            out[key] = np.array([float(r[key]) for r in rows])
        except ValueError:
            continue
    return out


def open_run(folder: str | Path) -> Run:
    """Read a run folder (the XDMF series lazily: their data is read per field and record)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise RunFolderError(f"{folder} is not a folder (give a run's output folder, with history.csv)")
    history = read_history(folder)
    summary_path = folder / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.is_file() else {}

    def series(name: str, id_name: str, names: str) -> Series | None:
        path = folder / f"{name}.xdmf"
        return read_series(path, id_name, names) if path.is_file() else None

    run = Run(folder, summary, history, series("beams", "beam_id", "beam_names"),
              series("sliders", "joint_id", "joint_names"), series("masses", "mass_id", "mass_names"),
              series("bodies", "body_id", "body_names"), series("guides", "guide_id", "guide_names"))
    beam_names = list(summary.get("final_end_positions", {}))  # in beam order; for series without names
    if run.beams is not None and run.beams.names[:1] == ["beam 0"] and len(beam_names) == len(run.beams.names):
        run.beams.names = beam_names
    joint_names = [k.removesuffix(".ds_dt") for k in run.columns(".ds_dt")]  # for series without names
    if run.sliders is not None and run.sliders.names[:1] == ["joint 0"] and len(joint_names) == len(run.sliders.names):
        run.sliders.names = joint_names
    return run
