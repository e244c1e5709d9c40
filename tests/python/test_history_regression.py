# SPDX-License-Identifier: MIT
"""scripts/history_regression.py, the check that a refactoring changed no shipped scene's
history: its comparison finds a change in any numeric column, a changed ending and another
number of records, and passes identical runs."""
from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))

import history_regression  # noqa: E402


def write_run(folder: Path, rows: list[tuple[float, float, str]], message: str = "completed") -> Path:
    folder.mkdir(parents=True)
    (folder / "summary.json").write_text(json.dumps({"complete": message == "completed", "message": message}))
    lines = ["# a comment line", "t,kinetic_energy,reason"] + [f"{t!r},{k!r},{r}" for t, k, r in rows]
    (folder / "history.csv").write_text("\n".join(lines) + "\n")
    return folder


def test_the_comparison_finds_what_changed(tmp_path):
    rows = [(0.0, 0.0, "initial"), (0.1, 2.5, "CONVERGED_FNORM_ABS"), (0.2, 3.0, "CONVERGED_FNORM_ABS")]
    ref = write_run(tmp_path / "ref", rows)
    assert history_regression.compare(ref, write_run(tmp_path / "same", rows), 1e-12) == (True, "identical")
    nudged = [rows[0], rows[1], (0.2, 3.0 * (1 + 1e-10), "CONVERGED_FNORM_ABS")]
    same, what = history_regression.compare(ref, write_run(tmp_path / "nudged", nudged), 1e-12)
    assert not same and "kinetic_energy row 2" in what
    assert history_regression.compare(ref, write_run(tmp_path / "loose", nudged), 1e-9)[0]
    assert not history_regression.compare(ref, write_run(tmp_path / "short", rows[:2]), 1e-12)[0]
    ended = write_run(tmp_path / "ended", rows, "Newton failed at step 2")
    assert history_regression.compare(ref, ended, 1e-12) == (False, "complete: True -> False")


def test_every_shipped_scene_is_listed():
    listed = {p.relative_to(ROOT / "runs").as_posix() for p in history_regression.scenes()}
    assert "seed/free_fall_1+4.toml" in listed and "cables/cable_swing.toml" in listed
    assert not any(p.startswith("studies/") for p in listed)  # study files have no [scene]


def test_the_floor_judges_roundoff_columns_against_the_run(tmp_path):
    """A column at roundoff level (here 1e-12 against values of order 1) differs by its own size
    from one build to the next: against its own scale that is a difference of order 1, against
    1e-3 of the run's largest value it is none."""
    def run_with(error: float, name: str) -> Path:
        folder = tmp_path / name
        folder.mkdir()
        (folder / "summary.json").write_text(json.dumps({"complete": True, "message": "completed"}))
        (folder / "history.csv").write_text(f"t,kinetic_energy,energy_balance_error\n0.0,2.0,0.0\n0.1,2.5,{error!r}\n")
        return folder

    ref, new = run_with(1e-12, "ref"), run_with(-1e-12, "new")
    same, what = history_regression.compare(ref, new, 1e-8)
    assert not same and "energy_balance_error" in what
    assert history_regression.compare(ref, new, 1e-8, floor=1e-3)[0]
    assert not history_regression.compare(ref, run_with(1e-3, "big"), 1e-8, floor=1e-3)[0]
