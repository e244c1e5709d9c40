# SPDX-License-Identifier: MIT
"""Stop a run cleanly on SIGINT (Ctrl-C) or SIGTERM.

While :func:`stop_on_signals` is active, the first SIGINT or SIGTERM only records a request:
the step loops poll :func:`requested` after each step (the static start after each continuation
step) and end the run as if it had reached a stop, so that history, checkpoint, XDMF and summary
are written for the last good state. The handler of that signal is then reset to the system
default, so a second one ends the process at once. The handlers are the core's (C), not
Python's: a Python handler runs only between bytecodes, so a second Ctrl-C during a long solve
would wait for it.

Under mpirun a signal may reach some ranks only, or at different steps: :func:`requested` agrees
across ranks (a reduction), so every rank stops after the same step.
"""
from __future__ import annotations

import contextlib
import signal
from typing import Iterator

from .parallel import run_comm

_handled = (signal.SIGINT, signal.SIGTERM)
_active = False


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM request a clean stop instead of raising
    KeyboardInterrupt or ending the process."""
    global _active
    from .. import _core

    previous = {s: signal.getsignal(s) for s in _handled}
    _core.install_stop_handlers()
    _active = True
    try:
        yield
    finally:
        _active = False
        for s, handler in previous.items():
            signal.signal(s, handler if handler is not None else signal.SIG_DFL)


def requested(comm: object | None = None) -> int | None:
    """The signal that asked for a stop (on any rank of comm; collective when comm has more than
    one rank), or None. Always None outside :func:`stop_on_signals`."""
    if not _active:
        return None
    from mpi4py import MPI

    from .. import _core

    comm = run_comm() if comm is None else comm
    mine = _core.stop_signal()
    if comm.Get_size() == 1:  # type: ignore[attr-defined]
        return mine or None
    return comm.allreduce(mine, op=MPI.MAX) or None  # type: ignore[attr-defined]


def describe(signum: int) -> str:
    return {signal.SIGINT: "SIGINT (Ctrl-C)", signal.SIGTERM: "SIGTERM"}.get(signum, f"signal {signum}")


def exit_code(signum: int) -> int:
    """The shell's convention for a process ended by a signal: 128 + its number."""
    return 128 + int(signum)
