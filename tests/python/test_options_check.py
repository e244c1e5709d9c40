# SPDX-License-Identifier: MIT
"""Typos in PETSc options (issue 22, item 8): every option given to a run that nothing read is a
warning naming it, where it came from and the closest known option, and is listed in
summary.json; the run still succeeds. Options read late or harmless give no warning."""
from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.skip_in_parallel  # each test starts its own processes

ROOT = Path(__file__).resolve().parents[2]
STATIC = ["--set", "analysis.steps=2", "--set", "beam.0.spans=6", "-q"]
DYNAMIC = ["--set", "analysis.t_end=0.004", "-q"]  # runs/seed/free_fall_1+4.toml: two steps of 2e-3


def warnings(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if "warning" in line]


def test_typo_on_the_command_line_is_a_warning_with_the_closest_option(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "res", *STATIC, "--",
                  "-snes_monitr", "-ksp_gmres_restart", "30", "-snes_monitor")
    assert out.returncode == 0, out.stderr
    assert "Traceback" not in out.stderr
    assert ("slidebeam: warning: PETSc option -snes_monitr from the command line was never used "
            "(did you mean -snes_monitor?)") in out.stderr
    # a real option of a solver this run does not use (GMRES; the run solves with LU)
    assert re.search(r"-ksp_gmres_restart .*never used \(it applies to a solver", out.stderr)
    assert len(warnings(out.stderr)) == 2
    summary = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert summary["complete"]
    unused = {u["option"]: u for u in summary["unused_petsc_options"]}
    assert set(unused) == {"-snes_monitr", "-ksp_gmres_restart"}
    assert unused["-snes_monitr"]["did_you_mean"] == "-snes_monitor"
    assert unused["-snes_monitr"]["source"] == "the command line"
    assert unused["-ksp_gmres_restart"]["known"] and unused["-ksp_gmres_restart"]["value"] == "30"


def test_typo_in_the_scene_petsc_table_and_options_file_names_the_file(run_cli, root, tmp_path):
    """A dynamic run; the table's option as written there (no dash), the options file by name."""
    scene = tmp_path / "fall.toml"
    scene.write_text((root / "runs" / "seed" / "free_fall_1+4.toml").read_text()
                     + "\n[petsc]\nsnes_rtoll = 1e-8\nsnes_max_it = 40\n")
    (tmp_path / "fall.opts").write_text("# beside the scene\n-snes_linesearch_typ basic\n-ksp_type preonly\n")
    out = run_cli("run", str(scene), "--out", "res", *DYNAMIC)
    assert out.returncode == 0, out.stderr
    assert ("slidebeam: warning: PETSc option snes_rtoll from the [petsc] table of " in out.stderr
            and "fall.toml was never used (did you mean snes_rtol?)" in out.stderr)
    assert re.search(r"PETSc option -snes_linesearch_typ from the options file \S*fall\.opts of the scene was "
                     r"never used \(did you mean -snes_linesearch_type\?\)", out.stderr)
    assert len(warnings(out.stderr)) == 2
    summary = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert summary["complete"]
    assert sorted(u["option"] for u in summary["unused_petsc_options"]) == ["-snes_linesearch_typ", "snes_rtoll"]


def test_typo_in_a_command_line_options_file_names_it(run_cli, root, tmp_path):
    (tmp_path / "my.opts").write_text("-snes_max_it 30\n-pc_factr_mat_solver_type mumps\n")
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "res", *STATIC, "--", "-options_file", "my.opts")
    assert out.returncode == 0, out.stderr
    assert ("PETSc option -pc_factr_mat_solver_type from the options file my.opts was never used "
            "(did you mean -pc_factor_mat_solver_type?)") in out.stderr
    assert len(warnings(out.stderr)) == 1


@pytest.mark.parametrize("options", (["-log_view"], ["-snes_monitor"], ["-snes_test_jacobian", "-log_view"],
                                     ["-options_left", "-options_view", "-malloc_dump", "-on_error_abort",
                                      "-no_signal_handler", "-memory_view"]))
def test_options_read_late_or_harmless_give_no_warning(run_cli, root, tmp_path, options):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "res", *STATIC, "--", *options)
    assert out.returncode == 0, out.stderr
    assert not warnings(out.stderr), out.stderr
    assert json.loads((tmp_path / "res" / "summary.json").read_text())["unused_petsc_options"] == []


SCENES_WITH_OPTIONS = sorted(p.relative_to(ROOT / "runs").as_posix() for p in (ROOT / "runs").rglob("*.toml")
                             if "[petsc]" in p.read_text() or p.with_suffix(".opts").is_file())


@pytest.mark.parametrize("scene", SCENES_WITH_OPTIONS)
def test_shipped_scenes_with_petsc_options_give_no_warning(run_cli, root, tmp_path, scene):
    assert SCENES_WITH_OPTIONS  # the pendulum scenes' sb_jacobian_reuse
    out = run_cli("run", str(root / "runs" / scene), "--out", "res", "-q", "--set", "analysis.t_end=0.003")
    assert out.returncode == 0, out.stderr
    assert not warnings(out.stderr), out.stderr


# on 2 ranks, one scene of each kind the Schwarz path's options meet: a director rope, sliding
# joints on carriers, an ANCF cable on a seabed (each scene is an mpirun of its own)
PARALLEL_CABLES = ("hanging_rope", "ropeway", "mooring_heave")


@pytest.mark.parametrize("ranks", (1, pytest.param(2, marks=pytest.mark.spawns_ranks)))
def test_shipped_options_file_gives_no_warning(run_cli, root, ranks):
    """runs/cables/iterative.opts (the Schwarz path) on the cable scenes, serially on all of
    them and on 2 ranks on PARALLEL_CABLES."""
    scenes = sorted((root / "runs" / "cables").glob("*.toml"))
    for scene in scenes if ranks == 1 else [p for p in scenes if p.stem in PARALLEL_CABLES]:
        out = run_cli("run", str(scene), "--out", scene.stem, "-q", "--set", "analysis.t_end=0.002",
                      "--set", "output.xdmf=false", "--", "-options_file",
                      str(root / "runs" / "cables" / "iterative.opts"), np=ranks)
        assert out.returncode == 0, (scene.name, out.stderr)
        assert not warnings(out.stderr), (scene.name, out.stderr)


@pytest.mark.spawns_ranks
def test_under_mpirun_each_warning_once(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "bend45.toml"), "--out", "res", *STATIC, "--", "-snes_monitr", np=2)
    assert out.returncode == 0, out.stderr
    assert warnings(out.stderr) == ["slidebeam: warning: PETSc option -snes_monitr from the command line was never "
                                    "used (did you mean -snes_monitor?)"]


def test_study_reports_each_unused_option_once(run_cli, root, tmp_path):
    out = run_cli("study", str(root / "runs" / "seed" / "free_fall_1+4.toml"), "--vary", "analysis.dt=4e-3,2e-3",
                  "--set", "analysis.t_end=0.008", "--out", "st", "-q", "--", "-snes_monitr")
    assert out.returncode == 0, out.stderr
    assert warnings(out.stderr) == ["slidebeam: warning: PETSc option -snes_monitr from the command line was never "
                                    "used (did you mean -snes_monitor?)"]


def test_every_sb_option_of_the_core_is_a_known_option():
    from slidebeam.run.options_check import closest, known_options

    in_source = set()
    for path in (ROOT / "src").rglob("*.[ch]pp"):
        in_source |= set(re.findall(r'"-(sb_[A-Za-z0-9_]+)"', path.read_text()))
    assert {"sb_jacobian_reuse", "sb_schwarz", "sb_condense_directors"} <= in_source
    assert in_source <= set(known_options())
    assert closest("sb_jacobian_reues") == "sb_jacobian_reuse"
    assert closest("snes_monitr") == "snes_monitor" and closest("snes_rtoll") == "snes_rtol"
    assert closest("ksp_rtol") == "ksp_rtol" and closest("completely_unrelated_name") is None
