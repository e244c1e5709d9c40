# SPDX-License-Identifier: MIT
"""Every shipped scene of runs/effects/ (damping, driven supports and sliders, drag, friction):
under energy-momentum the energy balance |H - H0 - W + D| closes to the Newton tolerance (1e-9
of the largest energy the run holds or moves: kinetic, stored, worked or dissipated) over the
scene's first steps, and something happens in them (W or D is not zero), so the check
cannot pass on a scene where no effect acts."""
from __future__ import annotations

from pathlib import Path

import pytest

import slidebeam

EFFECTS = Path(__file__).resolve().parents[2] / "runs" / "effects"
STEPS = 40


@pytest.mark.parametrize("name", sorted(p.name for p in EFFECTS.glob("*.toml")))
def test_shipped_effect_scene_closes_its_energy_balance(name):
    scene = slidebeam.load_scene(EFFECTS / name)
    assert scene.analysis.integrator == "energy-momentum", "the shipped effect scenes run energy-momentum"
    dt = scene.analysis.dt
    scene = slidebeam.load_scene(EFFECTS / name, [f"analysis.t_end={STEPS * dt!r}"])
    records = slidebeam.Simulation(scene).run_dynamic().records
    assert len(records) >= STEPS // scene.output.every
    scale = max(max(r.kinetic_energy, abs(r.strain_energy) + abs(r.potential_energy), abs(r.work), r.dissipated)
                for r in records)
    assert scale > 0.0
    assert max(abs(r.work) + r.dissipated for r in records) > 1e-6 * scale, "no effect acted"
    assert max(r.energy_balance_error for r in records) <= 1e-9 * scale
