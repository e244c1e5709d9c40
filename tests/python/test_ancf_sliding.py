# SPDX-License-Identifier: MIT
"""Sliding joints with ANCF cables (issue 9): the seed's S2 scenes with the carrier AB, the slider
CM or both as cables. Exact step Jacobians of every integrator with s on one side of a node and
across one and two nodes within a step; energy through element transitions under
energy-momentum (the exact discrete derivative of the Hermite curve); every integrator runs;
distributed == serial."""
from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

import slidebeam
from petsc4py import PETSc

from checks import check_joint_step_jacobian, distributed_and_serial_records

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "runs" / "seed"
INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
NEWTON_ATOL = 1e-10  # the SNES absolute tolerance (solvers/newton.cpp)


def as_cables(data: dict, cables: tuple[str, ...]) -> dict:
    """The seed scene with the named beams as ANCF cables: same geometry, spans = elements, the
    same square section (E, rho; a cable has no shear or torsion, so no nu)."""
    for beam in data["beam"]:
        if beam["name"] in cables:
            beam["formulation"] = "ancf"
            for key in ("d2", "quadrature"):
                beam.pop(key, None)
            beam["section"] = {k: v for k, v in beam["section"].items() if k != "nu"}
    return data


def seed_scene(name: str = "free_fall_inclined_1+4", cables: tuple[str, ...] = ("AB",), analysis: dict | None = None,
               joint: dict | None = None) -> slidebeam.Scene:
    with open(SEED / f"{name}.toml", "rb") as f:
        data = as_cables(tomllib.load(f), cables)
    data["analysis"].update(analysis or {})
    data["sliding_joint"][0].update(joint or {})
    return slidebeam.scene_from_dict(data, file=f"{name}.toml (cables {', '.join(cables)})", base_dir=str(SEED))


CASES = ([("AB", i, "exact", ds) for i in INTEGRATORS for ds in (0.03, 0.17, 0.71)] +
         [("AB", "energy-momentum", "midpoint", ds) for ds in (0.03, 0.71)] +
         [(c, i, "exact", 0.71) for c in ("CM", "AB+CM") for i in INTEGRATORS])


@pytest.mark.parametrize("cables,integrator,form,ds", CASES)
def test_step_jacobian_is_exact_across_nodes(cables, integrator, form, ds):
    """s_n = 0.4 and s_n+1 = s_n + ds on the 4-element carrier (nodes at 0.5, 1.0, 1.5): the same
    element (0.03), across the node at 0.5 (0.17), across 0.5 and 1.0 (0.71). The Jacobian is the
    derivative of the step residual (central finite differences)."""
    sim = slidebeam.Simulation(seed_scene(cables=tuple(cables.split("+")),
                                          analysis={"integrator": integrator, "dt": 0.01},
                                          joint={"discrete_gradient": form}))
    check_joint_step_jacobian(sim, ds, f"{cables} {integrator}/{form}")


def energy_run(cables: tuple[str, ...], form: str = "exact", name: str = "free_fall_inclined_1+4"):
    run = slidebeam.Simulation(seed_scene(name, cables, joint={"discrete_gradient": form})).run_dynamic()
    H = np.array([r.total_energy for r in run.records])
    K = max(r.kinetic_energy for r in run.records)
    s = np.array([r.joints[0].s for r in run.records])
    return run, np.abs(H - H[0]).max() / K, s


@pytest.mark.parametrize("cables", [("AB",), ("CM",), ("AB", "CM")])
def test_energy_momentum_conserves_energy_through_element_transitions(cables):
    """S2-incl, 1+4 mesh, dt = 1e-3, EM: C crosses the nodes (knots) at 0.5, 1.0 and 1.5 and
    reaches the carrier end; the total energy stays within 10x the Newton tolerance of its start,
    relative to the largest kinetic energy, and the constraints hold to the Newton tolerance."""
    run, drift, s = energy_run(cables)
    assert not run.complete and not run.failed and "reached the end of carrier 'AB'" in run.message
    assert all(s.min() < knot < s.max() for knot in (0.5, 1.0, 1.5))
    assert drift <= 10 * NEWTON_ATOL, f"{cables}: energy drift {drift:.3e}"
    assert max(r.constraint_residual for r in run.records) <= NEWTON_ATOL


def test_midpoint_form_does_not_conserve_energy_on_a_cable_carrier():
    """The seed's midpoint-evaluated derivative N'(s_mid) is not the secant of the cubic Hermite
    curve even inside one element (N'' is linear there, not constant as for the B-spline): the
    joint does work, far outside the exact form's band."""
    run, drift, s = energy_run(("AB",), "midpoint")
    exact_run, exact_drift, s_exact = energy_run(("AB",))
    n = min(len(s), len(s_exact))
    assert np.abs(s[:n] - s_exact[:n]).max() < 1e-4  # the same motion, to the scheme's error
    assert drift > 100 * NEWTON_ATOL and drift > 1e3 * exact_drift, (drift, exact_drift)


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_every_integrator_runs_the_joint_on_cables(integrator):
    """Short run, carrier and slider cables: constraints at solver tolerance, C moves along AB
    towards mid-span, as with director beams."""
    sim = slidebeam.Simulation(seed_scene("free_fall_1+4", ("AB", "CM"), {"integrator": integrator, "t_end": 0.1}))
    assert sim.joint_states()[0].s == pytest.approx(0.4, abs=1e-12)
    run = sim.run_dynamic()
    assert run.complete
    assert max(r.constraint_residual for r in run.records) <= NEWTON_ATOL
    assert run.records[-1].joints[0].s > 0.4


def test_cable_joint_follows_the_director_joint():
    """S2 1+4 to t = 0.3 with AB as a cable against AB as a director beam: slender beams (EI/EA
    ~ 2e-6 m^2), so the cable model differs only in what it leaves out (shear, torsion, rotary
    inertia): the sliding coordinate agrees to 1e-3."""
    runs = [slidebeam.Simulation(seed_scene("free_fall_1+4", c, {"t_end": 0.3})).run_dynamic() for c in ((), ("AB",))]
    s = [np.array([r.joints[0].s for r in run.records]) for run in runs]
    assert all(run.complete for run in runs) and len(s[0]) == len(s[1])
    assert np.abs(s[0] - s[1]).max() < 1e-3


@pytest.mark.parametrize("cables", [("AB",), ("CM",)])
def test_distributed_equals_serial(cables):
    """Meaningful under mpirun -n 2: the cable's nodes and the joint's unknowns live on different
    ranks, and the joint's ghost window moves along the carrier."""
    for a, b in distributed_and_serial_records(seed_scene("free_fall_inclined_1+4", cables, {"t_end": 0.4})):
        assert abs(a.joints[0].s - b.joints[0].s) < 1e-10
        assert np.abs(np.array(a.joints[0].reaction) - np.array(b.joints[0].reaction)).max() < 1e-8
