# SPDX-License-Identifier: MIT
"""Mooring lines at rest against published references (docs/verification.md, "Mooring lines:
published cases"): the quasi-static chain cases MoorDyn validates against (50, 200 and 600 m of
water) and Lowe & Langley's flexible jumper (OMAE 2006). The scenes are those of
scripts/compare_mooring.py (--chains, --jumper), which prints the tables with MoorPy and MoorDyn
beside them."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import slidebeam
from slidebeam.scene.catenary import MooringLine

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.skip_in_parallel  # closed forms; contact and buoyancy on 2 ranks: test_contact.py


def compare_mooring():
    spec = importlib.util.spec_from_file_location("compare_mooring", ROOT / "scripts" / "compare_mooring.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# depth: MoorDyn's segments (10 m), and the errors allowed against the quasi-static codes' tensions
# (fairlead, anchor). At 50 m the elastic catenary of the line as stated is itself 1.02 % and
# 1.14 % above them (slidebeam 1.04 % and 1.17 % at 5 m spans): the rest is the reference's.
CASES = {50.0: (82, 0.0125, 0.0125), 200.0: (76, 0.01, 0.01), 600.0: (170, 0.01, 0.01)}


@pytest.mark.parametrize("depth", CASES)
def test_the_published_chain_cases_rest_at_the_quasi_static_tensions(depth):
    """Fairlead and anchor tension after the equilibrium start against the quasi-static codes'
    (1 %; 50 m: 1.25 %, see CASES) and the elastic catenary on a rigid frictionless bed (3e-3;
    measured 0.2e-3 to 1.6e-3, the bed's 0.3 mm sink and the spans), and the touch-down point
    (1.5 %, the sampling of the 10 m spans)."""
    m = compare_mooring()
    spans, tol_fairlead, tol_anchor = CASES[depth]
    span, length, _, T_ref, A_ref = m.CHAIN_CASES[depth]
    fairlead, anchor, touchdown, _ = m.chain_at_rest(depth, spans)
    exact = MooringLine(span=span, height=depth, length=length, EA=m.CHAIN_EA, w=m.CHAIN_W)
    assert fairlead == pytest.approx(1e3 * T_ref, rel=tol_fairlead)
    assert anchor == pytest.approx(1e3 * A_ref, rel=tol_anchor)
    assert fairlead == pytest.approx(exact.fairlead_tension, rel=3e-3)
    assert anchor == pytest.approx(exact.anchor_tension, rel=3e-3)
    assert touchdown == pytest.approx(exact.touchdown, rel=1.5e-2)


def test_the_jumper_rests_at_lowe_and_langleys_end_forces():
    """The end forces of Lowe & Langley's jumper (11.40 and 45.71 kN at the top, -11.40 and
    24.04 kN at the bottom) within 0.1 kN (measured 0.03 kN at 68 spans); its bending stiffness
    matters: the catenary without it pulls 11.47 kN horizontally."""
    m = compare_mooring()
    top, bottom, _ = m.jumper_at_rest(68)
    assert np.abs(top / 1e3 - np.array(m.JUMPER_TOP)).max() < 0.1
    assert np.abs(bottom / 1e3 - np.array(m.JUMPER_BOTTOM)).max() < 0.1
    assert abs(top[1]) < 1e-6 and top[0] / 1e3 < 11.47 - 0.05


# case: the largest error of slidebeam's top tension allowed, kN (measured at 68 spans, dt = 0.05 s)
JUMPER_CASES = {1: 0.6, 2: 0.5, 3: 1.0}


@pytest.mark.parametrize("case", JUMPER_CASES)
def test_the_jumper_follows_lowe_and_langleys_top_tension(case):
    """Lowe & Langley's dynamic cases 1-3 (the top moved 10 m along x, y, z at a period of 27 s):
    the top tension over the 80 s after the ramp within 1 kN of the reference at every one of its
    samples (measured 0.42, 0.29 and 0.82 kN; 0.96 and 1.67 kN for cases 1 and 3 without the added
    mass), and its range within 0.3 kN."""
    m = compare_mooring()
    r = m.jumper_moving(case, 68, 0.05)
    assert np.abs(r["slidebeam"] - r["reference"]).max() < JUMPER_CASES[case]
    assert abs(r["slidebeam"].min() - r["reference"].min()) < 0.3
    assert abs(r["slidebeam"].max() - r["reference"].max()) < 0.3
    if case == 3:  # without the water's mass the tension swings less
        dry = m.jumper_moving(case, 68, 0.05, added_mass=False)
        assert np.abs(dry["slidebeam"] - dry["reference"]).max() > 1.0

def test_the_heaved_mooring_line_lifts_off_and_lands_without_a_cut_step():
    """runs/cables/mooring_heave.toml over its first heave (10 s): the fairlead's 4 m lift raises
    over 10 m of chain off the seabed and lays it down again, the fairlead tension swinging by
    over 300 kN; the bed's damping, set in over its damping_depth, keeps Newton from chattering
    at touch-down (no step cut; switched on whole at contact, 15 cuts in 40 s), and the energy
    balance closes to 1e-9 of the support's work (measured 2e-10)."""
    scene = slidebeam.load_scene(ROOT / "runs" / "cables" / "mooring_heave.toml")
    data = dict(scene.data)
    data["analysis"] = {**data["analysis"], "t_end": 10.0}
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(data))
    run = sim.run_dynamic()
    records = run.records
    assert sum(r.rejected_steps for r in records) == 0
    k = sim.output_labels().index("plane_contact[chain].length")
    grounded = np.array([r.outputs[k] for r in records])
    tension = np.array([np.linalg.norm(r.reactions[1].force) for r in records])
    assert grounded[0] - grounded.min() > 10.0 and grounded[-1] > grounded.min() + 10.0
    assert np.ptp(tension) > 3e5
    scale = max(max(r.kinetic_energy, abs(r.work), r.dissipated) for r in records)
    assert max(r.energy_balance_error for r in records) <= 1e-9 * scale
    assert records[-1].dissipated > 0.0
