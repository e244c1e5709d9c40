# SPDX-License-Identifier: MIT
"""The numbering of control points (Model::numbering_order, DofMap): a beam hanging from another
is numbered among the carrier points it hangs from, so that splitting the numbering over ranks
keeps each hanger on the rank of its stretch of carrier and the ranks' interface small."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI
from petsc4py import PETSc

import slidebeam
from checks import distributed_and_serial_records

ROOT = Path(__file__).resolve().parents[2]


def ropeway(tmp_path: Path, spans: int, hangers: int, *extra: str) -> slidebeam.Scene:
    out = tmp_path / "ropeway.toml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--carriers", "1", "--spans",
                    str(spans), "--hangers", str(hangers), "--start", "reference", *extra, "--out", str(out)],
                   check=True, capture_output=True)
    return slidebeam.load_scene(out)


def attachments(sim: slidebeam.Simulation) -> list[tuple[int, int]]:
    """(a hanger's first control point, the carrier control point nearest its top) per joint:
    the carrier's control points lie at the Greville abscissae 0, h/2, 3h/2, ..., L."""
    carrier = sim.scene.beams[0]
    h = carrier.geometry.length / carrier.spans
    pairs = []
    for joint, state in zip(sim.scene.sliding_joints, sim.joint_states()):
        nearest = min(carrier.spans + 1, max(0, int(round(state.s / h + 0.5))))
        pairs.append((sim.first_control_point(joint.slider), sim.first_control_point(0) + nearest))
    return pairs


def owner(sim: slidebeam.Simulation, cp: int) -> int:
    """The rank that owns control point cp (collective)."""
    first, _ = sim.control_point_unknowns(cp)
    lo, hi = sim.x.getOwnershipRange()
    return MPI.COMM_WORLD.allreduce(MPI.COMM_WORLD.Get_rank() if lo <= first < hi else 0, op=MPI.SUM)


def test_hangers_are_numbered_among_the_carrier_points_they_hang_from(tmp_path):
    """Each hanger's unknowns lie within a few control points' slots of the carrier point it
    hangs from (in scene order they would come after the whole carrier)."""
    sim = slidebeam.Simulation(ropeway(tmp_path, 32, 4))
    slot = 18
    carrier_end, _ = sim.control_point_unknowns(sim.first_control_point(0) + 33)
    for hanger, carrier in attachments(sim):
        a, _ = sim.control_point_unknowns(hanger)
        b, _ = sim.control_point_unknowns(carrier)
        assert abs(a - b) <= 8 * slot, (hanger, carrier, a, b)
        assert a < carrier_end  # not after the whole carrier
    order = sim.elimination_order()  # the factorisation's order is its own: sliders first
    assert sorted(order) == list(range(sim.x.getSize()))


@pytest.mark.skipif(MPI.COMM_WORLD.Get_size() != 2, reason="two ranks: mpirun -n 2")
def test_two_ranks_cut_a_ropeway_once(tmp_path):
    """A 400-span carrier with 40 sliding hangers (10276 unknowns) on 2 ranks: every hanger but
    the one at the cut on the rank of its carrier stretch, and so few interface unknowns that
    the exact correction (one block application per solve) is taken."""
    scene = ropeway(tmp_path, 400, 40, "--t-end", "0.002", "--dt", "1e-3")
    sim = slidebeam.Simulation(scene, MPI.COMM_WORLD)
    cut = sum(owner(sim, hanger) != owner(sim, carrier) for hanger, carrier in attachments(sim))
    assert cut <= 1
    sizes = MPI.COMM_WORLD.allgather(sim.x.getLocalSize())
    assert max(sizes) < 0.55 * sum(sizes)  # about half each
    outcome = sim.run_dynamic()
    assert outcome.complete and sim.snes.getKSP().getType() == PETSc.KSP.Type.PREONLY
    # summary.json says so: every step Jacobian solved by one application plus the correction
    from slidebeam.output.results import dynamic_summary, parallel_line

    summary = dynamic_summary(sim, outcome)
    p = summary["parallel"]
    assert p["jacobians_solved_by"] == {"one block application": 0,
                                        "block application and coupling correction": sim.integrator.jacobian_evaluations,
                                        "GMRES": 0}
    assert 0 < p["coupled_rows"] <= 48 and sum(p["unknowns_per_rank"]) == sim.x.getSize()
    assert not p["pivoting_lu"] and p["static_start"] is None
    assert "coupling correction" in parallel_line(summary)


@pytest.mark.skipif(MPI.COMM_WORLD.Get_size() != 2, reason="two ranks: mpirun -n 2")
def test_a_slider_stencil_is_never_cut(tmp_path):
    """Three carriers with 8 hangers each: the split falls inside the middle carrier's numbering,
    between a hanger's points. The points a joint's multipliers take their pivots from (the
    slider point's stencil) stay on the rank of the multipliers, so every block is regular: no
    step is rejected and every solve is one block application (with the stencil cut, a block
    met a zero pivot and every step fell back to MUMPS)."""
    out = tmp_path / "three.toml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make_cables.py"), "--carriers", "3", "--spans", "64",
                    "--hangers", "8", "--start", "reference", "--t-end", "0.003", "--out", str(out)],
                   check=True, capture_output=True)
    sim = slidebeam.Simulation(slidebeam.load_scene(out), MPI.COMM_WORLD)
    outcome = sim.run_dynamic()
    assert outcome.complete and outcome.rejected_steps == 0
    assert sim.snes.getKSP().getType() == PETSc.KSP.Type.PREONLY and not sim.integrator.pivoting_lu


def test_a_ropeway_distributed_equals_serial(tmp_path):
    """The numbering changes where the unknowns live, not the run: a ropeway on all ranks steps
    as on one."""
    assert len(distributed_and_serial_records(ropeway(tmp_path, 48, 6, "--t-end", "0.02", "--dt", "2e-3"))) >= 2
