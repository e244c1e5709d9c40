# SPDX-License-Identifier: MIT
"""Checkpoint and restart (issue 5): a run stopped and restarted from its checkpoint writes the
history and the XDMF series of the run that went on, and a checkpoint that does not fit the
scene is a clear error."""
from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from test_xdmf import read_series

pytestmark = pytest.mark.skip_in_parallel  # each test starts its own processes


def rows(path):
    return list(csv.DictReader(path.open()))


def assert_same_history(a: list[dict], b: list[dict]) -> None:
    """Two history.csv row lists agree: the same columns, the same reasons, numbers to 1e-12."""
    for ra, rb in zip(a, b):
        assert ra.keys() == rb.keys()
        for key in ra:
            if key == "reason":
                assert ra[key] == rb[key]
                continue
            x, y = float(ra[key]), float(rb[key])
            assert abs(x - y) <= 1e-12 * max(1.0, abs(x)), (ra["t"], key, x, y)


def test_a_restart_keeps_the_default_output_interval(run_cli, root, tmp_path):
    """Without output.every the interval follows t_end (about 200 records): a restart to a later
    t_end records at the interval of the run that wrote the checkpoint, as that run would have."""
    text = (root / "runs" / "seed" / "free_fall_1+4.toml").read_text()
    scene = tmp_path / "seed.toml"
    scene.write_text("\n".join(line for line in text.splitlines() if not line.startswith("every")))
    common = ["-q", "--set", "output.xdmf=false"]
    first = run_cli("run", str(scene), "--out", "parts", *common, "--set", "analysis.t_end=0.5")  # 500 steps: every 2
    assert first.returncode == 0, first.stderr
    second = run_cli("run", str(scene), "--restart", "parts/checkpoint.h5", *common, "--set", "analysis.t_end=1.0")
    assert second.returncode == 0, second.stderr
    whole = run_cli("run", str(scene), "--out", "whole", *common, "--set", "analysis.t_end=1.0",
                    "--set", "output.every=2")  # (1000 steps alone would record every 5th)
    assert whole.returncode == 0, whole.stderr
    a, b = rows(tmp_path / "whole" / "history.csv"), rows(tmp_path / "parts" / "history.csv")
    assert len(a) == len(b) == 501
    assert_same_history(a, b)


@pytest.mark.parametrize("integrator", ["energy-momentum", "newmark"])
def test_restarted_run_equals_the_uninterrupted_one(run_cli, root, tmp_path, integrator):
    """S2-incl (sliding joint, knot crossing near t = 0.2) to t = 0.3 in one go, and to 0.15 then
    restarted to 0.3: history and series agree to 1e-12 (the Newmark run also restores a)."""
    scene = str(root / "runs" / "seed" / "free_fall_inclined_1+4.toml")
    common = ["-q", "--set", f'analysis.integrator="{integrator}"', "--set", "output.every=10"]
    whole = run_cli("run", scene, "--out", "whole", *common, "--set", "analysis.t_end=0.3")
    assert whole.returncode == 0, whole.stderr
    first = run_cli("run", scene, "--out", "parts", *common, "--set", "analysis.t_end=0.15")
    assert first.returncode == 0, first.stderr
    assert (tmp_path / "parts" / "checkpoint.h5").is_file()
    second = run_cli("run", scene, "--restart", "parts/checkpoint.h5", *common, "--set", "analysis.t_end=0.3")
    assert second.returncode == 0, second.stderr
    assert "restarting from parts/checkpoint.h5 at t = 0.15 (step 150)" in second.stdout
    a, b = rows(tmp_path / "whole" / "history.csv"), rows(tmp_path / "parts" / "history.csv")
    assert len(a) == len(b) == 31
    assert_same_history(a, b)
    sa = json.loads((tmp_path / "whole" / "summary.json").read_text())
    sb = json.loads((tmp_path / "parts" / "summary.json").read_text())
    assert sa["steps"] == sb["steps"] == 300 and sa["newton_iterations"] == sb["newton_iterations"]
    # the restarted history's wall time is both runs': the restart's own is reported apart
    assert "wall_time_this_run_s" in sb and "wall_time_this_run_s" not in sa
    assert sb["wall_time_s"] > sb["wall_time_this_run_s"] > 0.0
    for series in ("beams.xdmf", "sliders.xdmf", "masses.xdmf"):
        pa, steps_a = read_series(tmp_path / "whole" / series)
        pb, steps_b = read_series(tmp_path / "parts" / series)
        assert np.array_equal(pa, pb) and len(steps_a) == len(steps_b) == 31
        for (ta, da), (tb, db) in zip(steps_a, steps_b):
            assert ta == pytest.approx(tb, abs=1e-15)
            for key in da:
                assert np.abs(da[key] - db[key]).max() <= 1e-12 * max(1.0, np.abs(da[key]).max()), (series, key)


def test_periodic_checkpoints_and_the_last_good_state(run_cli, root, tmp_path):
    """checkpoint_every writes along the run; after a Newton failure the checkpoint holds the
    last good state, from which a restart with smaller steps goes on (the first run's overrides
    apply again, so its dt_min = 0.05 is lowered too)."""
    scene = str(root / "runs" / "flying_spaghetti_2d.toml")
    out = run_cli("run", scene, "--out", "nm", "-q", "--set", 'analysis.integrator="newmark"',
                  "--set", "analysis.dt_min=0.05", "--set", "output.checkpoint_every=5")
    assert out.returncode == 1 and "Newton failed" in out.stderr
    summary = json.loads((tmp_path / "nm" / "summary.json").read_text())
    import h5py

    with h5py.File(tmp_path / "nm" / "checkpoint.h5", "r") as f:
        assert f["slidebeam"].attrs["step"] == summary["steps"]
        assert f["slidebeam"].attrs["t"] == pytest.approx(summary["t_reached"])
    again = run_cli("run", scene, "--restart", "nm/checkpoint.h5", "--out", "nm2", "-q",
                    "--set", 'analysis.integrator="newmark"', "--set", "analysis.t_end=" + str(summary["t_reached"] + 0.05),
                    "--set", "analysis.dt=0.01", "--set", "analysis.dt_min=1e-4")
    assert again.returncode == 0, again.stderr
    resumed = json.loads((tmp_path / "nm2" / "summary.json").read_text())
    assert resumed["complete"] and resumed["steps"] > summary["steps"]


@pytest.mark.parametrize("args, words", [
    (["--restart", "nowhere.h5"], "does not exist"),
    (["--restart", "ok/checkpoint.h5", "--set", "beam.AB.spans=8"], "unknowns"),
    (["--restart", "ok/checkpoint.h5", "--set", 'analysis.integrator="hht"'], "energy-momentum integrator"),
    (["--restart", "ok/history.csv"], "checkpoint"),
])
def test_checkpoints_that_do_not_fit_are_clear_errors(run_cli, root, tmp_path, args, words):
    scene = str(root / "runs" / "seed" / "free_fall_1+1.toml")
    ok = run_cli("run", scene, "--out", "ok", "-q", "--set", "analysis.t_end=0.01")
    assert ok.returncode == 0, ok.stderr
    bad = run_cli("run", scene, "-q", "--out", "bad", *args)
    assert bad.returncode == 2, bad.stderr
    assert words in bad.stderr and "Traceback" not in bad.stderr


def test_static_runs_cannot_restart(run_cli, root):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--restart", "x.h5")
    assert out.returncode == 2 and "dynamic runs only" in out.stderr


def test_a_checkpoint_keeps_the_records_exactly_and_older_checkpoints_still_read(root, tmp_path):
    """The records come back from a checkpoint bit for bit (joints, reactions, energy flows);
    a checkpoint of format 1, with its records as JSON, reads to the same records; one whose
    records lack the sliding joints' outputs (an earlier version's) is refused by name."""
    import dataclasses

    import h5py

    import slidebeam
    from slidebeam.output.checkpoint import CheckpointError, read_checkpoint, write_checkpoint

    scene = slidebeam.load_scene(root / "runs" / "effects" / "ropeway.toml", ["analysis.t_end=0.02", "output.every=1"])
    sim = slidebeam.Simulation(scene)
    outcome = sim.run_dynamic()
    assert outcome.records[-1].joints and outcome.records[-1].reactions and outcome.records[-1].flows
    path = tmp_path / "checkpoint.h5"
    write_checkpoint(sim, outcome.state, path)
    flows = len(sim.integrator.energy_flows)

    def plain(records):  # the initial record's empty flows are read back as zeros
        return [dataclasses.replace(r, flows=r.flows or [0.0] * flows) for r in records]

    assert read_checkpoint(sim, path).records == plain(outcome.state.records)
    with h5py.File(path, "a") as f:
        g = f["slidebeam"]
        old = [dataclasses.asdict(r) for r in outcome.state.records]
        for name in ("history", "history_reasons"):
            del g[name]
        del g.attrs["history_layout"]
        g.attrs["records"] = json.dumps(old)
        g.attrs["format"] = 1
    assert read_checkpoint(sim, path).records == outcome.state.records
    with h5py.File(path, "a") as f:  # an earlier version's: the sliding joints' values not among the outputs
        f["slidebeam"].attrs["records"] = json.dumps([dict(r, outputs=[]) for r in old])
    with pytest.raises(CheckpointError, match="earlier version kept the sliding joints'"):
        read_checkpoint(sim, path)


def test_a_checkpoint_is_committed_after_its_before_commit_step(root, tmp_path):
    """write_checkpoint renames its file into place only after before_commit has run, and even if
    it fails. At the end of a run the CLI closes the XDMF output there: a run killed while its
    writers finish keeps the previous checkpoint, whose restart writes the records after it
    again, instead of a final checkpoint beside a damaged last .h5."""
    import slidebeam
    from slidebeam.output.checkpoint import read_checkpoint, write_checkpoint

    scene = slidebeam.load_scene(root / "runs" / "seed" / "free_fall_1+4.toml", ["analysis.t_end=0.005"])
    sim = slidebeam.Simulation(scene)
    outcome = sim.run_dynamic()
    path = tmp_path / "checkpoint.h5"
    seen = []

    def full_disk() -> None:
        seen.append(path.exists())
        raise OSError("No space left on device")

    with pytest.raises(OSError, match="No space"):
        write_checkpoint(sim, outcome.state, path, before_commit=full_disk)
    assert seen == [False]
    assert read_checkpoint(sim, path).records[-1].t == outcome.state.records[-1].t
