# SPDX-License-Identifier: MIT
"""Multi-beam cable scenes (issue 6): the serial factorisation's fill stays linear in the scene
size with the model's elimination order."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI
from petsc4py import PETSc

ROOT = Path(__file__).resolve().parents[2]


def cable_scene(tmp_path: Path, carriers: int, spans: int, hangers: int, *extra: str) -> Path:
    out = tmp_path / f"cables_{carriers}_{spans}_{hangers}.toml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--carriers", str(carriers),
                    "--spans", str(spans), "--hangers", str(hangers), "--out", str(out), *extra],
                   check=True, capture_output=True)
    return out


def scene_order_extras_last(sim) -> list[int]:
    """A naive elimination order: the control points' blocks beam by beam in scene order, then
    every joint's and support's extra unknowns."""
    blocks: list[int] = []
    for beam in sim.scene.beams:
        first_cp = sim.first_control_point(beam.name)
        for cp in range(first_cp, first_cp + beam.spans + 2):
            first, coordinates = sim.control_point_unknowns(cp)
            blocks += range(first, first + coordinates + (6 if coordinates == 12 else 0))
    rest = sorted(set(range(sim.x.getSize())) - set(blocks))
    return blocks + rest


def lu_nonzeros_per_unknown(scene: Path, ordering: str) -> float:
    """LU fill of a step's Jacobian in an order: "sb_model" (Model::elimination_order),
    "natural" (the numbering), "naive" (scene_order_extras_last)."""
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(scene), MPI.COMM_SELF)
    assert sim.integrator.step(1e-3).converged
    A = sim.jacobian.duplicate(copy=True)
    if ordering != "natural":
        order = sim.elimination_order() if ordering == "sb_model" else scene_order_extras_last(sim)
        A.compose("sb_elimination_order", PETSc.IS().createGeneral(order, comm=PETSc.COMM_SELF))
    pc = PETSc.PC().create(PETSc.COMM_SELF)
    pc.setOperators(A)
    pc.setType("lu")
    pc.setFactorSolverType("petsc")
    pc.setFactorOrdering("natural" if ordering == "natural" else "sb_model")
    pc.setUp()
    return pc.getFactorMatrix().getInfo()["nz_used"] / A.getSize()[0]


def test_factorisation_fill_grows_linearly_with_the_scene(tmp_path):
    """Four times the carrier length and four times the hangers: with the model's order (sliders
    before carriers, multipliers next to their coordinates) the LU's nonzeros per unknown stay
    the same, and in the numbering's own order (hangers among the carrier points they hang from)
    they grow by 8 % (full quadrature and assumed strains alike; with the carrier's quadrature
    chosen by slenderness, the shorter spans once took full quadrature and hid it); in a naive
    order (beams in scene order, extras last) each joint fills its carrier from the joint to the
    carrier's end, so the fill per unknown grows with the scene (the test can fail)."""
    small, big = cable_scene(tmp_path, 1, 32, 4), cable_scene(tmp_path, 1, 128, 16)
    model, natural, naive = ([lu_nonzeros_per_unknown(s, o) for s in (small, big)]
                             for o in ("sb_model", "natural", "naive"))
    assert model[1] / model[0] < 1.05, model
    assert natural[1] / natural[0] < 1.12, natural
    assert naive[1] / naive[0] > 1.3, naive
    assert model[1] < 0.7 * naive[1]


def test_elimination_order_is_a_permutation_with_sliders_before_carriers(tmp_path):
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(cable_scene(tmp_path, 2, 8, 2)), MPI.COMM_SELF)
    order = sim.elimination_order()
    n = sim.x.getSize()
    assert sorted(order) == list(range(n))
    position = {old: new for new, old in enumerate(order)}
    for k, joint in enumerate(sim.scene.sliding_joints):
        first_extra = sim.sliding_coordinate_index(k) - 3
        slider, carrier = sim.first_control_point(joint.slider), sim.first_control_point(joint.carrier)
        # the joint's extras right after the slider's three points, before any carrier point
        last_slider, _ = sim.control_point_unknowns(slider + 2)
        first_carrier, _ = sim.control_point_unknowns(carrier)
        assert position[first_extra] > position[last_slider + 17]
        assert position[first_extra] < position[first_carrier]
        # numbered in that slot too (DofMap): owned with the slider's points
        assert first_extra == last_slider + 18


def test_static_start_hangs_a_straight_rope_in_its_sag():
    """A straight rope between spherical supports has no transverse stiffness but its tiny EI:
    statics from there is a near-singular mechanism. The equilibrium start reaches its sag,
    which matches the taut elastic cable (parabola, d^3 = 3 q L^4 / (64 EA)) to 0.5 %, and the
    run then stays at rest."""
    import math

    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(ROOT / "runs" / "cables" / "slack_rope.toml"))
    outcome = sim.run_dynamic()
    assert outcome.complete and sim.settled is not None and sim.settled.converged
    EA, q, L = 1e11 * math.pi * 1e-4, 7800 * math.pi * 1e-4 * 9.81, 20.0
    sag = -outcome.records[0].tracked[0][2]
    assert sag == pytest.approx((3 * q * L**4 / (64 * EA)) ** (1 / 3), rel=5e-3)
    energy = abs(outcome.records[0].total_energy)
    assert max(r.kinetic_energy for r in outcome.records) < 1e-12 * energy
    assert abs(outcome.records[-1].tracked[0][2] + sag) < 1e-9 * sag


def _ropeway(tmp_path: Path, static: str, quadrature: str = "assumed_strain") -> "slidebeam.Simulation":
    import slidebeam

    scene = cable_scene(tmp_path, 1, 32, 3, "--start", "equilibrium", "--static", static, "--t-end", "0.02")
    return slidebeam.Simulation(slidebeam.load_scene(scene, [f"beam.{b}.quadrature={quadrature}" for b in range(4)]))


def test_static_start_with_held_sliders_keeps_them_in_place(tmp_path):
    sim = _ropeway(tmp_path, "held")
    s0 = [j.s for j in sim.joint_states()]
    outcome = sim.run_dynamic()
    assert outcome.complete
    first = outcome.records[0]
    assert [j.s for j in first.joints] == pytest.approx(s0, abs=1e-12)
    assert first.kinetic_energy == 0.0
    assert first.tracked[0][2] < -2.0 - 0.05  # the cable sags under the masses: the hanger's end below its start
    # released, the sliders start to move (they were held off the low point)
    assert max(abs(a.s - b.s) for a, b in zip(outcome.records[-1].joints, first.joints)) > 1e-6


@pytest.mark.parametrize("quadrature", ["full", "assumed_strain"])
def test_static_start_with_free_sliders_finds_the_low_point(tmp_path, quadrature):
    """Free sliders on a symmetric sagging rope all end at its low point, the middle, and stay.
    With assumed strains the carrier's energy ripples with the load's place in a
    span (the knots' averaged strains hide part of the kink under the load): on this nearly
    flat landscape they settle 0.26 m off the middle, less than half a span (0.625 m);
    docs/theory.md, "Where assumed strains lose, and the default"."""
    sim = _ropeway(tmp_path, "free", quadrature)
    outcome = sim.run_dynamic()
    assert outcome.complete
    for rec in (outcome.records[0], outcome.records[-1]):
        s = [j.s for j in rec.joints]
        assert s == pytest.approx([s[0]] * 3, abs=1e-6)
        assert s[0] == pytest.approx(10.0, abs=1e-6 if quadrature == "full" else 0.5 * 20.0 / 32)
    energy = abs(outcome.records[0].total_energy)
    assert max(r.kinetic_energy for r in outcome.records) < 1e-12 * energy


def test_static_start_keeps_free_sliders_on_their_carriers(tmp_path):
    """64 spans, full quadrature: the continuation's closing plain Newton solve had landed on a
    stationary point of the carrier's curve extended beyond its ends (s = -0.147 and 20.245 on a
    20 m carrier) and reported it converged. Steps and polishes that leave the carrier are
    rejected now: the sliders end together near the low point (a ripple of the discretisation
    away from the middle knot: measured 0.034 m)."""
    import slidebeam

    scene = cable_scene(tmp_path, 1, 64, 3, "--start", "equilibrium", "--static", "free", "--t-end", "0.002")
    sim = slidebeam.Simulation(slidebeam.load_scene(scene, [f"beam.{b}.quadrature=full" for b in range(4)]))
    assert sim.settle().converged
    s = [j.s for j in sim.joint_states()]
    assert s == pytest.approx([10.0] * 3, abs=0.5 * 20.0 / 64)


def test_equilibrium_start_keys_are_checked(tmp_path):
    import slidebeam

    text = (ROOT / "runs" / "cables" / "slack_rope.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('start = "equilibrium"', 'start = "equilibrum"'))
    with pytest.raises(slidebeam.SceneError, match="start"):
        slidebeam.load_scene(bad)
    bad.write_text(text.replace('type = "dynamic"', 'type = "static"'))
    with pytest.raises(slidebeam.SceneError, match='applies to type = "dynamic" only'):
        slidebeam.load_scene(bad)


@pytest.mark.parametrize("path", ["blocks", "mumps", "rank 0"])
def test_static_start_is_the_same_on_all_ranks_and_on_one(path):
    """Meaningful under mpirun. By default the static start runs on all ranks, its continuation
    steps on the time steps' block solve (every one of them here; a polish would be MUMPS's); with
    -sb_equilibrium_blocks false all on MUMPS. Either way the equilibrium equals the serial one
    to the level its residual floor defines it (1e-8 of the sag). With -sb_equilibrium_on_rank_0
    rank 0 solves it alone with the serial solver: the same continuation, Newton iterations and
    residual as the serial run, bit for bit."""
    import slidebeam
    from test_condensation import petsc_options

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "ropeway.toml", ["analysis.t_end=0.002"])
    options = {"rank 0": {"sb_equilibrium_on_rank_0": "true"}, "mumps": {"sb_equilibrium_blocks": "false"},
               "blocks": {}}[path]
    with petsc_options(**options):
        world_sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
        world = world_sim.run_dynamic().records
    alone_sim = slidebeam.Simulation(scene, MPI.COMM_SELF)
    alone = alone_sim.run_dynamic().records
    distributed = MPI.COMM_WORLD.Get_size() > 1
    assert world_sim.settled_on_rank_0 == (path == "rank 0" and distributed)
    if path == "rank 0":
        assert world_sim.settled == alone_sim.settled
    else:
        assert world_sim.settled.converged
        blocks = world_sim.settled.block_steps
        assert blocks == (world_sim.settled.pseudo_steps if path == "blocks" and distributed else 0), blocks
    for a, b in zip(world, alone):
        for p, q in zip(a.tracked, b.tracked):
            assert max(abs(u - v) for u, v in zip(p, q)) < (1e-10 if path == "rank 0" else 1e-8)


@pytest.mark.skipif(MPI.COMM_WORLD.Get_size() != 2, reason="two ranks: mpirun -n 2")
def test_static_start_runs_distributed_when_rank_0_cannot_hold_the_model(monkeypatch):
    """Rank 0's serial copy of the model is refused by the memory check (here: made to refuse
    any model on one rank): the static start asked to run there (-sb_equilibrium_on_rank_0) runs
    on all ranks instead, and says so."""
    import slidebeam
    import slidebeam.run.model
    from slidebeam.scene import SceneError

    check = slidebeam.run.model.check_memory

    def refuse_alone(scene, comm=None):
        if comm is not None and comm.Get_size() == 1:
            raise SceneError("needs more memory than this node has", scene.file, "[[beam]]", "spans")
        return check(scene, comm)

    from test_condensation import petsc_options

    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "ropeway.toml", ["analysis.t_end=0.002"])
    with petsc_options(sb_equilibrium_on_rank_0="true"):
        sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
    monkeypatch.setattr(slidebeam.run.model, "check_memory", refuse_alone)
    sim.settle()
    assert sim.settled.converged and not sim.settled_on_rank_0
    assert any("rank 0 alone cannot hold the model" in w for w in sim.warnings)


@pytest.mark.skip_in_parallel
@pytest.mark.spawns_ranks
def test_iterative_solver_path_gives_the_direct_solvers_history(run_cli, tmp_path):
    """runs/cables/iterative.opts (GMRES + Schwarz on the model's subdomains), on one rank and
    on two (two subdomains, joints across them), reproduces the direct LU's run to the Newton
    tolerance, with a few GMRES iterations per solve (no fallback to the direct LU)."""
    import csv
    import re

    scene = str(ROOT / "runs" / "cables" / "ropeway.toml")
    opts = str(ROOT / "runs" / "cables" / "iterative.opts")
    common = ["--set", "analysis.t_end=0.03", "--set", "output.xdmf=false", "-q"]
    runs = {"lu": run_cli("run", scene, "--out", "lu", *common),
            "gmres1": run_cli("run", scene, "--out", "gmres1", *common, "--", "-options_file", opts,
                              "-ksp_converged_reason"),
            "gmres2": run_cli("run", scene, "--out", "gmres2", *common, "--", "-options_file", opts,
                              "-ksp_converged_reason", np=2)}
    for name, res in runs.items():
        assert res.returncode == 0, (name, res.stderr)
        if name != "lu":
            its = [int(n) for n in re.findall(r"Linear (?:\w+ )?solve converged due to \w+ iterations (\d+)", res.stdout)]
            assert its and max(its) <= 10, (name, its[:20])
            assert not re.search(r"Linear (\w+ )?solve did not converge", res.stdout)
    rows = {name: list(csv.DictReader((tmp_path / name / "history.csv").open())) for name in runs}
    tracked = [k for k in rows["lu"][0] if k.startswith("hanger") and "@" in k]  # tracked points
    assert tracked
    for name in ("gmres1", "gmres2"):
        assert len(rows[name]) == len(rows["lu"])
        for a, b in zip(rows["lu"], rows[name]):
            for k in tracked + ["total_energy"]:
                assert abs(float(a[k]) - float(b[k])) <= 1e-8 * max(1.0, abs(float(a[k]))), (name, a["t"], k)


def test_a_rank_ghosts_only_windows_of_the_carriers_it_does_not_own(tmp_path):
    """Meaningful under mpirun: each joint ghosts the carrier points around its s (a window that
    follows the slider), not its whole carrier; a long carrier split over ranks is then ghosted
    only at the rank boundary and at the joints' windows."""
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(cable_scene(tmp_path, 1, 256, 4, "--start", "reference")))
    lo, hi = sim.x.getOwnershipRange()
    window = 4 * 18 * (3 + 2 * 4 + 2)  # joints x (touched points + 2 x margin + slack) x unknowns per point
    carrier = 18 * 258
    assert sim._model.ghost_count <= (hi - lo) + window + 18 * 4
    assert window < carrier / 4  # the bound is meaningful: far below ghosting the whole carrier
    for _ in range(3):
        assert sim.integrator.step(1e-3).converged
