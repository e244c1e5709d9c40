# SPDX-License-Identifier: MIT
"""Small scenes under mpirun (-sb_serial_below): a model with fewer unknowns than the threshold is
owned by rank 0 alone, its solve is the serial one (block Jacobi's one block, solved exactly,
no Krylov iterations), and the run equals the serial run. Meaningful under mpirun -n 2."""
from __future__ import annotations

from pathlib import Path

import pytest
from mpi4py import MPI

import slidebeam
from checks import distributed_and_serial_records
from conftest import DISTRIBUTE
from test_condensation import petsc_options

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "runs" / "seed" / "free_fall_1+4.toml"


def seed() -> slidebeam.Scene:
    return slidebeam.load_scene(SEED, ["analysis.t_end=0.1"])


def test_a_small_model_is_owned_by_rank_0_alone():
    with petsc_options(sb_serial_below="1500"):
        sim = slidebeam.Simulation(seed(), MPI.COMM_WORLD)
        lo, hi = sim.x.getOwnershipRange()
        size = sim.x.getSize()
        assert size < 1500
        assert (lo, hi) == ((0, size) if MPI.COMM_WORLD.Get_rank() == 0 else (size, size))
        pairs = distributed_and_serial_records(seed())
        assert pairs


def test_the_threshold_and_its_off_switch():
    """At or above the threshold (here: 0, the tests' default under mpirun) every rank owns a part."""
    with petsc_options(sb_serial_below="100"):  # the seed scene has 166 unknowns
        sim = slidebeam.Simulation(seed(), MPI.COMM_WORLD)
        lo, hi = sim.x.getOwnershipRange()
        assert hi > lo or MPI.COMM_WORLD.Get_size() == 1
    assert DISTRIBUTE == ("-sb_serial_below", "0")


@pytest.mark.skip_in_parallel
@pytest.mark.spawns_ranks
def test_small_scenes_under_mpirun_are_owned_by_rank_0(run_cli, tmp_path):
    """The CLI on 2 ranks with the default threshold: the seed scene's history equals the serial one."""
    common = ["--set", "analysis.t_end=0.1", "--set", "output.xdmf=false", "-q"]
    one = run_cli("run", str(SEED), "--out", "one", *common)
    two = run_cli("run", str(SEED), "--out", "two", *common, "--", "-sb_serial_below", "1500", np=2)
    assert one.returncode == 0 and two.returncode == 0, two.stderr
    from test_restart import rows

    a, b = rows(tmp_path / "one" / "history.csv"), rows(tmp_path / "two" / "history.csv")
    assert len(a) == len(b) > 5 and a[0].keys() == b[0].keys()
    # the two solve paths stop at different Newton iterates, within the Newton tolerance (the
    # reactions, from the multipliers, feel it most: 1e-9 N)
    solver = {"reason", "newton_iterations", "residual_norm"}
    for ra, rb in zip(a, b):
        for key in ra.keys() - solver:
            x, y = float(ra[key]), float(rb[key])
            assert abs(x - y) <= 1e-8 * max(1.0, abs(x)), (ra["t"], key, x, y)


@pytest.mark.skip_in_parallel
@pytest.mark.spawns_ranks
def test_a_static_analysis_under_mpirun_runs_on_rank_0(run_cli, tmp_path):
    """A static analysis has no distributed path that pays: under mpirun rank 0 runs it alone
    at any size (here distributed otherwise: -sb_serial_below 0), and its history is the serial
    one; -sb_statics_on_rank_0 false distributes it (MUMPS)."""
    from test_restart import rows

    scene = str(ROOT / "runs" / "rollup.toml")
    common = ["-q", "--set", "analysis.steps=4", "--set", "output.xdmf=false"]
    one = run_cli("run", scene, "--out", "one", *common)
    two = run_cli("run", scene, "--out", "two", *common, "--", "-sb_serial_below", "0", np=2)
    spread = run_cli("run", scene, "--out", "spread", *common, "--", "-sb_serial_below", "0",
                     "-sb_statics_on_rank_0", "false", np=2)
    assert one.returncode == two.returncode == spread.returncode == 0, two.stderr + spread.stderr
    assert "a static analysis: rank 0 runs the scene alone" in two.stdout
    assert "rank 0 runs the scene alone" not in spread.stdout
    a, b = rows(tmp_path / "one" / "history.csv"), rows(tmp_path / "two" / "history.csv")
    assert len(a) == len(b) == 5 and a == b


@pytest.mark.skip_in_parallel
@pytest.mark.spawns_ranks
def test_sigterm_to_mpirun_stops_a_run_on_rank_0_alone_cleanly(tmp_path):
    """mpirun passes SIGTERM to every rank: the waiting rank ignores it, rank 0 stops after its
    step and writes a consistent folder, and every rank ends."""
    import json
    import signal
    import time

    from test_faults import LONG, wait_for_steps

    import os
    import subprocess

    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_COMM", "PMIX", "OMPI_MCA_ess", "OMPI_FILE"))}
    proc = subprocess.Popen(["mpirun", "--oversubscribe", "-n", "2", str(ROOT / "scripts" / "slidebeam"), "run",
                             str(ROOT / "runs" / "pendulum16.toml"), "--out", "o", *LONG, "--", "-sb_serial_below",
                             "1500"], cwd=tmp_path, env=env, text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wait_for_steps(proc)
    time.sleep(1.0)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert "Traceback" not in err and "interrupted by SIGTERM" in err, err
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["complete"] is False and summary["stopped"].startswith("interrupted by SIGTERM")
    assert (tmp_path / "o" / "checkpoint.h5").is_file() and (tmp_path / "o" / "history.csv").is_file()


@pytest.mark.skip_in_parallel
@pytest.mark.spawns_ranks
def test_a_checkpoint_of_a_run_on_rank_0_alone_restarts_distributed(run_cli, tmp_path):
    """Rank 0 alone writes the checkpoint with its own communicator; a distributed restart on 2
    ranks reads it and goes on as the serial run that never stopped (to 1e-8: the solve paths
    differ)."""
    from test_restart import rows

    common = ["-q", "--set", "output.every=10", "--set", "output.xdmf=false"]
    first = run_cli("run", str(SEED), "--out", "parts", *common, "--set", "analysis.t_end=0.1",
                    "--", "-sb_serial_below", "1500", np=2)
    assert first.returncode == 0 and "rank 0 runs the scene alone" in first.stdout, first.stderr
    second = run_cli("run", str(SEED), "--restart", "parts/checkpoint.h5", *common, "--set", "analysis.t_end=0.2",
                     np=2)  # (run_cli distributes under mpirun: -sb_serial_below 0)
    assert second.returncode == 0 and "rank 0 runs the scene alone" not in second.stdout, second.stderr
    whole = run_cli("run", str(SEED), "--out", "whole", *common, "--set", "analysis.t_end=0.2")
    assert whole.returncode == 0, whole.stderr
    a, b = rows(tmp_path / "whole" / "history.csv"), rows(tmp_path / "parts" / "history.csv")
    assert len(a) == len(b) == 21
    for ra, rb in zip(a, b):
        for key in ("total_energy", "kinetic_energy", "CM@1.x", "CM@1.z", "CM_on_AB.s"):
            assert abs(float(ra[key]) - float(rb[key])) <= 1e-8 * max(1.0, abs(float(ra[key]))), (ra["t"], key)


@pytest.mark.skipif(MPI.COMM_WORLD.Get_size() != 2, reason="two ranks: mpirun -n 2")
@pytest.mark.parametrize("scene_file, sets, coupled", [
    # two carriers with their hangers: the split of the numbering falls between them
    (ROOT / "runs" / "cables" / "ropeway.toml", ["analysis.t_end=0.004"], False),
    # one carrier and its slider, cut across the carrier
    (ROOT / "runs" / "hard" / "slider_skips_spans.toml", ["analysis.t_end=0.004"], True),
])
def test_uncoupled_ranks_solve_with_one_application(scene_file, sets, coupled):
    """When no Jacobian entry couples the ranks' unknowns, block Jacobi with exact blocks is the
    exact solve: one application per Newton step (KSPPREONLY), the run as the serial one to 1e-10.
    Where the ranks are coupled, the coupling correction makes one application exact
    (tests/python/test_coupling_correction.py)."""
    from petsc4py import PETSc

    scene = slidebeam.load_scene(scene_file, sets)
    sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
    assert sim.run_dynamic().complete
    ksp = sim.snes.getKSP()
    assert ksp.getType() == PETSc.KSP.Type.PREONLY
    assert ksp.getIterationNumber() == 1
    solves = sim.integrator.parallel_solves
    jacobians = sim.integrator.jacobian_evaluations
    assert (solves["corrected"], solves["blocks"]) == ((jacobians, 0) if coupled else (0, jacobians))
    assert solves["krylov"] == 0 and (solves["coupled_rows"] > 0) == coupled
    distributed_and_serial_records(scene)
