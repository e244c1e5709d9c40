# SPDX-License-Identifier: MIT
"""Cable nets (scripts/make_cables.py --net): ropes welded where they cross, so that the beams
form loops. At a crossing the four rope ends are held by three rigid joints; each joint's
multipliers take their pivots from a point of their own (Model::resolve_anchors), and the net's
points are eliminated in a fill-reducing order (Model::loop_structure_orders)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

from checks import hanger_toml
from test_cables import lu_nonzeros_per_unknown

ROOT = Path(__file__).resolve().parents[2]


def net_scene(tmp_path: Path, k: int, spans: int) -> Path:
    out = tmp_path / f"net_{k}_{spans}.toml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--net", str(k), "--spans", str(spans),
                    "--t-end", "0.005", "--out", str(out)], check=True, capture_output=True)
    return out


def test_a_net_steps_on_the_condensed_lu_without_pivoting(tmp_path):
    """With the three joints of a crossing anchored at one rope end, that end's 6 degrees of
    freedom would have to give pivots to 18 multipliers: the LU meets zero pivots and the steps
    fall back to the pivoting LU (the test can fail: it did before the anchors were matched)."""
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(net_scene(tmp_path, 3, 2)), MPI.COMM_SELF)
    for _ in range(3):
        assert sim.integrator.step(1e-3).converged
    assert not sim.integrator.pivoting_lu


def test_a_nets_factorisation_fill_grows_slowly_with_its_width(tmp_path):
    """A net 4x as wide (16x the unknowns): in the model's order (nested loops eliminated by
    minimum degree) the LU's nonzeros per unknown grow by a third; in the numbering's band
    order they grow with the width (4.8x from 3 to 12 ropes)."""
    small, big = net_scene(tmp_path, 3, 2), net_scene(tmp_path, 12, 2)
    model = [lu_nonzeros_per_unknown(s, "sb_model") for s in (small, big)]
    band = [lu_nonzeros_per_unknown(s, "natural") for s in (small, big)]
    assert model[1] / model[0] < 1.5, model
    assert band[1] / band[0] > 3.0, band
    assert model[1] < 0.3 * band[1], (model, band)


def test_a_net_runs_the_same_on_all_ranks_and_on_one(tmp_path):
    """Meaningful under mpirun: the split cuts ropes, the steps take the coupling correction, and
    the history equals the serial one. The net is numbered along its longer side, so that on 2
    ranks the split is a straight cut across the 4 ropes of one direction, 24 coupled rows each
    (split between breadth-first levels, diagonally across the net, it had 210 rows)."""
    import slidebeam

    scene = slidebeam.load_scene(net_scene(tmp_path, 4, 2))
    world_sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
    world = world_sim.run_dynamic().records
    alone = slidebeam.Simulation(scene, MPI.COMM_SELF).run_dynamic().records
    assert not world_sim.integrator.pivoting_lu
    if MPI.COMM_WORLD.Get_size() == 2:
        solves = world_sim.integrator.parallel_solves
        assert 0 < solves["coupled_rows"] <= 4 * 24, solves
        assert solves["corrected"] > 0 and solves["krylov"] == 0, solves
    assert len(world) == len(alone) > 1
    for a, b in zip(world, alone):
        for p, q in zip(a.tracked, b.tracked):
            assert max(abs(u - v) for u, v in zip(p, q)) < 1e-10


@pytest.mark.skipif(MPI.COMM_WORLD.Get_size() != 2, reason="two ranks: mpirun -n 2")
def test_a_net_cut_wider_than_the_limit_is_owned_by_rank_0(tmp_path):
    """Meaningful under mpirun (2 ranks): the 4x4 net's straight cut leaves each rank 8 control
    points next to the other's (4 ropes, 2 points a side); with -sb_serial_above_cut below that,
    rank 0 owns the whole model (the coupling correction's set-up would cost more than the split
    saves on nets cut across many ropes), and the run says why."""
    import slidebeam
    from slidebeam.output.results import parallel_line, parallel_summary
    from test_condensation import petsc_options

    scene = slidebeam.load_scene(net_scene(tmp_path, 4, 2))
    split = slidebeam.Simulation(scene, MPI.COMM_WORLD)
    assert split.cut_points == 8
    assert all(n > 0 for n in MPI.COMM_WORLD.allgather(split.x.getLocalSize()))
    with petsc_options(sb_serial_above_cut="7"):
        alone = slidebeam.Simulation(scene, MPI.COMM_WORLD)
        assert alone.cut_points == 8
        assert MPI.COMM_WORLD.allgather(alone.x.getLocalSize()) == [alone.x.getSize(), 0]
        assert alone.integrator.step(1e-3).converged
        line = parallel_line({"parallel": parallel_summary(alone)})
    assert "rank 0 owns all" in line and "8 control points" in line, line


def test_the_run_header_groups_a_nets_beams(tmp_path):
    """A net has hundreds of beams: the run's header lists beams described alike as one line
    (a scene of a dozen beams or fewer lists each)."""
    import slidebeam
    from slidebeam.app.cli import BEAMS_LISTED, _describe

    header = _describe(slidebeam.load_scene(net_scene(tmp_path, 3, 2))).splitlines()
    assert header[1].startswith("  24 beams (x0_0 ... y2_3): line, L = 5, 2 spans"), header
    assert len(header) == 3, header
    few = _describe(slidebeam.load_scene(ROOT / "runs" / "right_angle_cantilever.toml")).splitlines()
    assert [line.split(":")[0] for line in few[1:3]] == ["  beam leg1", "  beam leg2"]
    assert BEAMS_LISTED < 24


def test_a_hanger_sliding_on_a_net_is_eliminated_before_the_net(tmp_path):
    """The net is one unit of the elimination order, and a slider's beam comes before its
    carrier's: the hanger (last in the scene) and its joint's extras come before every point of
    the net, so that the joint's fill stays in a window of the net (the test can fail: the net
    was emitted at its first beam, before the hanger)."""
    import slidebeam

    scene = net_scene(tmp_path, 3, 2)
    scene.write_text(scene.read_text() + hanger_toml("x1_1", (7.5, 10.0, 0.0), 1.0))
    sim = slidebeam.Simulation(slidebeam.load_scene(scene), MPI.COMM_SELF)
    order = sim.elimination_order()
    assert sorted(order) == list(range(sim.x.getSize()))
    position = {old: new for new, old in enumerate(order)}
    first_extra = sim.sliding_coordinate_index(0) - 3
    net_points = [cp for beam in sim.scene.beams if beam.name != "hanger"
                  for cp in range(sim.first_control_point(beam.name), sim.first_control_point(beam.name) + beam.spans + 2)]
    first_net = min(position[sim.control_point_unknowns(cp)[0]] for cp in net_points)
    assert position[first_extra] < first_net
    assert sim.integrator.step(1e-3).converged and not sim.integrator.pivoting_lu


def test_a_falling_net_keeps_its_energy_under_energy_momentum(tmp_path):
    """The net falls from its flat drawing for 20 steps: the energy it gains in motion and strain
    is the potential energy it loses, to the Newton tolerance (welds and supports do no work)."""
    import slidebeam

    scene = net_scene(tmp_path, 4, 2)
    scene.write_text(scene.read_text().replace("t_end = 0.005", "t_end = 0.02"))
    last = slidebeam.Simulation(slidebeam.load_scene(scene), MPI.COMM_SELF).run_dynamic().records[-1]
    assert last.t == 0.02 and last.kinetic_energy > 1.0
    assert abs(last.total_energy) < 1e-10 * last.kinetic_energy, last.total_energy


@pytest.mark.skip_in_parallel
def test_a_boulder_dropped_into_a_net_is_caught_and_the_energy_balance_closes(tmp_path):
    """make_cables.py --net 3 --boulder 50: a rock (a rigid body carrying a contact sphere) falls
    at 10 m/s into a damped net; the net turns it back (its centre rises again after its lowest
    point), the damping takes energy, and the balance kinetic + strain + potential + dissipated
    closes to 1e-9 of the energy dissipated; the steps stay on the condensed LU without pivoting."""
    import numpy as np

    import slidebeam

    out = tmp_path / "rock.toml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--net", "3", "--spans", "2",
                    "--length", "1.5", "--boulder", "50", "--drop", "0.1", "--damping", "0.01", "--t-end", "0.15",
                    "--dt", "0.002",
                    "--out", str(out)], check=True, capture_output=True)
    sim = slidebeam.Simulation(slidebeam.load_scene(out), MPI.COMM_SELF)
    run = sim.run_dynamic()
    assert run.complete and run.records[-1].rejected_steps == 0, run.message
    z = np.array([r.tracked[-1][2] for r in run.records])
    low = int(np.argmin(z))
    assert 0 < low < len(z) - 1 and z[-1] > z[low]
    dissipated = run.records[-1].dissipated
    assert dissipated > 10.0
    assert max(abs(r.energy_balance_error) for r in run.records) <= 1e-9 * dissipated
    assert not sim.integrator.pivoting_lu
