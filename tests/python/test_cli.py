# SPDX-License-Identifier: MIT
"""The command line as a user meets it: help, results, PETSc options, and clear errors."""
from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.skip_in_parallel  # each test starts its own processes

SMALL = ["--set", "analysis.steps=3", "--set", "beam.0.spans=6"]  # fast variants of the scenes


def test_help(run_cli):
    for args in (["--help"], ["run", "--help"], ["check", "--help"]):
        out = run_cli(*args)
        assert out.returncode == 0 and "usage" in out.stdout


def test_run_writes_results(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "res", *SMALL)
    assert out.returncode == 0, out.stderr
    assert "active effects: beam_elastic[strip], director_constraints[strip], clamp[strip@start], moment[strip@end]" in out.stdout
    summary = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert summary["complete"] and summary["converged"] and summary["steps"] == 3
    assert summary["active_effects"] == ["beam_elastic[strip]", "director_constraints[strip]", "clamp[strip@start]",
                                         "moment[strip@end]"]
    assert summary["newton_iterations"] == sum(summary["newton_iterations_per_step"]) > 0
    assert set(summary["final_end_positions"]["strip"]) == {"start", "end"}
    rows = list(csv.DictReader((tmp_path / "res" / "history.csv").open()))
    assert [int(r["step"]) for r in rows] == [0, 1, 2, 3]
    tip = [float(rows[-1][f"strip@10.{c}"]) for c in "xyz"]
    assert tip == pytest.approx(summary["final_end_positions"]["strip"]["end"], abs=1e-12)
    config = list(csv.DictReader((tmp_path / "res" / "final_configuration.csv").open()))
    assert len(config) == 6 * 8 + 1 and float(config[-1]["s"]) == 10.0
    assert {"eps_axial", "kappa3", "fx", "mz", "tension"} <= set(config[0])
    # a pure end moment: a bending moment all along (a coarse full-quadrature strip: within 20 %)
    moments = [float(r["mz"]) for r in config]
    assert min(moments) > 0.8 * max(moments) > 1.0


def test_check_validates_only(run_cli, root, tmp_path):
    out = run_cli("check", str(root / "runs" / "bend45.toml"))
    assert out.returncode == 0 and "scene is valid" in out.stdout
    assert not any(tmp_path.iterdir())


def test_petsc_options_after_double_dash(run_cli, root):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "res", *SMALL, "--",
                  "-snes_test_jacobian", "-log_view")
    assert out.returncode == 0, out.stderr
    ratios = [float(v) for v in re.findall(r"\|\|J - Jfd\|\|_F/\|\|J\|\|_F = ([0-9.eE+-]+)", out.stdout)]
    assert ratios and max(ratios) < 1e-6
    assert "SBAssembleJac" in out.stdout and "SB:beam_elastic" in out.stdout  # our log events


def test_a_chosen_pivoting_solver_is_no_fall_back(run_cli, root):
    """The console's note on steps solved on the pivoting LU is about fall-backs: a run whose user
    chose SuperLU has none (it used to say "0 steps ran on the pivoting LU")."""
    out = run_cli("run", str(root / "runs" / "pendulum16.toml"), "--out", "res", "--set", "analysis.t_end=0.01", "--",
                  "-sb_ts_pc_type", "lu", "-sb_ts_pc_factor_mat_solver_type", "superlu")
    assert out.returncode == 0, out.stderr
    assert "done in" in out.stdout and "pivoting LU" not in out.stdout


def test_options_file_beside_scene(run_cli, root, tmp_path):
    scene = tmp_path / "rollup.toml"
    scene.write_text((root / "runs" / "rollup.toml").read_text())
    (tmp_path / "rollup.opts").write_text("# solver settings for rollup.toml\n-snes_converged_reason\n-snes_max_it 30\n")
    out = run_cli("run", str(scene), "--out", "res", *SMALL)
    assert out.returncode == 0, out.stderr
    # (the solver's prefix in the line: the load steps', or the continuation's where Newton cut to 30
    # iterations does not finish a step)
    assert re.search(r"Nonlinear (sb_(static|eq)_ )?solve converged due to", out.stdout)
    (tmp_path / "rollup.opts").write_text("snes_monitor\n")
    out = run_cli("run", str(scene), "--out", "res", *SMALL)
    assert out.returncode == 2 and "rollup.opts" in out.stderr and "Traceback" not in out.stderr


@pytest.mark.spawns_ranks
def test_mpi_run_matches_serial(run_cli, root, tmp_path):
    """The distributed static solve (a static analysis runs on rank 0 alone unless told not to)
    gives the serial history."""
    a = run_cli("run", str(root / "runs" / "bend45.toml"), "--out", "np1", *SMALL)
    b = run_cli("run", str(root / "runs" / "bend45.toml"), "--out", "np2", *SMALL, "--", "-sb_statics_on_rank_0",
                "false", np=2)
    assert a.returncode == 0 and b.returncode == 0, b.stderr
    ha = list(csv.reader((tmp_path / "np1" / "history.csv").open()))
    hb = list(csv.reader((tmp_path / "np2" / "history.csv").open()))
    tip = [k for k, name in enumerate(ha[0]) if name.startswith("arc@")]
    assert len(tip) == 3
    for ra, rb in zip(ha[1:], hb[1:]):
        for k in tip:
            assert abs(float(ra[k]) - float(rb[k])) < 1e-10
    assert json.loads((tmp_path / "np2" / "summary.json").read_text())["ranks"] == 2


BAD = {
    "malformed": ("[[beam]\nname = 'a'\n", ["TOML syntax error", "line 1"]),
    "unknown_key": ("[[beam]]\nname='a'\nstart=[0,0,0]\nend=[1,0,0]\nspan=4\n"
                    "section={EA=1.0,kGA=1.0,GJ=1.0,EI2=1.0,EI3=1.0}\n", ["[[beam]] #1 ('a')", "'span'", "spans"]),
    "negative_spans": ("[[beam]]\nname='a'\nstart=[0,0,0]\nend=[1,0,0]\nspans=-2\n"
                       "section={EA=1.0,kGA=1.0,GJ=1.0,EI2=1.0,EI3=1.0}\n", ["[[beam]] #1 ('a')", "'spans'"]),
    "wrong_type": ("[[beam]]\nname='a'\nstart=[0,0,0]\nend=[1,0,0]\nspans='ten'\n"
                   "section={EA=1.0,kGA=1.0,GJ=1.0,EI2=1.0,EI3=1.0}\n", ["'spans'", "integer"]),
    "zero_length": ("[[beam]]\nname='a'\nstart=[0,0,0]\nend=[0,0,0]\nspans=2\n"
                    "section={EA=1.0,kGA=1.0,GJ=1.0,EI2=1.0,EI3=1.0}\n", ["[[beam]] #1 ('a')"]),
    "missing_beam": ("[[beam]]\nname='a'\nstart=[0,0,0]\nend=[1,0,0]\nspans=2\n"
                     "section={EA=1.0,kGA=1.0,GJ=1.0,EI2=1.0,EI3=1.0}\n"
                     "[[support]]\ntype='clamp'\nbeam='b'\nat='start'\n", ["[[support]] #1", "'beam'", "'b'"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_is_a_clear_error(run_cli, tmp_path, case):
    text, expected = BAD[case]
    scene = tmp_path / f"{case}.toml"
    scene.write_text(text)
    for args in (("run", str(scene), "--out", "res"), ("check", str(scene))):
        out = run_cli(*args)
        assert out.returncode == 2, (case, args, out.stdout, out.stderr)
        assert "Traceback" not in out.stderr + out.stdout
        assert f"{case}.toml" in out.stderr
        for piece in expected:
            assert piece in out.stderr, (piece, out.stderr)
    assert not (tmp_path / "res").exists()


def test_unwritable_output_folder(run_cli, root, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", str(blocker / "sub"), *SMALL)
    assert out.returncode == 2 and "not writable" in out.stderr and "Traceback" not in out.stderr


def test_newton_failure_is_clean_and_marked_incomplete(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "res", *SMALL, "--", "-snes_max_it", "1")
    assert out.returncode == 1
    assert "Newton failed at load step 1" in out.stderr and "residual norm" in out.stderr
    assert "Traceback" not in out.stderr
    summary = json.loads((tmp_path / "res" / "summary.json").read_text())
    assert summary["complete"] is False and summary["converged"] is False
    assert "Newton failed" in summary["message"]
    rows = list(csv.DictReader((tmp_path / "res" / "history.csv").open()))
    assert rows[-1]["converged"] == "0"
    # the configuration written is the last converged one: the undeformed reference
    assert summary["final_end_positions"]["strip"]["end"] == pytest.approx([10.0, 0.0, 0.0], abs=1e-12)


DYNAMIC_SCENES = ("flying_spaghetti_2d", "flying_spaghetti_3d", "right_angle_cantilever", "pendulum16", "pendulum64",
                  "pendulum16_ancf", "pendulum64_ancf")


@pytest.mark.parametrize("integrator", ("energy-momentum", "midpoint", "newmark", "hht"))
def test_dynamic_scenes_run_with_every_integrator(run_cli, root, tmp_path, integrator):
    """Every D-scene starts and steps with every integrator (short runs; the full runs are in
    docs/verification.md, "Dynamics")."""
    for name in DYNAMIC_SCENES:
        out = run_cli("run", str(root / "runs" / f"{name}.toml"), "--out", name, "-q",
                      "--set", f'analysis.integrator="{integrator}"', "--set", "analysis.t_end=0.3"
                      if not name.startswith("pendulum") else "analysis.t_end=0.02")
        assert out.returncode == 0, (name, out.stderr)
        summary = json.loads((tmp_path / name / "summary.json").read_text())
        assert summary["complete"] and summary["integrator"] == integrator


def test_dynamic_run_writes_energy_momentum_history_and_plot(run_cli, root, tmp_path):
    scene = str(root / "runs" / "flying_spaghetti_2d.toml")
    out = run_cli("run", scene, "--out", "d1", "--set", "analysis.t_end=3.0")
    assert out.returncode == 0, out.stderr
    assert "beam_inertia[spaghetti]" in out.stdout and "done in" in out.stdout
    rows = list(csv.DictReader((tmp_path / "d1" / "history.csv").open()))
    assert len(rows) == 31 and float(rows[-1]["t"]) == pytest.approx(3.0)
    for col in ("kinetic_energy", "strain_energy", "potential_energy", "total_energy", "linear_momentum.x",
                "angular_momentum.z", "constraint_residual", "newton_iterations", "spaghetti@10.x"):
        assert col in rows[0]
    last = rows[-1]
    total = sum(float(last[k]) for k in ("kinetic_energy", "strain_energy", "potential_energy"))
    assert float(last["total_energy"]) == pytest.approx(total, rel=1e-12)
    assert float(last["linear_momentum.x"]) == pytest.approx(8.0 * 2.5, rel=1e-9)  # impulse of F = 8 over 2.5 s
    summary = json.loads((tmp_path / "d1" / "summary.json").read_text())
    assert summary["complete"] and summary["steps"] == 30 and summary["max_constraint_residual"] < 1e-9
    plot = run_cli("plot", "d1", "--out", "d1.png")
    assert plot.returncode == 0, plot.stderr
    assert (tmp_path / "d1.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    missing = run_cli("plot", "nowhere")
    assert missing.returncode == 2 and "history.csv" in missing.stderr and "Traceback" not in missing.stderr


def test_dynamic_failure_is_a_clean_stop(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "flying_spaghetti_2d.toml"), "--out", "nm", "-q",
                  "--set", 'analysis.integrator="newmark"', "--set", "analysis.dt_min=0.05")
    assert out.returncode == 1
    assert "Newton failed at step" in out.stderr and "residual norm" in out.stderr
    assert "Traceback" not in out.stderr
    summary = json.loads((tmp_path / "nm" / "summary.json").read_text())
    assert summary["complete"] is False and summary["t_reached"] < 15.0
    rows = list(csv.DictReader((tmp_path / "nm" / "history.csv").open()))
    assert rows[-1]["converged"] == "0" and all(r["converged"] == "1" for r in rows[:-1])
    assert all(v not in ("nan", "inf") for r in rows for v in r.values())


def test_dynamic_summary_counts_every_step_not_only_recorded_ones(run_cli, root, tmp_path):
    out = run_cli("run", str(root / "runs" / "pendulum16.toml"), "--out", "p", "-q", "--set", "analysis.t_end=0.05")
    assert out.returncode == 0, out.stderr
    summary = json.loads((tmp_path / "p" / "summary.json").read_text())
    rows = list(csv.DictReader((tmp_path / "p" / "history.csv").open()))
    assert summary["steps"] == 50 and len(rows) == 6  # output.every = 10
    assert summary["newton_iterations"] >= 50 > sum(int(r["newton_iterations"]) for r in rows)


def test_unsolvable_initial_acceleration_is_a_solver_error(run_cli, tmp_path):
    """Newmark needs a_0 from [M G^T; G 0]: without rotary inertia the directors have no mass
    and the system is singular. That is a property of the scene: exit 1 with a hint, no trace."""
    scene = tmp_path / "massless.toml"
    scene.write_text("""
analysis = { type = "dynamic", integrator = "newmark", dt = 0.01, t_end = 0.02 }
[[beam]]
name = "a"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
spans = 2
section = { EA = 1.0e3, kGA = 1.0e3, GJ = 1.0, EI2 = 1.0, EI3 = 1.0, rhoA = 1.0 }
""")
    out = run_cli("run", str(scene), "--out", "m")
    assert out.returncode == 1
    assert "initial acceleration" in out.stderr and "mass" in out.stderr and "Traceback" not in out.stderr
    assert not (tmp_path / "m" / "summary.json").exists()


def test_start_warnings_reach_the_summary(run_cli, tmp_path):
    """A slider drawn 1e-6 m off its carrier: the run warns on the console and summary.json
    keeps the warning (a run without any has an empty list)."""
    section = "{ EA = 1e4, kGA = 1e4, GJ = 1.0, EI2 = 1.0, EI3 = 1.0, rhoA = 1.0, rhoI2 = 1e-3, rhoI3 = 1e-3 }"
    for name, dz in (("on", "0.0"), ("off", "1e-6")):
        (tmp_path / f"{name}.toml").write_text(f"""
[analysis]
type = "dynamic"
dt = 0.01
t_end = 0.02
[[beam]]
name = "carrier"
start = [0.0, 0.0, 0.0]
end = [2.0, 0.0, 0.0]
spans = 4
section = {section}
[[beam]]
name = "hanger"
start = [0.5, 0.0, {dz}]
end = [0.5, 0.0, -1.0]
spans = 1
section = {section}
[[support]]
type = "clamp"
beam = "carrier"
at = "start"
[[sliding_joint]]
slider = "hanger"
carrier = "carrier"
""")
        out = run_cli("run", f"{name}.toml", "--out", name)
        assert out.returncode == 0, out.stderr
        found = json.loads((tmp_path / name / "summary.json").read_text())["warnings"]
        if name == "on":
            assert found == [] and "off their carriers" not in out.stderr, (found, out.stderr)
        else:
            assert len(found) == 2 and "off their carriers" in found[0] and "pull of the sliders" in found[1], found
            assert all(m in out.stderr for m in found), (found, out.stderr)


SEED_MESHES = ("1+1", "1+2", "1+4", "1+8")


@pytest.mark.parametrize("integrator", ("energy-momentum", "midpoint", "newmark", "hht"))
def test_seed_benchmark_scenes_run_with_every_integrator(run_cli, root, tmp_path, integrator):
    """Every S2 mesh and quadrature starts and steps with every integrator (short runs)."""
    for mesh in SEED_MESHES:
        for quad in ("", "_reduced"):
            name = f"free_fall_{mesh}{quad}"
            out = run_cli("run", str(root / "runs" / "seed" / f"{name}.toml"), "--out", name, "-q",
                          "--set", f'analysis.integrator="{integrator}"', "--set", "analysis.t_end=0.02")
            assert out.returncode == 0, (name, out.stderr)
            summary = json.loads((tmp_path / name / "summary.json").read_text())
            assert summary["complete"] and summary["outputs"]["CM_on_AB"]["s"] > 0.4


def test_slider_reaching_the_carrier_end_stops_the_run(run_cli, root, tmp_path):
    """S2-incl: C slides down the inclined carrier and reaches B at t = 0.81 s. By default the run
    stops there (exit 0, message), with a shortened last step that ends with C at B: the last
    record, the final configuration and the checkpoint hold C on the carrier, within 1e-9 of its
    length from the end; the run is converged, not complete, and says why it stopped.
    at_carrier_end = "fail" makes it an error (exit 1)."""
    scene = str(root / "runs" / "seed" / "free_fall_inclined_1+4.toml")
    out = run_cli("run", scene, "--out", "stop", "-q", "--set", "analysis.dt=0.002")
    assert out.returncode == 0, out.stderr
    assert "reached the end of carrier 'AB'" in out.stdout
    summary = json.loads((tmp_path / "stop" / "summary.json").read_text())
    assert summary["complete"] is False and 0.7 < summary["t_reached"] < 0.9
    assert summary["converged"] is True and "reached the end of carrier 'AB'" in summary["stopped"]
    assert 2.0 - 2e-9 <= summary["outputs"]["CM_on_AB"]["s"] <= 2.0
    rows = list(csv.DictReader((tmp_path / "stop" / "history.csv").open()))
    for col in ("CM_on_AB.s", "CM_on_AB.ds_dt", "CM_on_AB.reaction.x", "CM_on_AB.reaction.y", "CM_on_AB.reaction.z"):
        assert col in rows[0]
    assert float(rows[0]["CM_on_AB.s"]) == pytest.approx(0.4, abs=1e-12)
    assert float(rows[-1]["CM_on_AB.ds_dt"]) > 1.0  # sliding fast at the end
    s = [float(r["CM_on_AB.s"]) for r in rows]
    assert all(b >= a for a, b in zip(s, s[1:]))  # C only slides down
    assert 2.0 - 2e-9 <= s[-1] <= 2.0 and float(rows[-1]["t"]) == summary["t_reached"]
    assert float(rows[-1]["dt"]) < 0.002  # the shortened last step
    fail = run_cli("run", scene, "--out", "fail", "-q", "--set", "analysis.dt=0.002",
                   "--set", 'sliding_joint.0.at_carrier_end="fail"')
    assert fail.returncode == 1 and "reached the end of carrier 'AB'" in fail.stderr
    assert "Traceback" not in fail.stderr


def test_cost_breakdown_names_only_the_scene_effects(run_cli, root, tmp_path):
    """The cost table (stdout) and summary.json list one row per effect type the scene created,
    then ghost exchange, linear solve, output and the rest; the shares add up to the wall time."""
    out = run_cli("run", str(root / "runs" / "rollup.toml"), "--out", "r", *SMALL)
    assert out.returncode == 0, out.stderr
    assert "cost by phase" in out.stdout and "assembly: beam_elastic" in out.stdout
    summary = json.loads((tmp_path / "r" / "summary.json").read_text())
    phases = [row["phase"] for row in summary["cost"]]
    assert phases == ["assembly: beam_elastic", "assembly: director_constraints", "assembly: clamp",
                      "assembly: moment", "ghost exchange", "linear solve (incl. factorisation)", "output",
                      "other (Newton updates, records, Python)"]
    assert sum(row["share"] for row in summary["cost"]) == pytest.approx(1.0, abs=1e-6)
    assert summary["cost"][0]["calls"] > 0 and summary["cost"][0]["time_s"] > 0
    seed = run_cli("run", str(root / "runs" / "seed" / "free_fall_1+1.toml"), "--out", "s", "-q",
                   "--set", "analysis.t_end=0.01")
    assert seed.returncode == 0, seed.stderr
    phases = [row["phase"] for row in json.loads((tmp_path / "s" / "summary.json").read_text())["cost"]]
    assert "assembly: sliding_joint (incl. contact search)" in phases and "assembly: gravity" in phases
    assert "assembly: clamp" not in phases and "assembly: rigid_joint" not in phases


@pytest.mark.skip_in_parallel
def test_cost_table_counts_the_same_with_petsc_whole_log(run_cli, root, tmp_path):
    """The cost table's light event log and PETSc's whole log (-log_view) see the same calls of
    every phase (the run is the same), and -log_view still prints PETSc's vector events, which
    the light log leaves out."""
    scene = str(root / "runs" / "effects" / "moving_anchor.toml")
    light = run_cli("run", scene, "--out", "light", "-q", "--set", "analysis.t_end=0.05")
    whole = run_cli("run", scene, "--out", "whole", "-q", "--set", "analysis.t_end=0.05", "--", "-log_view")
    assert light.returncode == 0 and whole.returncode == 0, light.stderr + whole.stderr
    rows = [{r["phase"]: r["calls"] for r in json.loads((tmp_path / d / "summary.json").read_text())["cost"]}
            for d in ("light", "whole")]
    assert rows[0] == rows[1]
    assert rows[0]["linear solve (incl. factorisation)"] > 0 and rows[0]["ghost exchange"] > 0
    assert "VecNorm" in whole.stdout and "VecNorm" not in light.stdout


@pytest.mark.spawns_ranks
@pytest.mark.parametrize("scene, sets", [
    # S2-incl on a 16-span carrier: C slides from s = 0.4 to 1.5 across the control points of
    # every rank (the joint lives with the slider, its carrier points are ghosts)
    (("seed", "free_fall_inclined_1+4.toml"), ["beam.AB.spans=16", "analysis.t_end=0.66"]),
    # from the straight drawing: the equilibrium start is defined only to its roundoff floor
    # (test_cables checks it across ranks at that level)
    (("cables", "ropeway.toml"), ["analysis.t_end=0.1", "analysis.start=reference"]),
])
def test_one_two_and_three_ranks_give_the_same_history(run_cli, root, tmp_path, scene, sets):
    args = [a for s in sets for a in ("--set", s)] + ["--set", "output.xdmf=false", "-q"]
    rows = {}
    for np_ in (1, 2, 3):
        out = run_cli("run", str(root.joinpath("runs", *scene)), "--out", f"np{np_}", *args, np=np_)
        assert out.returncode == 0, out.stderr
        rows[np_] = list(csv.DictReader((tmp_path / f"np{np_}" / "history.csv").open()))
    s_col = [c for c in rows[1][0] if c.endswith(".s")][0]
    s = [float(r[s_col]) for r in rows[1]]
    assert max(s) - min(s) > (1.0 if scene[0] == "seed" else 0.0)
    # the scale of a quantity: the largest value of its family (all components, all rows)
    scale: dict[str, float] = {}
    for r in rows[1]:
        for key, v in r.items():
            if key != "reason":
                fam = key.split(".")[0]
                scale[fam] = max(scale.get(fam, 1.0), abs(float(v)))
    for np_ in (2, 3):
        assert len(rows[np_]) == len(rows[1])
        for a, b in zip(rows[1], rows[np_]):
            for key in a:
                if key in ("reason", "newton_iterations", "residual_norm") or "reaction" in key:
                    continue
                x, y = float(a[key]), float(b[key])
                # support reactions: residuals of stiff rows, as exact as the Newton tolerance lets them be
                tol = 1e-8 if key.rsplit(".", 1)[-1] in ("fx", "fy", "fz", "mx", "my", "mz") else 1e-10
                # the balance error is a difference of energies: on their scale
                fam = "total_energy" if key == "energy_balance_error" else key.split(".")[0]
                assert abs(x - y) <= tol * scale[fam], (np_, a["t"], key, x, y)
