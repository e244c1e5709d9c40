# SPDX-License-Identifier: MIT
"""The memory a scene needs, estimated before anything is allocated, and the refusal of scenes
that cannot fit (issue 22: ``spans = 1000000000`` used to allocate gigabytes and run for
minutes before failing).

What the estimate counts, in bytes (the constants are fits to the peak resident memory of
short runs of 1000 to 30000 spans, serial and on 2 ranks, with ~15 % margin; see
scripts/measure_memory.py):

- the solver, per unknown (:data:`BYTES_PER_UNKNOWN`): the state and integrator vectors, the
  Jacobian (about 50 nonzeros a row for director beams), its LU factors (SuperLU serially,
  MUMPS with 200 % workspace in parallel; the chain of control points is a band, so the fill
  grows linearly), the model's element data and ghosts. Unknowns: 18 per control point of a
  director beam (12 coordinates, 6 multipliers; spans + 2 points), 6 per node of an ANCF cable
  (spans + 1 nodes), a few per joint and support. This part is shared among the ranks.
- the output, per sample point (:data:`BYTES_PER_SAMPLE`; spans x samples_per_span + 1 per
  beam): the fields of an XDMF record and the text of final_configuration.csv. Every rank
  holds its own copy.
- the history kept in memory until the run ends, per record (:data:`BYTES_PER_RECORD` plus
  :data:`BYTES_PER_RECORD_ITEM` per tracked point, sliding joint, support and rigid joint):
  every load step of a static run, every output.every-th step (or output.interval) of a dynamic one. Per rank.

Not counted: the processes themselves (Python, PETSc, MPI: about 100 MB each), which already
run when the estimate is made. The estimate is compared with what the node has available
(MemAvailable of /proc/meminfo, or less if a cgroup limit leaves less); ranks on the same node
share it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from ..scene.effect_tables import effect_specs
from ..scene.parse import Scene, SceneError
from .parallel import run_comm

# Fits (bytes): director 6.0-6.3 kB per unknown serially, 7.0 kB on 2 ranks (sum over ranks);
# ANCF cable 1.9-3.0 kB serially, 3.7 kB on 2 ranks; 1.0-1.1 kB per sample point.
BYTES_PER_UNKNOWN = {"director": 7_500, "ancf": 4_500}
BYTES_PER_SAMPLE = 1_300
BYTES_PER_RECORD = 2_048
BYTES_PER_RECORD_ITEM = 512
UNKNOWNS_PER_EXTRA = 8  # a joint's or support's multipliers and coordinates (generous)
INDEX_LIMIT = 2**31 - 1  # PETSc's 32-bit PetscInt (this build): global indices must fit


@dataclass(frozen=True)
class Part:
    """One contribution to the estimate, and the scene key that sizes it."""

    table: str  # "[[beam]] #1 ('strip')", "[output]", "[analysis]"
    key: str  # "spans", "samples_per_span", "steps", "dt"
    bytes: int  # on one node
    what: str  # "1000000000 spans: 18000000036 unknowns"


@dataclass(frozen=True)
class Estimate:
    unknowns: int
    parts: tuple[Part, ...]
    ranks: int  # ranks on the node the figures are for

    @property
    def total(self) -> int:
        return sum(p.bytes for p in self.parts)

    @property
    def largest(self) -> Part:
        return max(self.parts, key=lambda p: p.bytes)


def unknowns_of_beam(beam) -> int:
    return 6 * (beam.spans + 1) if beam.formulation == "ancf" else 18 * (beam.spans + 2)


def _beam_table(beam) -> str:
    return f"[[beam]] #{beam.index + 1} ('{beam.name}')"


def recorded_steps(scene: Scene) -> tuple[int | float, str]:
    """(records the history keeps in memory, the key that sizes them)."""
    a = scene.analysis
    if a.type == "static":
        return a.steps + 2, "steps"
    steps = a.planned_steps()
    return scene.output.records(steps, a.t_end) + 2, "dt"


def constraint_entries(scene: Scene) -> int:
    """Entries whose effect is a constraint (supports, joints): each adds a few multipliers, and
    a reaction or joint state to every record."""
    return sum(1 for e in scene.effects if effect_specs()[e.type].role == "constraint")


def estimate(scene: Scene, ranks: int = 1, ranks_on_node: int | None = None) -> Estimate:
    """The memory `scene` needs on one node where `ranks_on_node` of the run's `ranks` ranks
    run (default: all of them). Plain integer arithmetic: no size overflows it."""
    local = ranks if ranks_on_node is None else ranks_on_node
    share = local / max(1, ranks)
    parts: list[Part] = []
    unknowns = 0
    samples = 0
    for b in scene.beams:
        n = unknowns_of_beam(b)
        unknowns += n
        samples += b.spans * scene.output.samples_per_span + 1
        parts.append(Part(_beam_table(b), "spans", math.ceil(n * BYTES_PER_UNKNOWN[b.formulation] * share),
                          f"{b.spans} spans ({n} unknowns)"))
    # joints and supports: a few multipliers each (their memory is in the beams' margin)
    constraints = constraint_entries(scene)
    unknowns += constraints * UNKNOWNS_PER_EXTRA
    parts.append(Part("[output]", "samples_per_span", samples * BYTES_PER_SAMPLE * local,
                      f"{samples} output sample points"))
    records, key = recorded_steps(scene)
    items = len(scene.output.track) + constraints  # reactions and sliding joints
    per_record = BYTES_PER_RECORD + BYTES_PER_RECORD_ITEM * items
    record_bytes = records * per_record * local
    parts.append(Part("[analysis]", key, math.ceil(record_bytes) if math.isfinite(record_bytes) else record_bytes,
                      f"{records:.3g} history records"))
    return Estimate(unknowns, tuple(parts), local)


def available_memory() -> tuple[int, str] | None:
    """(bytes that can still be allocated on this node, where the figure comes from), or None
    where the system does not say (not Linux)."""
    try:
        info = dict(line.split(":", 1) for line in Path("/proc/meminfo").read_text().splitlines() if ":" in line)
        avail = int(info["MemAvailable"].split()[0]) * 1024
    except (OSError, KeyError, ValueError):
        return None
    source = "MemAvailable in /proc/meminfo"
    for limit_file, usage_file in (("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
                                   ("/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                    "/sys/fs/cgroup/memory/memory.usage_in_bytes")):
        try:
            limit_text = Path(limit_file).read_text().strip()
            if limit_text == "max":
                continue
            room = int(limit_text) - int(Path(usage_file).read_text().strip())
        except (OSError, ValueError):
            continue
        if 0 <= room < avail:
            avail, source = room, f"the container's memory limit ({limit_file})"
    return avail, source


def size_text(n: float) -> str:
    """Bytes for people: 812 kB, 3.4 GB, 1.3e+05 TB."""
    if not math.isfinite(n):
        return "more bytes than can be counted"
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= scale:
            value = n / scale
            return f"{value:.3g} {unit}" if value < 1e4 else f"{value:.2e} {unit}"
    return f"{n / 1e3:.3g} kB"


def _node_layout(comm) -> tuple[int, int, int]:
    """(ranks, ranks on this rank's node, this rank's node leader flag as 0/1)."""
    if comm is None:
        return 1, 1, 1
    from mpi4py import MPI

    node = comm.Split_type(MPI.COMM_TYPE_SHARED)
    try:
        return comm.Get_size(), node.Get_size(), int(node.Get_rank() == 0)
    finally:
        node.Free()


def check_memory(scene: Scene, comm=None) -> Estimate:
    """Refuse (SceneError naming file, table and key) a scene whose estimate exceeds the memory
    its node has available, or whose unknowns PETSc's indices cannot count; else return the
    estimate for this rank's node. Collective over comm (an mpi4py communicator; default
    the run's, parallel.run_comm, when mpi4py is loaded): every rank refuses, with the same message."""
    if comm is None:
        try:
            comm = run_comm()
        except ImportError:
            comm = None
    ranks, local, _ = _node_layout(comm)
    est = estimate(scene, ranks, local)
    avail = available_memory()
    error = None
    if avail is not None and est.total > avail[0]:
        error = _too_big(scene, est, avail)
    if comm is not None and ranks > 1:
        errors = [e for e in comm.allgather(error) if e is not None]
        error = errors[0] if errors else None  # the same message on every rank
    if error is None and est.unknowns > INDEX_LIMIT:
        part = _largest_beam_part(scene, est)
        error = (f"{part.what} give {est.unknowns} unknowns in all, more than PETSc's 32-bit indices can count "
                 f"({INDEX_LIMIT}); use fewer spans",
                 part.table, part.key)
    if error is not None:
        message, table, key = error
        raise SceneError(message, scene.file, table, key)
    return est


def _largest_beam_part(scene: Scene, est: Estimate) -> Part:
    beams = [p for p in est.parts if p.table.startswith("[[beam]] #")]
    return max(beams, key=lambda p: p.bytes)


def _too_big(scene: Scene, est: Estimate, avail: tuple[int, str]) -> tuple[str, str, str]:
    part = est.largest
    fix = {"spans": "use fewer spans", "samples_per_span": "lower output.samples_per_span",
           "steps": "use fewer load steps", "dt": "record less often (raise output.every or output.interval) or use a larger dt"}[part.key]
    ranks = f" on this node ({est.ranks} ranks)" if est.ranks > 1 else ""
    message = (f"{part.what} make the run need about {size_text(est.total)} of memory{ranks}, but this machine "
               f"has {size_text(avail[0])} available ({avail[1]}); {fix}")
    return message, part.table, part.key


def memory_line(est: Estimate) -> str:
    """One line for `slidebeam check`: the estimate against what the node has."""
    avail = available_memory()
    have = f" of {size_text(avail[0])} available" if avail else ""
    return f"  memory: about {size_text(est.total)}{have} ({est.unknowns} unknowns)"
