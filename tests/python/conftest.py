# SPDX-License-Identifier: MIT
"""Test set-up: import the package from python/, initialise PETSc once, keep ranks in step."""
from __future__ import annotations

import contextlib
import gc
import os
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")

import petsc4py  # noqa: E402

petsc4py.init([])
from mpi4py import MPI  # noqa: E402
from petsc4py import PETSc  # noqa: E402, F401

# Under mpirun the tests' scenes, small, would be owned by rank 0 alone (-sb_serial_below): the
# rank-equality tests are about the distributed solve, so they distribute whatever the size.
# test_parallel_small.py checks the one-owner layout itself.
DISTRIBUTE = ("-sb_serial_below", "0")
if MPI.COMM_WORLD.Get_size() > 1:
    PETSc.Options().setValue(*DISTRIBUTE)


@contextlib.contextmanager
def petsc_options(**options: str) -> Iterator[None]:
    """These PETSc options in the database for the block (a Simulation built in it reads them),
    removed afterwards."""
    for k, v in options.items():
        PETSc.Options().setValue(k, v)
    try:
        yield
    finally:
        for k in options:
            PETSc.Options().delValue(k)


def pytest_configure(config: pytest.Config) -> None:
    if MPI.COMM_WORLD.Get_size() > 1 and not config.option.basetemp:
        # one temporary tree per rank: ranks must not clean up each other's folders
        config.option.basetemp = f"/tmp/slidebeam-pytest-{os.getpid()}-rank{MPI.COMM_WORLD.Get_rank()}"
    config.addinivalue_line("markers", "skip_in_parallel: only meaningful on one rank (spawns its own processes, "
                                       "or checks a closed form that other tests run on 2 ranks)")
    config.addinivalue_line("markers", "spawns_ranks: starts an mpirun of its own; scripts/test.sh runs these apart "
                                       "from the others, whose processes would starve its ranks")
    config.addinivalue_line("markers", "stability: the hard-case suite of runs/hard/ (issue 8; a few minutes)")
    config.addinivalue_line("markers", "one_case_in_parallel: of a parametrized test, only the first case runs "
                                       "under mpirun (the cases differ in what the serial pass checks, not in "
                                       "how the run is distributed)")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if MPI.COMM_WORLD.Get_size() == 1:
        return
    seen: set[tuple[str, str]] = set()
    for item in items:
        if not item.get_closest_marker("one_case_in_parallel"):
            continue
        function = (item.nodeid.split("::")[0], getattr(item, "originalname", item.name))
        if function in seen:
            item.add_marker(pytest.mark.skip(reason="one case of this test runs under mpirun"))
        seen.add(function)


def pytest_runtest_setup(item: pytest.Item) -> None:
    if item.get_closest_marker("skip_in_parallel") and MPI.COMM_WORLD.Get_size() > 1:
        pytest.skip("runs only in serial")


def pytest_runtest_teardown(item: pytest.Item) -> None:
    # PETSc destructors are collective: collect on every rank before the next test starts.
    gc.collect()
    MPI.COMM_WORLD.Barrier()


@pytest.fixture
def root() -> Path:
    return ROOT


@pytest.fixture
def run_cli(tmp_path: Path):
    """Run scripts/slidebeam in a subprocess (optionally under mpirun)."""
    import subprocess

    def run(*args: str, np: int = 1, cwd: Path | None = None, timeout: float = 600) -> subprocess.CompletedProcess:
        cmd = [str(ROOT / "scripts" / "slidebeam"), *args]
        if np > 1:
            cmd = ["mpirun", "--oversubscribe", "-n", str(np), *cmd]
        env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_COMM", "PMIX", "OMPI_MCA_ess", "OMPI_FILE"))}
        if np > 1 and not any("sb_serial_below" in a for a in args):
            env["PETSC_OPTIONS"] = " ".join([env.get("PETSC_OPTIONS", ""), *DISTRIBUTE]).strip()
        if np > 1:
            # ranks that wait yield the core: beside the suite's other worker the cores are
            # oversubscribed without mpirun knowing it, and busy-polling ranks starved each
            # other (the 3-rank history test took 82 s instead of 5)
            env["OMPI_MCA_mpi_yield_when_idle"] = "1"
        return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd or tmp_path, env=env, timeout=timeout)

    return run
