# SPDX-License-Identifier: MIT
"""ANCF cable beams in scenes (issue 9): scene validation, step Jacobians of every integrator
against finite differences, a large-deflection static benchmark against the elastica, energy
and momentum conservation under energy-momentum, and distributed == serial."""
from __future__ import annotations

import math

import numpy as np
import pytest

import slidebeam
from checks import check_step_jacobian, distributed_and_serial_records, with_em_dissipation

INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
NEWTON_ATOL = 1e-10  # the SNES absolute tolerance (solvers/newton.cpp)

CABLE_SECTION = {"EA": 1e3, "EI": 2.0, "rhoA": 1.0}
DIRECTOR_SECTION = {"EA": 8e2, "kGA": 4e2, "GJ": 1.0, "EI2": 2.0, "EI3": 2.5, "rhoA": 0.5, "rhoI2": 0.01, "rhoI3": 0.02}


def cable(name: str = "c", start=(0, 0, 0), end=(1.5, 0.4, 0.3), spans: int = 4, **extra) -> dict:
    return {"name": name, "formulation": "ancf", "start": list(start), "end": list(end), "spans": spans,
            "section": dict(CABLE_SECTION), **extra}


def scene(**parts) -> slidebeam.Scene:
    data = {"analysis": {"type": "static"}, "beam": [cable()]}
    data.update(parts)
    return slidebeam.scene_from_dict(data)


# -- scene ---------------------------------------------------------------------------------

@pytest.mark.parametrize("change, key, words", [
    ({"d2": [0, 0, 1]}, "d2", "not used by formulation = 'ancf'"),
    ({"quadrature": "reduced"}, "quadrature", "not used by formulation = 'ancf'"),
    ({"strain": "seed"}, "strain", "not used by formulation = 'ancf'"),
    ({"section": {"EA": 1.0, "EI": 1.0, "GJ": 1.0}}, "GJ", "no shear, torsion or rotary inertia"),
    ({"section": {"EA": 1.0, "EI2": 1.0}}, "EI2", "no shear, torsion or rotary inertia"),
    ({"section": {"shape": "rectangle", "b": 0.1, "h": 0.2, "E": 1e9}}, "h", "a rectangle needs b == h"),
    ({"section": {"shape": "circle", "r": 0.1, "E": 1e9, "nu": 0.3}}, "nu", "no shear, torsion"),
    ({"formulation": "absolute"}, "formulation", "must be one of"),
])
def test_scene_refuses_what_a_cable_does_not_have(change, key, words):
    with pytest.raises(slidebeam.SceneError) as err:
        scene(beam=[{**cable(), **change}])
    assert words in str(err.value) and key in str(err.value), str(err.value)


def test_scene_refuses_curved_cables_moments_and_joints():
    arc = {k: v for k, v in cable().items() if k not in ("start", "end")}
    arc["arc"] = {"center": [0, 0, 0], "radius": 1.0, "normal": [0, 0, 1], "start": [1, 0, 0], "angle": 90}
    with pytest.raises(slidebeam.SceneError, match="needs a straight stress-free state"):
        scene(beam=[arc])
    with pytest.raises(slidebeam.SceneError, match="is an ANCF cable.*only forces act on it"):
        scene(load=[{"type": "moment", "beam": "c", "at": "end", "value": [0, 0, 1]}])
    director = {"name": "d", "start": [1.5, 0.4, 0.3], "end": [2, 0, 0], "spans": 2, "section": DIRECTOR_SECTION}
    with pytest.raises(slidebeam.SceneError, match="is an ANCF cable.*welds director triads"):
        scene(beam=[cable(), director], rigid_joint=[{"beams": ["c", "d"], "at": ["end", "start"]}])
    with pytest.raises(slidebeam.SceneError, match="is for formulation = 'ancf'"):
        scene(beam=[{**director, "section": {**DIRECTOR_SECTION, "EI": 1.0}}])


def test_shape_section_and_model_layout():
    s = scene(beam=[cable(section={"shape": "circle", "r": 0.01, "E": 2e11, "rho": 7850.0})])
    sec = s.beams[0].section
    assert sec.EA == pytest.approx(2e11 * math.pi * 1e-4)
    assert sec.EI2 == sec.EI3 == pytest.approx(2e11 * math.pi * 1e-8 / 4)
    sim = slidebeam.Simulation(s)
    assert [e.type for e in sim.active_effects] == ["ancf_elastic"]
    q = sim.control_points("c")
    assert q.shape == (5, 6)  # 4 elements: 5 nodes of r, r'
    t = np.array([1.5, 0.4, 0.3]) / np.linalg.norm([1.5, 0.4, 0.3])
    assert np.allclose(q[:, 3:], t) and np.allclose(q[-1, :3], [1.5, 0.4, 0.3])
    assert sim.x.getSize() == 30


# -- step Jacobians ------------------------------------------------------------------------

def everything_scene(integrator: str) -> slidebeam.Scene:
    """An ANCF cable with every effect it supports (clamp, interior spherical support, hat force,
    gravity, point mass, initial spin) next to a director beam, so that the numbering mixes
    both block sizes."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": 0.05, "t_end": 0.2},
        "petsc": {"sb_project_velocity": "false"},  # the spins violate the supports: kept as given
        "beam": [{"name": "d", "start": [0, 1, 0], "end": [1, 1.2, 0.1], "spans": 2, "velocity": [0.1, 0, 0.2],
                  "angular_velocity": [0.3, -0.5, 1.0], "section": DIRECTOR_SECTION},
                 cable(spans=4, velocity=[0.1, 0.3, -0.2], angular_velocity=[0.5, -1.0, 2.0]),
                 cable("free", start=(0, -1, 0), end=(1, -1.2, 0.2), spans=3, angular_velocity=[1.0, 0.5, 0.0])],
        "support": [{"type": "clamp", "beam": "c", "at": "start"},
                    {"type": "spherical", "beam": "c", "at": 0.9},
                    {"type": "spherical", "beam": "d", "at": "start"}],
        "load": [{"type": "force", "beam": "c", "at": "end", "value": [0.0, 1.0, 2.0],
                  "time_function": {"type": "hat", "t0": 0.0, "t1": 0.1, "t2": 0.3}},
                 {"type": "force", "beam": "free", "at": 0.4, "value": [0.5, 0.0, -1.0]}],
        "point_mass": [{"beam": "c", "at": 1.1, "mass": 0.7}, {"beam": "free", "at": "end", "mass": 0.2}],
        "gravity": {"g": [0.0, 0.0, -9.81]},
    })


@pytest.mark.parametrize("integrator", INTEGRATORS + ("energy-momentum, xi = 0.3",))
def test_step_jacobian_matches_finite_differences(integrator):
    sim = slidebeam.Simulation(with_em_dissipation(everything_scene(integrator.split(",")[0]), integrator))
    check_step_jacobian(sim, steps=2, h=0.05, seed=11, label=integrator)


# -- statics: large-deflection cantilever ---------------------------------------------------

def elastica_tip(k: float, n: int = 4000) -> tuple[float, float]:
    """Tip of an inextensible cantilever of length 1 under a transverse tip force with
    P L^2 / EI = k (fixed direction): theta'' = -k cos(theta), theta(0) = 0, theta'(1) = 0,
    solved by shooting on theta'(0) with classical RK4 (error ~ 1e-13 at n = 4000).
    Returns (x, y) of the tip, the load pointing along -y. Mattiasson (1981) tabulates
    1 - x = 0.05643, y = 0.30172 for k = 1."""
    def shoot(kappa0: float) -> tuple[float, float, float]:
        h = 1.0 / n
        y = np.array([0.0, kappa0, 0.0, 0.0])  # theta, theta', x, y

        def f(v):
            return np.array([v[1], -k * math.cos(v[0]), math.cos(v[0]), math.sin(v[0])])
        for _ in range(n):
            k1 = f(y)
            k2 = f(y + 0.5 * h * k1)
            k3 = f(y + 0.5 * h * k2)
            k4 = f(y + h * k3)
            y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        return y[1], y[2], y[3]
    a, b = 0.0, k  # theta'(1) > 0 at kappa0 = k (> bending moment at the root), < 0 at 0
    for _ in range(60):
        m = 0.5 * (a + b)
        if shoot(m)[0] > 0:
            b = m
        else:
            a = m
    _, x, y = shoot(0.5 * (a + b))
    return x, -y


@pytest.mark.parametrize("k", [1.0, 5.0])
@pytest.mark.one_case_in_parallel
def test_cantilever_tip_force_matches_the_elastica(k):
    """Clamped cable of length 1, EI = 1, EA = 1e7 (nearly inextensible: axial strain <= k 1e-7),
    tip force P = k EI/L^2 across. 64 elements: tip within 5e-7 L of the inextensible elastica.
    The cable locks in membrane mode at this slenderness (EA L^2/EI = 1e7): tip errors at
    k = 1 with 4/8/16/32/64 elements are 4.1e-3, 8.0e-4, 6.4e-5, 1.4e-6, 8.2e-9 (k = 5: 2.4e-2,
    2.3e-3, 4.3e-4, 2.8e-5, 1.4e-7); with EA = 1e5 the error stops at the extensibility of the
    cable, 2.8e-6 (k = 1), from 16 elements on."""
    s = slidebeam.scene_from_dict({
        "analysis": {"type": "static", "steps": 10},
        "beam": [{"name": "c", "formulation": "ancf", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 64,
                  "section": {"EA": 1e7, "EI": 1.0}}],
        "support": [{"type": "clamp", "beam": "c", "at": "start"}],
        "load": [{"type": "force", "beam": "c", "at": "end", "value": [0.0, -k, 0.0]}],
        "output": {"track": [{"beam": "c", "at": "end"}]},
    })
    sim = slidebeam.Simulation(s)
    records = sim.solve_static()
    assert records[-1].converged and records[-1].t == 1.0
    tip = np.array(records[-1].tracked[0])
    x, y = elastica_tip(k)
    if k == 1.0:
        assert (1 - x, -y) == pytest.approx((0.05643, 0.30172), abs=2e-5)  # the published table
    err = float(np.linalg.norm(tip - [x, y, 0.0]))
    assert err < 5e-7, f"k = {k}: tip {tip}, elastica ({x:.6f}, {y:.6f}), error {err:.2e}"


# -- dynamics: conservation ----------------------------------------------------------------

def free_cable(integrator: str = "energy-momentum", t_end: float = 1.0, **analysis) -> slidebeam.Scene:
    """A free 3D cable: spinning and drifting, kicked by a hat force at its end (t < 0.2) so
    that it bends and stretches, then free."""
    return slidebeam.scene_from_dict({
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": 0.01, "t_end": t_end, **analysis},
        "beam": [cable(start=(0, 0, 0), end=(2, 0.5, 0.2), spans=6, velocity=[0.5, -0.2, 0.1],
                       angular_velocity=[0.4, 0.2, 1.5], section={"EA": 2e3, "EI": 5.0, "rhoA": 1.0})],
        "load": [{"type": "force", "beam": "c", "at": "end", "value": [0.0, 20.0, -30.0],
                  "time_function": {"type": "hat", "t0": 0.0, "t1": 0.1, "t2": 0.2}}],
        "output": {"track": [{"beam": "c", "at": "end"}, {"beam": "c", "at": 0.7}]},
    })


def test_energy_momentum_keeps_energy_and_momenta_of_a_free_cable():
    run = slidebeam.Simulation(free_cable()).run_dynamic()
    assert run.complete, run.message
    free = [r for r in run.records if r.t > 0.2 + 1e-9]
    H = np.array([r.total_energy for r in free])
    assert len(free) > 50 and free[0].strain_energy > 0.1 * H[0]  # it does bend and stretch
    drift = np.abs(H - H[0]).max() / H[0]
    assert drift <= 10 * NEWTON_ATOL, f"relative energy drift {drift:.3e}"
    L = np.array([r.linear_momentum for r in free])
    J = np.array([r.angular_momentum for r in free])
    assert np.abs(L - L[0]).max() <= 1e-10 * np.abs(L[0]).max()
    assert np.abs(J - J[0]).max() <= 1e-10 * np.abs(J[0]).max()
    # the kick changed them: the test is not vacuous
    assert np.abs(L[0] - np.array(run.records[0].linear_momentum)).max() > 0.5


def test_midpoint_rule_does_not_keep_the_cable_energy():
    run = slidebeam.Simulation(free_cable("midpoint")).run_dynamic()
    assert run.complete, run.message
    H = np.array([r.total_energy for r in run.records if r.t > 0.2 + 1e-9])
    assert np.abs(H - H[0]).max() / H[0] > 1e-3  # measured 6.3e-3 (energy-momentum: 1.4e-13)


def test_distributed_equals_serial():
    """Meaningful under mpirun -n 2: the cable is split over ranks."""
    for a, b in distributed_and_serial_records(free_cable(t_end=0.3)):
        assert np.abs(np.array(a.angular_momentum) - np.array(b.angular_momentum)).max() < 1e-9


def test_output_samples_the_centre_line(tmp_path):
    sim = slidebeam.Simulation(free_cable(t_end=0.02))
    s, q = sim.centreline("c", samples_per_span=4)
    assert q.shape == (len(s), 6)
    assert np.allclose(q[-1, :3], [2, 0.5, 0.2])
    samples = sim._model.sample_beam(0, sim.x, None, 4)
    assert samples["position"].shape == (25, 3)
    assert np.allclose(samples["position"], q[:, :3])
    assert np.allclose(np.linalg.norm(samples["d1"], axis=1), 1.0) and not samples["d2"].any()
    assert np.abs(samples["strain"]).max() < 1e-14  # the reference state is stress free


def test_pendulum_as_cable_follows_the_director_pendulum():
    """runs/pendulum16_ancf.toml is the rod of runs/pendulum16.toml as an ANCF cable: for this
    slender rod (r/L = 0.01) shear and rotary inertia change the motion by O((r/L)^2), so after
    0.2 s of swinging (0.29 m of tip travel) the two tips agree to 1e-4 m (measured 2.5e-5)."""
    from pathlib import Path

    runs = Path(__file__).resolve().parents[2] / "runs"
    tips = []
    for name in ("pendulum16", "pendulum16_ancf"):
        sim = slidebeam.Simulation(slidebeam.load_scene(runs / f"{name}.toml", ["analysis.t_end=0.2"]))
        for _ in range(200):
            assert sim.integrator.step(1e-3).converged
        tips.append(np.asarray(sim.evaluate("rod", 1.0))[0, :3])
    assert tips[0][2] < -0.15  # it did swing down
    assert np.linalg.norm(tips[0] - tips[1]) < 1e-4
