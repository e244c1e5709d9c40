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


def lu_nonzeros_per_unknown(scene: Path, ordering: str) -> float:
    import slidebeam

    sim = slidebeam.Simulation(slidebeam.load_scene(scene), MPI.COMM_SELF)
    assert sim.integrator.step(1e-3).converged
    A = sim.jacobian.duplicate(copy=True)
    if ordering == "sb_model":
        order = PETSc.IS().createGeneral(sim.elimination_order(), comm=PETSc.COMM_SELF)
        A.compose("sb_elimination_order", order)
    pc = PETSc.PC().create(PETSc.COMM_SELF)
    pc.setOperators(A)
    pc.setType("lu")
    pc.setFactorSolverType("petsc")
    pc.setFactorOrdering(ordering)
    pc.setUp()
    return pc.getFactorMatrix().getInfo()["nz_used"] / A.getSize()[0]


def test_factorisation_fill_grows_linearly_with_the_scene(tmp_path):
    """Four times the carrier length and four times the hangers: with the model's order (sliders
    before carriers, multipliers next to their coordinates) the LU's nonzeros per unknown stay
    the same; in the natural order (extras last) each joint fills its carrier from the joint to
    the carrier's end, so the fill per unknown grows with the scene (the test can fail)."""
    small, big = cable_scene(tmp_path, 1, 32, 4), cable_scene(tmp_path, 1, 128, 16)
    model = [lu_nonzeros_per_unknown(s, "sb_model") for s in (small, big)]
    natural = [lu_nonzeros_per_unknown(s, "natural") for s in (small, big)]
    assert model[1] / model[0] < 1.05, model
    assert natural[1] / natural[0] > 1.3, natural
    assert model[1] < 0.7 * natural[1]


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
        assert position[first_extra] > position[18 * (slider + 2) + 17]
        assert position[first_extra] < position[18 * carrier]
