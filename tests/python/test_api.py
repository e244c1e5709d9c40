# SPDX-License-Identifier: MIT
"""The Python API as docs/api.md describes it: named points, energies with the kinetic part,
the static and the step residual, results written from a script, and the solvers' PETSc
options prefixes (plain options still apply; prefixed ones win for their solver)."""
from __future__ import annotations

import csv
import dataclasses
import json
import math

import numpy as np
import pytest
from mpi4py import MPI
from petsc4py import PETSc

import slidebeam
from slidebeam import _core
from slidebeam.run import options_check


def cantilever(**analysis):
    return slidebeam.scene_from_dict({
        "scene": {"name": "cantilever"},
        "analysis": {"type": "static", "steps": 2, **analysis},
        "beam": [{"name": "rod", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 4,
                  "section": {"EA": 1e4, "kGA": 1e4, "GJ": 10.0, "EI2": 10.0, "EI3": 10.0, "rhoA": 1.0}}],
        "support": [{"type": "clamp", "beam": "rod", "at": "start"}],
        "load": [{"type": "force", "beam": "rod", "at": "end", "value": [0, 2.0, 1.0]}],
    })


def pendulum(t_end=0.01, **sets):
    overrides = [f"analysis.t_end={t_end}", "beam.0.spans=4", "output.every=1"] + [f"{k}={v}" for k, v in sets.items()]
    return slidebeam.load_scene(slidebeam_root() / "runs" / "pendulum16.toml", overrides)


def slidebeam_root():
    from pathlib import Path

    return Path(__file__).resolve().parents[2]


def test_point_names_the_columns_of_evaluate():
    sim = slidebeam.Simulation(cantilever())
    sim.solve_static()
    p = sim.point("rod", 0.7)
    q = sim.evaluate("rod", 0.7)
    assert q.shape == (1, 12)
    for k, part in enumerate((p.phi, p.d1, p.d2, p.d3)):
        assert part.shape == (3,) and (part == q[0, 3 * k:3 * k + 3]).all()
    assert sim.evaluate("rod", [0.0, 0.5, 1.0]).shape == (3, 12)


def test_point_of_an_ancf_cable_has_the_tangent_and_no_directors():
    scene = slidebeam.scene_from_dict({
        "analysis": {"steps": 1},
        "beam": [{"name": "c", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 4, "formulation": "ancf",
                  "section": {"EA": 1e5, "EI": 1.0}}],
        "support": [{"type": "clamp", "beam": "c", "at": "start"}],
    })
    p = slidebeam.Simulation(scene).point("c", 1.0)
    assert p.d2 is None and p.d3 is None
    assert np.allclose(p.phi, [1, 0, 0]) and np.allclose(p.d1, [1, 0, 0])


def test_energies_of_a_static_scene():
    sim = slidebeam.Simulation(cantilever())
    rec = sim.solve_static()[-1]
    e = sim.energies()
    assert e["kinetic"] == 0.0 and e["strain"] == pytest.approx(rec.strain_energy)
    assert e["total"] == pytest.approx(e["strain"] + e["potential"])


def test_energies_of_a_dynamic_scene_include_the_kinetic_energy():
    sim = slidebeam.Simulation(pendulum())
    assert sim.energies()["kinetic"] == 0.0
    outcome = sim.run_dynamic()
    assert isinstance(outcome, slidebeam.RunOutcome) and outcome.complete
    last = outcome.records[-1]
    e = sim.energies()
    assert e["kinetic"] > 0 and e["kinetic"] == pytest.approx(last.kinetic_energy, rel=1e-12)
    assert e["total"] == pytest.approx(last.total_energy, abs=1e-12)
    assert e["total"] == pytest.approx(e["kinetic"] + e["strain"] + e["potential"])


@pytest.mark.parametrize("integrator", ["energy-momentum", "midpoint", "newmark", "hht"])
def test_step_residual_is_what_the_last_step_solved(integrator):
    sim = slidebeam.Simulation(pendulum(t_end=0.005, **{"analysis.integrator": integrator}))
    with pytest.raises(RuntimeError, match="no time step"):
        sim.step_residual()
    outcome = sim.run_dynamic()
    last = outcome.records[-1]
    step = sim.step_residual().norm()
    assert math.isclose(step, last.residual_norm, rel_tol=1e-6, abs_tol=1e-14)
    # the static residual of the swinging pendulum is its out-of-balance (inertia) force
    assert sim.static_residual().norm() > 1e3 * step
    assert sim.residual().norm() == sim.static_residual().norm()


def test_step_residual_needs_a_dynamic_scene():
    sim = slidebeam.Simulation(cantilever())
    with pytest.raises(ValueError, match="static_residual"):
        sim.step_residual()


def test_result_writer_writes_what_the_cli_writes(tmp_path):
    folder = tmp_path / "dyn"
    sim = slidebeam.Simulation(pendulum(t_end=0.005))
    with slidebeam.ResultWriter(sim, folder) as writer:
        outcome = sim.run_dynamic(on_step=writer.record)
        summary = writer.finish(outcome)
    assert summary["complete"] and summary["analysis"] == "dynamic"
    if MPI.COMM_WORLD.Get_rank() == 0:
        names = {p.name for p in folder.iterdir()}
        assert {"history.csv", "final_configuration.csv", "summary.json", "beams.xdmf", "beams.h5"} <= names
        rows = list(csv.DictReader((folder / "history.csv").open()))
        assert len(rows) == len(outcome.records) == 6
        assert float(rows[-1]["kinetic_energy"]) == pytest.approx(outcome.records[-1].kinetic_energy)
        on_disk = json.loads((folder / "summary.json").read_text())
        assert on_disk["steps"] == 5 and on_disk["final_energy"]["total"] == pytest.approx(summary["final_energy"]["total"])
        assert (folder / "beams.xdmf").read_text().count("<Grid Name=\"t") == 6 or \
            (folder / "beams.xdmf").read_text().count("Time Value") == 6


def test_write_results_of_static_records(tmp_path):
    sim = slidebeam.Simulation(cantilever())
    records = sim.solve_static()
    summary = slidebeam.write_results(sim, records, tmp_path / "static")
    assert summary["complete"] and summary["steps"] == 2 and "final_end_positions" in summary
    if MPI.COMM_WORLD.Get_rank() == 0:
        rows = list(csv.DictReader((tmp_path / "static" / "history.csv").open()))
        assert [int(r["step"]) for r in rows] == [0, 1, 2]
        assert not (tmp_path / "static" / "beams.xdmf").exists()


def test_solvers_have_our_options_prefixes():
    sim = slidebeam.Simulation(cantilever())
    assert sim.snes.getOptionsPrefix() == "sb_static_"
    assert sim.snes.getKSP().getOptionsPrefix() == "sb_static_"
    dyn = slidebeam.Simulation(pendulum())
    assert dyn.snes.getOptionsPrefix() == "sb_ts_"
    assert _core.EquilibriumSolver(dyn._model).snes.getOptionsPrefix() == "sb_eq_"
    assert set(_core.SOLVER_PREFIXES.values()) == set(options_check.SOLVER_PREFIXES)


def _max_it(sim) -> int:
    return sim.snes.getTolerances()[3]


def test_plain_options_apply_and_prefixed_ones_win():
    opts = PETSc.Options()
    try:
        opts.setValue("snes_max_it", 17)
        assert _max_it(slidebeam.Simulation(cantilever())) == 17
        assert _max_it(slidebeam.Simulation(pendulum())) == 17
        opts.setValue("sb_ts_snes_max_it", 23)  # the time steps only
        assert _max_it(slidebeam.Simulation(cantilever())) == 17
        assert _max_it(slidebeam.Simulation(pendulum())) == 23
        opts.setValue("snes_max_it", 19)  # the copies follow the plain option
        assert _max_it(slidebeam.Simulation(cantilever())) == 19
    finally:
        for key in ("snes_max_it", "sb_ts_snes_max_it"):
            opts.delValue(key)
    assert _max_it(slidebeam.Simulation(cantilever())) == 50  # the copy went with the plain option


def test_a_scenes_plain_option_does_not_leak_into_the_next_scene():
    first = cantilever()
    first = dataclasses.replace(first, petsc_options={"snes_max_it": "13"})
    assert _max_it(slidebeam.Simulation(first)) == 13
    assert _max_it(slidebeam.Simulation(cantilever())) == 50


def test_a_plain_option_read_through_its_copy_is_not_unused():
    opts = PETSc.Options()
    options_check.remember_command_line([])
    try:
        opts.setValue("snes_max_it", 30)
        opts.setValue("sb_static_snes_rtoll", 1e-9)  # a typo under a prefix
        options_check._initial = {**(options_check._initial or {}), "snes_max_it": "30", "sb_static_snes_rtoll": "1e-9"}
        sim = slidebeam.Simulation(cantilever())
        sim.solve_static()
        unused = {u.option: u for u in options_check.unused_options(sim.scene)}
        assert "-snes_max_it" not in unused
        assert unused["-sb_static_snes_rtoll"].did_you_mean == "-sb_static_snes_rtol"
    finally:
        opts.delValue("snes_max_it")
        opts.delValue("sb_static_snes_rtoll")
        options_check._initial = None


def test_write_results_of_dynamic_records_without_their_outcome(tmp_path):
    sim = slidebeam.Simulation(pendulum(t_end=0.003))
    outcome = sim.run_dynamic()
    summary = slidebeam.write_results(sim, outcome.records, tmp_path / "records")
    assert summary["complete"] and summary["message"] == "completed" and summary["steps"] == 3
    assert summary["final_energy"]["total"] == pytest.approx(outcome.records[-1].total_energy)
