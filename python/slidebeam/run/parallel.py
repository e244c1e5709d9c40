# SPDX-License-Identifier: MIT
"""The communicator a run works on: MPI's world, or one rank's own when a scene too small to gain
from distribution runs on rank 0 alone (-sb_serial_below; the other ranks wait for it). Every
collective of the run (output, checkpoints, stop signals, cost tables) goes over run_comm()."""
from __future__ import annotations

import contextlib
import time
from collections.abc import Iterator
from typing import Any

_run_comm: Any = None


def run_comm() -> Any:
    """The run's mpi4py communicator (default: COMM_WORLD)."""
    if _run_comm is not None:
        return _run_comm
    from mpi4py import MPI

    return MPI.COMM_WORLD


@contextlib.contextmanager
def running_on(comm: Any) -> Iterator[None]:
    """Run the body with comm as the run's communicator."""
    global _run_comm
    saved, _run_comm = _run_comm, comm
    try:
        yield
    finally:
        _run_comm = saved


_others_waiting = False


@contextlib.contextmanager
def running_alone() -> Iterator[None]:
    """Rank 0 runs the body on its own (COMM_SELF) while the other ranks wait for it in a
    barrier; they are released when the body ends, however it ends."""
    global _others_waiting
    from mpi4py import MPI

    _others_waiting = True
    try:
        with running_on(MPI.COMM_SELF):
            yield
    finally:
        release_waiting_ranks()


def release_waiting_ranks() -> None:
    """Let the ranks that wait for rank 0's run alone go (once; nothing otherwise). Also called
    by an exit that cannot wait for the body's end (a failed write)."""
    global _others_waiting
    if not _others_waiting:
        return
    _others_waiting = False
    from mpi4py import MPI

    MPI.COMM_WORLD.Ibarrier().Wait()


def wait_sleeping(comm: Any) -> None:
    """Wait in a barrier of comm until the rank doing the work enters it, sleeping between
    checks: polling MPI would keep this rank's core busy, the core the working rank may need."""
    request = comm.Ibarrier()
    while not request.Test():
        time.sleep(0.01)


def _core_bool(name: str) -> bool:
    """The bool option -sb_<name>, or its default in the core (_core.<NAME>)."""
    from petsc4py import PETSc

    from .. import _core

    return bool(PETSc.Options().getBool(f"sb_{name}", getattr(_core, name.upper())))


def statics_on_rank_0() -> bool:
    """-sb_statics_on_rank_0: static analyses of a distributed run on rank 0 alone."""
    return _core_bool("statics_on_rank_0")


def equilibrium_on_rank_0() -> bool:
    """-sb_equilibrium_on_rank_0: the static start of a distributed dynamic run on rank 0 alone."""
    return _core_bool("equilibrium_on_rank_0")


def _core_int(name: str) -> int:
    """The int option -sb_<name>, or its default in the core (_core.<NAME>)."""
    from petsc4py import PETSc

    from .. import _core

    return int(PETSc.Options().getInt(f"sb_{name}", getattr(_core, name.upper())))


def serial_above_cut() -> int:
    """-sb_serial_above_cut: a model whose split would leave a rank more control points next to
    another rank's is owned by rank 0 alone (0: no limit)."""
    return _core_int("serial_above_cut")


def serial_below() -> int:
    """-sb_serial_below: a model with fewer unknowns runs on one rank (0: always distribute)."""
    return _core_int("serial_below")
