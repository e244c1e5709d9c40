# SPDX-License-Identifier: MIT
"""Faults a new user meets (issue 22): interrupts, sliders leaving their carriers in static runs,
failed static starts and time roundoff. Every way a run ends leaves a consistent folder:
history, summary saying what happened, the XDMF series and (dynamic runs) a checkpoint."""
from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

from test_restart import assert_same_history, rows
from test_xdmf import read_series

pytestmark = pytest.mark.skip_in_parallel  # each test starts its own processes

ROOT = Path(__file__).resolve().parents[2]


def start(*args: str, cwd: Path) -> subprocess.Popen:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_COMM", "PMIX", "OMPI_MCA_ess", "OMPI_FILE"))}
    return subprocess.Popen([str(ROOT / "scripts" / "slidebeam"), *args], cwd=cwd, env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def wait_for_steps(proc: subprocess.Popen) -> None:
    """Until the run prints its first step line (the model is built, stepping has begun)."""
    assert proc.stdout is not None
    for line in proc.stdout:
        if line.lstrip().startswith("step"):
            return
    raise AssertionError(f"the run ended before stepping: {proc.wait()} {proc.stderr.read() if proc.stderr else ''}")


LONG = ["--set", "analysis.t_end=1000", "--set", "output.every=50"]  # far longer than any test waits


@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_ends_the_run_with_a_consistent_folder(tmp_path, sig, code):
    """SIGINT / SIGTERM during a dynamic run: the run ends after the current step with exit
    128 + signal, and the folder holds history, checkpoint, XDMF and a summary marked incomplete
    with the reason, all at the same last good state."""
    proc = start("run", str(ROOT / "runs" / "pendulum16.toml"), "--out", "o", *LONG, cwd=tmp_path)
    wait_for_steps(proc)
    time.sleep(1.0)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == code, err
    assert "Traceback" not in err and "interrupted by SIG" in err
    out = tmp_path / "o"
    for name in ("history.csv", "summary.json", "checkpoint.h5", "final_configuration.csv", "beams.xdmf", "beams.h5"):
        assert (out / name).is_file(), name
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is False and summary["converged"] is True
    assert summary["stopped"].startswith(f"interrupted by {signal.Signals(sig).name}")
    t = summary["t_reached"]
    assert 0 < t < 1000
    assert float(rows(out / "history.csv")[-1]["t"]) == t
    _, steps = read_series(out / "beams.xdmf")
    assert steps[-1][0] == pytest.approx(t, abs=1e-12)
    # the checkpoint holds that state: a restart goes on from there
    cont = subprocess.run([str(ROOT / "scripts" / "slidebeam"), "run", str(ROOT / "runs" / "pendulum16.toml"),
                           "--restart", "o/checkpoint.h5", "-q", "--set", "output.every=50",
                           "--set", f"analysis.t_end={t + 0.1}"], cwd=tmp_path, capture_output=True, text=True)
    assert cont.returncode == 0, cont.stderr
    assert f"at t = {t:.6g}" in cont.stdout


def test_a_second_sigint_aborts_at_once(tmp_path):
    """The first Ctrl-C asks for a clean stop; a second one ends the process at once (killed by
    SIGINT, no clean-up), even when the first has not been acted on yet."""
    proc = start("run", str(ROOT / "runs" / "pendulum16.toml"), "--out", "o", *LONG, cwd=tmp_path)
    wait_for_steps(proc)
    proc.send_signal(signal.SIGINT)
    t0 = time.perf_counter()
    # Signals sent before the process runs its handler arrive as one (under load that can be tens
    # of milliseconds): repeat until it ends. The first delivered one asks for the clean stop,
    # the next one kills, long before the clean stop (a step, then the output files) is done.
    while proc.poll() is None and time.perf_counter() - t0 < 5.0:
        time.sleep(0.01)
        with contextlib.suppress(ProcessLookupError):
            proc.send_signal(signal.SIGINT)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGINT
    assert time.perf_counter() - t0 < 5.0


def test_a_run_killed_with_sigkill_restarts_to_the_uninterrupted_history(tmp_path):
    """With checkpoint_every, a run killed outright (no clean-up at all) restarts from its last
    checkpoint and ends with the history of the run that was never interrupted."""
    scene = str(ROOT / "runs" / "pendulum16.toml")
    common = ["-q", "--set", "analysis.t_end=30", "--set", "output.every=100", "--set", "output.checkpoint_every=3000"]
    whole = subprocess.run([str(ROOT / "scripts" / "slidebeam"), "run", scene, "--out", "whole", *common],
                           cwd=tmp_path, capture_output=True, text=True)
    assert whole.returncode == 0, whole.stderr
    proc = start("run", scene, "--out", "killed", *common, cwd=tmp_path)
    deadline = time.perf_counter() + 120
    while not (tmp_path / "killed" / "checkpoint.h5").is_file():
        assert proc.poll() is None, "the run ended before its first checkpoint"
        assert time.perf_counter() < deadline
        time.sleep(0.02)
    time.sleep(0.3)
    proc.send_signal(signal.SIGKILL)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    assert not (tmp_path / "killed" / "summary.json").exists()  # killed before the end
    again = subprocess.run([str(ROOT / "scripts" / "slidebeam"), "run", scene, "--restart", "killed/checkpoint.h5",
                            *common], cwd=tmp_path, capture_output=True, text=True)
    assert again.returncode == 0, again.stderr
    a, b = rows(tmp_path / "whole" / "history.csv"), rows(tmp_path / "killed" / "history.csv")
    assert len(a) == len(b) == 301
    assert_same_history(a, b)
    _, steps = read_series(tmp_path / "killed" / "beams.xdmf")
    assert [round(t, 9) for t, _ in steps] == [round(0.1 * k, 9) for k in range(301)]



def test_data_written_after_a_checkpoint_cannot_damage_the_records_before_it(tmp_path):
    """HDF5 files are not crash-safe: a run killed while it writes can leave a group's index
    half-rewritten, which once lost records from before the checkpoint. The records after a
    checkpoint go into a file of their own, so the files before it are never written again, and
    a restart deletes (not repairs) whatever was written after its checkpoint."""
    scene = str(ROOT / "runs" / "pendulum16.toml")
    common = ["-q", "--set", "output.every=100", "--set", "output.checkpoint_every=1000"]
    cli = [str(ROOT / "scripts" / "slidebeam"), "run", scene]

    def run(*args: str) -> None:
        done = subprocess.run([*cli, *common, *args], cwd=tmp_path, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr

    run("--out", "r", "--set", "analysis.t_end=2")
    out = tmp_path / "r"
    before = {p.name: p.read_bytes() for p in out.glob("*.h5") if p.name != "checkpoint.h5"}
    assert sorted(before) == ["beams.1.h5", "beams.h5"]  # t <= 1, then (1, 2]
    (tmp_path / "at2.h5").write_bytes((out / "checkpoint.h5").read_bytes())
    run("--restart", "r/checkpoint.h5", "--set", "analysis.t_end=3")
    assert {p.name: p.read_bytes() for p in out.glob("*.h5") if p.name in before} == before
    new = out / "beams.2.h5"
    _, whole = read_series(out / "beams.xdmf")
    assert [round(t, 9) for t, _ in whole] == [round(0.1 * k, 9) for k in range(31)]
    # as a run killed while writing (2, 3] might leave it: the segment after t = 2 is garbage
    new.write_bytes(b"\x89HDF\r\n\x1a\n" + os.urandom(4096))
    run("--restart", str(tmp_path / "at2.h5"), "--out", "r", "--set", "analysis.t_end=3")
    _, again = read_series(out / "beams.xdmf")
    assert [t for t, _ in again] == [t for t, _ in whole]
    for (_, a), (_, b) in zip(whole, again):
        assert all((a[name] == b[name]).all() for name in a)

RAIL = """
[scene]
name = "rail_static"
[analysis]
type = "static"
steps = 4
[[beam]]
name = "rail"
start = [0.0, 0.0, 0.0]
end = [4.0, 0.0, 0.0]
d2 = [0.0, 1.0, 0.0]
spans = 16
section = { shape = "rectangle", b = 0.05, h = 0.05, E = 2.0e11, nu = 0.3, rho = 7800.0 }
[[beam]]
name = "hanger"
start = [3.9, 0.0, 0.0]
end = [3.9, 0.0, -1.0]
d2 = [1.0, 0.0, 0.0]
spans = 4
section = { shape = "rectangle", b = 0.02, h = 0.02, E = 2.0e11, nu = 0.3, rho = 7800.0 }
[[support]]
type = "clamp"
beam = "rail"
at = "start"
[[support]]
type = "clamp"
beam = "rail"
at = "end"
[[sliding_joint]]
slider = "hanger"
carrier = "rail"
[gravity]
g = [0.0, 0.0, -9.81]
"""


def test_a_static_run_stops_when_a_slider_leaves_its_carrier(run_cli, tmp_path):
    """A pendulum on a clamped rail, static: Newton's first load step puts the slider beyond the
    rail's end (s = 4.008 on a 4 m rail), an equilibrium of the extrapolated spline. The run stops
    there as a dynamic run does: exit 0, converged but not complete, the reason said; the results
    hold the last load step with the slider on the rail. at_carrier_end = "fail": exit 1."""
    (tmp_path / "rail.toml").write_text(RAIL)
    out = run_cli("run", "rail.toml", "--out", "stop", "-q")
    assert out.returncode == 0, out.stderr
    summary = json.loads((tmp_path / "stop" / "summary.json").read_text())
    assert summary["complete"] is False and summary["converged"] is True
    assert "reached the end of carrier 'rail'" in summary["stopped"]
    assert 0.0 <= summary["outputs"]["hanger_on_rail"]["s"] <= 4.0
    assert all(0.0 <= float(r["hanger_on_rail.s"]) <= 4.0 for r in rows(tmp_path / "stop" / "history.csv"))
    fail = run_cli("run", "rail.toml", "--out", "fail", "-q", "--set", 'sliding_joint.0.at_carrier_end="fail"')
    assert fail.returncode == 1 and "reached the end of carrier 'rail'" in fail.stderr
    assert json.loads((tmp_path / "fail" / "summary.json").read_text())["complete"] is False


UNSUPPORTED = """
[scene]
name = "unsupported"
[analysis]
type = "dynamic"
start = "equilibrium"
t_end = 0.01
dt = 1e-3
[[beam]]
name = "rod"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
spans = 4
section = { shape = "circle", r = 0.01, E = 210.0, nu = 0.3, rho = 7800.0 }
[gravity]
g = [0.0, 0.0, -9.81]
"""


def test_a_failed_static_start_leaves_a_consistent_folder_and_names_likely_causes(run_cli, tmp_path):
    """No supports and E typed in GPa: the static start finds no equilibrium. Exit 1, and the
    folder holds the XDMF pair, a history with the initial state and a summary saying what
    happened, with the likely causes (here: no support, E in GPa)."""
    (tmp_path / "s.toml").write_text(UNSUPPORTED)
    out = run_cli("run", "s.toml", "--out", "o", "-q")
    assert out.returncode == 1 and "Traceback" not in out.stderr
    assert "no equilibrium" in out.stderr and "no [[support]]" in out.stderr and "not GPa" in out.stderr
    folder = tmp_path / "o"
    for name in ("beams.xdmf", "beams.h5", "history.csv", "summary.json", "final_configuration.csv"):
        assert (folder / name).is_file(), name
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["complete"] is False and summary["converged"] is False and summary["steps"] == 0
    assert len(summary["likely_causes"]) >= 2
    assert len(rows(folder / "history.csv")) == 1


def test_times_are_multiples_of_the_step(run_cli, root, tmp_path):
    """t_n = n dt, not a running sum: the last time is t_end exactly and every recorded time is
    the step number times dt, in the history and in the XDMF series (static load steps too)."""
    out = run_cli("run", str(root / "runs" / "pendulum16.toml"), "--out", "d", "-q", "--set", "analysis.t_end=3",
                  "--set", "analysis.dt=0.002", "--set", "output.every=100")
    assert out.returncode == 0, out.stderr
    assert json.loads((tmp_path / "d" / "summary.json").read_text())["t_reached"] == 3.0
    hist = rows(tmp_path / "d" / "history.csv")
    assert [float(r["t"]) for r in hist] == [int(r["step"]) * 0.002 for r in hist]
    _, steps = read_series(tmp_path / "d" / "beams.xdmf")
    assert [t for t, _ in steps] == [int(r["step"]) * 0.002 for r in hist]
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "s", "-q", "--set", "analysis.steps=10",
                  "--set", "beam.0.spans=8")
    assert out.returncode == 0, out.stderr
    assert [float(r["t"]) for r in rows(tmp_path / "s" / "history.csv")] == [k * 0.1 for k in range(11)]


def test_check_places_the_sliders_as_run_does(run_cli, root):
    """`check` builds the model: a slider 5 cm off its carrier is refused by check (exit 2, the
    joint named) as by run, not only when the run starts."""
    scene = str(root / "runs" / "seed" / "free_fall_1+4.toml")
    off = ["--set", "beam.1.start=[0.4,0.05,0.0]", "--set", "beam.1.end=[0.4,-0.95,0.0]"]
    out = run_cli("check", scene, *off)
    assert out.returncode == 2 and "[[sliding_joint]] #1" in out.stderr and "0.05 from carrier 'AB'" in out.stderr
    assert "Traceback" not in out.stderr
    assert run_cli("check", scene).returncode == 0


def test_supports_that_repeat_each_other_are_warned_about(run_cli, root, tmp_path):
    """A spherical support where a clamp already holds, or one support twice: a warning naming
    both tables, by check and by run (both would report the same reaction)."""
    text = (root / "runs" / "rollup.toml").read_text()
    (tmp_path / "dup.toml").write_text(text + '\n[[support]]\ntype = "spherical"\nbeam = "strip"\nat = "start"\n')
    out = run_cli("check", "dup.toml")
    assert out.returncode == 0
    assert "warning" in out.stderr and "[[support]] #2 (spherical) repeats what [[support]] #1 (clamp)" in out.stderr
    (tmp_path / "twice.toml").write_text(text + '\n[[support]]\ntype = "clamp"\nbeam = "strip"\nat = "start"\n')
    out = run_cli("run", "twice.toml", "--out", "o", "-q", "--set", "analysis.steps=2", "--set", "beam.0.spans=8")
    assert out.returncode == 0 and "[[support]] #2 (clamp) repeats what [[support]] #1 (clamp)" in out.stderr
    assert "warning" not in run_cli("check", str(root / "runs" / "rollup.toml")).stderr


def test_a_restart_runs_the_scene_of_its_checkpoint(run_cli, root, tmp_path):
    """The checkpoint keeps the effective scene: a restart applies the first run's --set overrides
    again (here output.every = 5, the file says 10) and says what changed; a changed dt is
    warned about, since the run then does not go on as the first one would have."""
    scene = str(root / "runs" / "seed" / "free_fall_inclined_1+4.toml")
    first = run_cli("run", scene, "--out", "r", "-q", "--set", "output.every=5", "--set", "analysis.t_end=0.05")
    assert first.returncode == 0, first.stderr
    again = run_cli("run", scene, "--restart", "r/checkpoint.h5", "-q", "--set", "analysis.t_end=0.1")
    assert again.returncode == 0, again.stderr
    assert "--set output.every=5" in again.stdout and "analysis.t_end: 0.05 -> 0.1" in again.stdout
    steps = [int(r["step"]) for r in rows(tmp_path / "r" / "history.csv")]
    assert steps == list(range(0, 101, 5))
    dt = run_cli("run", scene, "--restart", "r/checkpoint.h5", "-q", "--set", "analysis.t_end=0.12",
                 "--set", "analysis.dt=5e-4")
    assert dt.returncode == 0, dt.stderr
    assert "warning" in dt.stderr and "analysis.dt: 0.001 -> 0.0005" in dt.stderr
