# SPDX-License-Identifier: MIT
"""Where a run's time goes, from PETSc's log events: one row per effect type the scene created
(its residual and Jacobian assembly; the sliding joint's row includes its contact search, the
knot-span lookup at every evaluation), the ghost exchange, the linear solves (factorisations
included), the output, and the rest. Effects the scene does not name have no event and no
row. Times are the largest over the ranks."""
from __future__ import annotations

from typing import TYPE_CHECKING

from .parallel import run_comm

if TYPE_CHECKING:
    from .simulation import Simulation

OUTPUT_EVENT = "SBOutput"


def start_logging() -> None:
    """Turn on the event log of the cost table before the run (PETSc's whole log with -log_view)."""
    from .. import _core

    _core.start_cost_log()


class output_phase:  # noqa: N801 - used as `with output_phase():`, like a function
    """Log event around a write of results (XDMF, CSV, checkpoints). A class, not a generator:
    a record every step enters it a thousand times a second."""

    _event = None

    def __enter__(self) -> None:
        if output_phase._event is None:
            from petsc4py import PETSc

            output_phase._event = PETSc.Log.Event(OUTPUT_EVENT)
        output_phase._event.begin()

    def __exit__(self, *exc: object) -> None:
        output_phase._event.end()


def _perf(name: str) -> tuple[float, int]:
    from mpi4py import MPI

    from .. import _core

    time, count = _core.event_stats(name)
    comm = run_comm()
    t = comm.allreduce(float(time), op=MPI.MAX)
    n = comm.allreduce(int(count), op=MPI.MAX)
    return t, n


def event_time(name: str) -> float:
    """Time in a PETSc log event so far, the largest over the ranks (collective)."""
    return _perf(name)[0]


def cost_breakdown(sim: "Simulation", wall: float) -> list[dict]:
    """Rows {phase, event, time_s, calls, share} for the run so far (collective)."""
    types: list[str] = []
    for e in sim.active_effects:
        if e.type not in types:
            types.append(e.type)
    rows = []
    for t in types:
        label = f"{t} (incl. contact search)" if t == "sliding_joint" else t
        rows.append((f"assembly: {label}", f"SB:{t}"))
    # PETSc starts the KSPSolve event after KSPSetUp: the factorisation (PCSetUp) is logged apart
    rows += [("ghost exchange", "SBGhostUpdate"), ("linear solve (incl. factorisation)", "KSPSolve+PCSetUp"),
             ("output", OUTPUT_EVENT)]
    out = []
    for phase, event in rows:
        perf = [_perf(e) for e in event.split("+")]
        t, n = sum(p[0] for p in perf), perf[0][1]
        out.append({"phase": phase, "event": event, "time_s": t, "calls": n, "share": t / wall if wall > 0 else 0.0})
    rest = max(0.0, wall - sum(r["time_s"] for r in out))
    out.append({"phase": "other (Newton updates, records, Python)", "event": "", "time_s": rest, "calls": 0,
                "share": rest / wall if wall > 0 else 0.0})
    return out


def cost_table(rows: list[dict], wall: float) -> str:
    width = max(len(r["phase"]) for r in rows)
    lines = [f"  {'phase':<{width}}  {'time [s]':>9}  {'share':>6}  {'calls':>8}"]
    for r in rows:
        lines.append(f"  {r['phase']:<{width}}  {r['time_s']:9.3f}  {100 * r['share']:5.1f}%  {r['calls']:8d}")
    lines.append(f"  {'wall time':<{width}}  {wall:9.3f}")
    return "\n".join(lines)
