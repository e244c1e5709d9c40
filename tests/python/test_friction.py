# SPDX-License-Identifier: MIT
"""Friction on a sliding joint ([[friction]]: regularised Coulomb from the joint's normal force):
a block on a rigid inclined rail slides with s'' = -g (sin a - mu cos a) and, for tan a < mu,
only creeps at the regularisation's rate; the step dissipates and the energy balance closes under
energy-momentum; step Jacobians against finite differences under every integrator (both joint
forms); 1 rank = 2 ranks."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from mpi4py import MPI

import slidebeam
from checks import distributed_and_serial_records, step_jacobian_error, trial_end_state
from test_dynamics import INTEGRATORS

BLOCK = "runs/effects/friction_block.toml"
SEED = "runs/seed/free_fall_1+4.toml"
G, ALPHA = 9.80665, math.radians(30.0)


def block(root, mu: float, regularization: float, t_end: float = 1.0, dt: float = 1e-3) -> slidebeam.Scene:
    scene = slidebeam.load_scene(root / BLOCK, [f"analysis.t_end={t_end}", f"analysis.dt={dt}"])
    data = dict(scene.data)
    data["friction"] = [{"beam": "block", "mu": mu, "regularization": regularization}]
    return slidebeam.scene_from_dict(data, file=str(root / BLOCK), base_dir=str(root / "runs" / "effects"))


def s_history(scene: slidebeam.Scene) -> tuple[np.ndarray, np.ndarray, list]:
    records = slidebeam.Simulation(scene).run_dynamic().records
    return np.array([r.t for r in records]), np.array([r.joints[0].s for r in records]), records


def test_a_sliding_block_accelerates_as_the_closed_form(root):
    """mu = 0.3 < tan 30 deg: s'' = -g (sin a - mu cos a). The regularised force falls short of
    mu N by mu N (1 - sdot / sqrt(sdot^2 + v^2)) ~ mu N v^2 / (2 sdot^2): with v = 1e-7 m/s and
    sdot > 0.2 m/s that is below 1e-12 g, so the measured acceleration (second differences of s,
    which the midpoint-type step integrates exactly for a constant force) matches to 1e-9.
    Measured by a parabola through s(t) over t >= 0.2 s: second differences of records 0.01 s
    apart amplify the Newton tolerance's ~1e-12 in s to ~3e-8."""
    t, s, records = s_history(block(root, 0.3, 1e-7))
    exact = -G * (math.sin(ALPHA) - 0.3 * math.cos(ALPHA))
    late = t >= 0.2
    c = np.polyfit(t[late] - 0.6, s[late], 2)
    assert abs(2 * c[0] - exact) <= 1e-9 * G, 2 * c[0] - exact
    assert np.abs(np.polyval(c, t[late] - 0.6) - s[late]).max() <= 1e-10
    K = max(r.kinetic_energy for r in records)
    assert max(r.energy_balance_error for r in records) <= 1e-9 * K


@pytest.mark.parametrize("v_reg", (1e-3, 1e-4))
def test_a_block_held_by_friction_only_creeps(root, v_reg):
    """mu = 0.7 > tan 30 deg: the block sticks, up to the regularisation's creep, at the rate
    where mu N sdot / sqrt(sdot^2 + v^2) = m g sin a: |sdot| = v r / sqrt(1 - r^2), r = tan a / mu,
    proportional to v."""
    t, s, _ = s_history(block(root, 0.7, v_reg, t_end=0.3))
    r = math.tan(ALPHA) / 0.7
    creep = v_reg * r / math.sqrt(1 - r * r)
    speed = np.abs(np.diff(s)) / np.diff(t)
    assert speed.max() <= 1.01 * creep
    assert speed[-1] == pytest.approx(creep, rel=1e-3)
    assert abs(s[-1] - s[0]) <= 1.01 * creep * t[-1]


def test_friction_dissipates_and_the_balance_closes(root):
    """Under energy-momentum each step dissipates -F ds = mu N h sdot^2 / sqrt(sdot^2 + v^2) >= 0;
    H - H0 - W + D stays at the Newton tolerance, and D is the lost mechanical energy; without
    friction D = 0 and the block slides with g sin a."""
    t, s, records = s_history(block(root, 0.3, 1e-3, t_end=0.5))
    K = max(r.kinetic_energy for r in records)
    D = [r.dissipated for r in records]
    assert D[-1] > 0.1 * K and all(b >= a for a, b in zip(D, D[1:]))
    assert max(r.energy_balance_error for r in records) <= 1e-10 * K
    # the friction work is mu N |ds| (up to the regularisation): mu m g cos a |s - s0| with m = 1.01 kg
    m = 1.0 + 0.1 * 0.1
    assert D[-1] == pytest.approx(0.3 * m * G * math.cos(ALPHA) * abs(s[-1] - s[0]), rel=1e-3)
    _, s0, free = s_history(block(root, 0.0, 1e-3, t_end=0.5))
    assert all(r.dissipated == 0.0 for r in free)
    assert 2 * (s0[0] - s0[-1]) / t[-1] ** 2 == pytest.approx(G * math.sin(ALPHA), rel=1e-6)


def seed_with_friction(root, integrator: str, form: str, mu: float = 0.4, v_reg: float = 0.05) -> slidebeam.Scene:
    """The seed's flexible carrier and director slider (a swinging beam whose tip slides): the
    normal force depends on the multipliers, the slider's directors and the carrier's tangent."""
    scene = slidebeam.load_scene(root / SEED, [f'analysis.integrator="{integrator}"', "analysis.t_end=0.1"])
    data = dict(scene.data)
    data["sliding_joint"] = [{**data["sliding_joint"][0], "form": form}]
    data["friction"] = [{"beam": "CM", "mu": mu, "regularization": v_reg}]
    return slidebeam.scene_from_dict(data, file=str(root / SEED), base_dir=str(root / "runs" / "seed"))


@pytest.mark.parametrize("sdot", (0.1, 1.0))
@pytest.mark.parametrize("form", ("frame", "spatial"))
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_friction_step_jacobian(root, integrator, form, sdot):
    """sdot = 2 v_reg: where the force bends (its rate term mu N g'(sdot) / h dominates the s
    row); 20 v_reg: saturated, the s row's friction entries are those of N (multipliers, the
    slider's directors, the carrier's tangent)."""
    sim = slidebeam.Simulation(seed_with_friction(root, integrator, form))
    assert "friction" in [e.type for e in sim.active_effects]
    x1 = trial_end_state(sim, steps=3, h=0.01, seed=5)
    lo, hi = x1.getOwnershipRange()
    i_s = sim.sliding_coordinate_index()
    s0 = sim.joint_states()[0].s
    if lo <= i_s < hi:
        x1.setValue(i_s, s0 + 0.01 * sdot)
    x1.assemble()
    worst, scale = step_jacobian_error(sim, x1)
    assert worst <= 1e-6 * scale, f"{integrator}: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"
    # the s row and column on their own scale. Where the force bends, eps = 1e-7 keeps the
    # difference's truncation ~((eps / h) / v_reg)^2 / 6 below 1e-8; saturated, eps = 1e-5 keeps
    # the roundoff of the position rows' residuals (~1e3, in the s column) at 1e-8
    worst, scale = step_jacobian_error(sim, x1, 1e-7 if sdot < 0.5 else 1e-5, [i_s])
    assert scale > 0.1
    assert worst <= 1e-6 * scale, f"{integrator}, s row: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"


def test_friction_block_serial_equals_parallel(root):
    """Meaningful under mpirun -n 2: the joint and its friction on one rank, the rail on both."""
    pairs = distributed_and_serial_records(block(root, 0.3, 1e-3, t_end=0.05))
    for a, b in pairs:
        assert abs(a.dissipated - b.dissipated) <= 1e-10 * max(1.0, abs(b.dissipated))
        assert abs(a.joints[0].s - b.joints[0].s) <= 1e-10


@pytest.mark.parametrize("friction, words", [
    ({"beam": "block", "mu": -0.1}, "mu"),
    ({"beam": "block", "mu": 0.3, "regularization": 0.0}, "regularization"),
    ({"beam": "rail", "mu": 0.3}, "not the slider of a sliding_joint"),
])
def test_friction_is_validated(root, friction, words):
    scene = slidebeam.load_scene(root / BLOCK)
    data = dict(scene.data)
    data["friction"] = [friction]
    with pytest.raises((ValueError, slidebeam.SceneError), match=words):
        slidebeam.Simulation(slidebeam.scene_from_dict(data, file=str(root / BLOCK),
                                                       base_dir=str(root / "runs" / "effects")))


def test_friction_written_before_its_sliding_joint(root):
    """The tables' order in the file does not matter: [[friction]] (and [[slider_drive]]) above
    the [[sliding_joint]] they act on find it, and the run is the same."""
    scene = block(root, mu=0.3, regularization=1e-3, t_end=0.05)
    first = {"friction": scene.data["friction"],
             "slider_drive": [{"beam": "block", "speed": 0.1, "start": 0.01, "stop": 0.04, "ramp": 0.01}],
             **{k: v for k, v in scene.data.items() if k != "friction"}}
    last = {**{k: v for k, v in first.items() if k not in ("friction", "slider_drive")},
            "friction": first["friction"], "slider_drive": first["slider_drive"]}
    assert list(first)[0] == "friction" and list(last)[-1] == "slider_drive"
    runs = []
    for data in (first, last):
        sc = slidebeam.scene_from_dict(data, file=str(root / BLOCK), base_dir=str(root / "runs" / "effects"))
        runs.append(s_history(sc)[1])
    assert np.array_equal(runs[0], runs[1]) and runs[0][-1] != runs[0][0]
