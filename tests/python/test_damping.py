# SPDX-License-Identifier: MIT
"""Structural damping ([[damping]]: Kelvin-Voigt and mass-proportional) and the energy balance
H - H_0 = W - D of dynamic runs: the step Jacobian against finite differences under every
integrator, the logarithmic decrement of a cantilever's first mode against the closed form, the
balance closing to the Newton tolerance under energy-momentum, 1 rank = 2 ranks."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import slidebeam
from checks import check_step_jacobian, distributed_and_serial_records
from test_dynamics import INTEGRATORS, everything_scene


def with_damping(scene: slidebeam.Scene, **damping: object) -> slidebeam.Scene:
    data = dict(scene.data)
    data["damping"] = [{"beam": b.name, **damping} for b in scene.beams]
    return slidebeam.scene_from_dict(data)


@pytest.mark.parametrize("quadrature", ("full", "assumed_strain"))
@pytest.mark.parametrize("integrator", INTEGRATORS + ("energy-momentum, xi = 0.3",))
def test_damping_step_jacobian_matches_finite_differences(integrator, quadrature):
    scene = with_damping(everything_scene(integrator.split(",")[0], quadrature),
                         retardation_times=[0.01, 0.02, 0.03, 0.04, 0.05, 0.06], mass_proportional=0.7)
    if "xi" in integrator:
        scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, em_dissipation=0.3))
    sim = slidebeam.Simulation(scene)
    assert [e.type for e in sim.active_effects].count("beam_damping") == 2
    check_step_jacobian(sim, steps=1, h=0.05, seed=11, label=integrator)  # (Newmark diverges on this scene by its third step)


def test_energy_balance_closes_under_energy_momentum():
    """Every counted term at once: damping (D), a hat force (a time-dependent potential: its
    explicit change is work), a material moment (work), gravity, supports and a rigid joint. H -
    H_0 - W + D stays at the Newton tolerance; D grows monotonically; without damping D = 0.
    (The scene starts at rest: its initial spin does not respect the supports.)"""
    data = dict(everything_scene("energy-momentum", "full").data)
    data["beam"] = [{k: v for k, v in b.items() if k not in ("velocity", "angular_velocity")} for b in data["beam"]]
    scene = with_damping(slidebeam.scene_from_dict(data), retardation_time=0.02, mass_proportional=0.5)
    scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, t_end=1.0, dt=0.01))
    records = slidebeam.Simulation(scene).run_dynamic().records
    K = max(r.kinetic_energy for r in records)
    D = [r.dissipated for r in records]
    assert D[-1] > 1e-3 * K and all(b >= a - 1e-14 for a, b in zip(D, D[1:]))
    assert max(abs(r.work) for r in records) > 1e-3 * K
    worst = max(r.energy_balance_error for r in records)
    assert worst <= 1e-9 * K, f"|H - H0 - W + D| = {worst:.3e} of max K {K:.3e}"
    undamped = dataclasses.replace(scene, effects=())
    assert all(r.dissipated == 0.0 for r in slidebeam.Simulation(undamped).run_dynamic().records)


def test_two_entries_on_one_beam_get_columns_of_their_own(tmp_path):
    """Two [[damping]] entries on one beam (Kelvin-Voigt and mass-proportional given apart): each
    has its own history column (the second numbered #2); they shared one name."""
    data = dict(cantilever(retardation_time=0.01).data)
    data["damping"] = [*data["damping"], {"beam": "rod", "mass_proportional": 0.2}]
    data["analysis"] = {**data["analysis"], "t_end": 0.05}
    sim = slidebeam.Simulation(slidebeam.scene_from_dict(data))
    labels = sim.energy_flow_labels()
    assert len(labels) == len(set(labels))
    assert "beam_damping[rod].dissipated" in labels and "beam_damping[rod]#2.dissipated" in labels
    sim.run_dynamic()


def cantilever(**damping: object) -> slidebeam.Scene:
    """A slender cantilever (L = 1, EI = 1, rhoA = 1; first mode 3.516 rad/s), pushed at the tip by
    a slow hat load (which excites the first mode), then left to ring down."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "dt": 0.005, "t_end": 9.0},
        "beam": [{"name": "rod", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 16, "quadrature": "assumed_strain",
                  "section": {"EA": 1e5, "kGA": 1e5, "GJ": 1.0, "EI2": 1.0, "EI3": 1.0,
                              "rhoA": 1.0, "rhoI2": 1e-6, "rhoI3": 1e-6}}],
        "support": [{"type": "clamp", "beam": "rod", "at": "start"}],
        "load": [{"type": "force", "beam": "rod", "at": "end", "value": [0.0, 0.0, 0.05],
                  "time_function": {"type": "hat", "t0": 0.0, "t1": 0.4, "t2": 0.8}}],
        "damping": [{"beam": "rod", **damping}],
        "output": {"track": [{"beam": "rod", "at": "end"}], "every": 1},  # peaks need every step
    })


def pendulum(**damping: object) -> slidebeam.Scene:
    """A stiff rod (L = 1) hanging from a spherical support, swinging with a small amplitude from
    a rigid initial spin: one mode, w = sqrt(3 g / (2 L)) = 3.836 rad/s, the flexible ones not
    excited. Mass-proportional damping is modal: this mode gets zeta = alpha / (2 w)."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "dt": 0.005, "t_end": 9.0},
        "beam": [{"name": "rod", "start": [0, 0, 0], "end": [0, 0, -1], "spans": 4, "d2": [1, 0, 0],
                  "angular_velocity": [0.0, 0.05, 0.0], "rotation_center": [0, 0, 0],
                  "section": {"EA": 1e6, "kGA": 1e6, "GJ": 1e3, "EI2": 1e3, "EI3": 1e3,
                              "rhoA": 1.0, "rhoI2": 1e-6, "rhoI3": 1e-6}}],
        "support": [{"type": "spherical", "beam": "rod", "at": "start"}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
        "damping": [{"beam": "rod", **damping}],
        "output": {"track": [{"beam": "rod", "at": "end"}], "every": 1},  # peaks need every step
    })


def decrement_and_frequency(records, t_from: float, axis: int = 2) -> tuple[float, float]:
    """Mean logarithmic decrement between successive positive peaks of the tip's coordinate
    `axis` after t_from, and the damped angular frequency from their spacing (peaks by parabolic
    interpolation)."""
    t = np.array([r.t for r in records])
    z = np.array([r.tracked[0][axis] for r in records])
    peaks = []
    for i in range(1, len(z) - 1):
        if t[i] > t_from and z[i] > 0 and z[i] >= z[i - 1] and z[i] > z[i + 1]:
            a, b, c = z[i - 1], z[i], z[i + 1]
            d = 0.5 * (a - c) / (a - 2 * b + c)
            peaks.append((t[i] + d * (t[1] - t[0]), b - 0.25 * (a - c) * d))
    assert len(peaks) >= 3
    tp, zp = np.array(peaks).T
    return float(np.mean(np.log(zp[:-1] / zp[1:]))), float(2 * math.pi / np.mean(np.diff(tp)))


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("kind", ["kelvin_voigt", "mass_proportional"])
def test_logarithmic_decrement_matches_the_closed_form(kind):
    """Damping ratio about 0.02. Kelvin-Voigt with retardation time tau damps a mode of undamped
    frequency w with zeta = tau w / 2 (the cantilever's first mode, 3.516 rad/s; its higher
    modes are damped out first), mass-proportional damping alpha with zeta = alpha / (2 w) (the
    pendulum, one mode); then delta = 2 pi zeta / sqrt(1 - zeta^2) and the damped frequency is
    w sqrt(1 - zeta^2). w follows from the measured damped frequency; the decrement must match
    to 1 % (measured: 2e-4 and 1e-4)."""
    if kind == "kelvin_voigt":
        tau = 0.0114
        delta, wd = decrement_and_frequency(slidebeam.Simulation(cantilever(retardation_time=tau)).run_dynamic().records,
                                            t_from=1.5)
        w2 = (1 - math.sqrt(1 - tau**2 * wd**2)) * 2 / tau**2  # wd^2 = w^2 (1 - tau^2 w^2 / 4)
        zeta, w_expected = tau * math.sqrt(w2) / 2, 3.516
    else:
        alpha = 0.1534
        delta, wd = decrement_and_frequency(slidebeam.Simulation(pendulum(mass_proportional=alpha)).run_dynamic().records,
                                            t_from=0.0, axis=0)
        zeta, w_expected = alpha / (2 * math.sqrt(wd**2 + alpha**2 / 4)), 3.836  # wd^2 = w^2 - alpha^2 / 4
    expected = 2 * math.pi * zeta / math.sqrt(1 - zeta**2)
    assert 0.015 < zeta < 0.025 and abs(wd - w_expected) < 0.01 * w_expected, (zeta, wd)
    assert delta == pytest.approx(expected, rel=0.01), (delta, expected, zeta)


def test_damped_runs_agree_on_one_and_two_ranks():
    scene = with_damping(everything_scene("energy-momentum", "full"), retardation_time=0.02, mass_proportional=0.3)
    for world, alone in distributed_and_serial_records(scene):
        assert abs(world.dissipated - alone.dissipated) <= 1e-10 * max(1.0, abs(alone.dissipated))


@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_cable_damping_step_jacobian_and_balance(integrator):
    """ANCF cables: the damping's step Jacobian against finite differences; under
    energy-momentum the balance closes with damping on both cables."""
    from test_ancf import everything_scene as cable_scene

    scene = with_damping(cable_scene(integrator), retardation_time=0.02, mass_proportional=0.5)
    sim = slidebeam.Simulation(scene)
    assert [e.type for e in sim.active_effects].count("beam_damping") == len(scene.beams)
    check_step_jacobian(sim, steps=1, h=0.05, seed=3, label=integrator)
    if integrator != "energy-momentum":
        return
    data = dict(scene.data)
    data["beam"] = [{k: v for k, v in b.items() if k not in ("velocity", "angular_velocity")} for b in data["beam"]]
    run = slidebeam.scene_from_dict(data)
    run = dataclasses.replace(run, analysis=dataclasses.replace(run.analysis, t_end=0.5, dt=0.01))
    records = slidebeam.Simulation(run).run_dynamic().records
    K = max(r.kinetic_energy for r in records)
    assert records[-1].dissipated > 1e-4 * K
    assert max(r.energy_balance_error for r in records) <= 1e-9 * K
