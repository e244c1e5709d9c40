# SPDX-License-Identifier: MIT
"""Coulomb friction with true stick on a sliding joint ([[friction]]; docs/theory.md, "Friction
that sticks"): a block on a rigid rail stays put while tan(alpha) <= mu (to roundoff, also at
tan(alpha) = mu), starts to slide with the closed-form acceleration once a driven support tilts
the rail past mu, and on a quarter-circle rail swings, reverses and comes to rest where the
closed form says; a flexible pendulum on that rail runs to the end under the schemes; the energy
balance closes with the dissipation mu N |ds| under energy-momentum; step Jacobians against
finite differences under every integrator, both joint forms, stick and slip both ways; 1 rank =
2 ranks."""
from __future__ import annotations

import math

import numpy as np
import pytest

import slidebeam
from checks import distributed_and_serial_records, step_jacobian_error, trial_end_state
from test_dynamics import INTEGRATORS

BLOCK = "runs/effects/friction_block.toml"
SEED = "runs/seed/free_fall_1+4.toml"
G, ALPHA = 9.80665, math.radians(30.0)
# The block: a beam 2 cm long whose middle slides and carries 1 kg, with the rotary inertia of a
# 1 kg block of that length (m L^2 / 12 about its middle, per unit length m L / 12). With the beam's
# own (1e-5, a point mass on a stick) it turns about its slider with almost no inertia, and that
# soft mode, not friction, took Newton 5-6 iterations in one step in ten (frictionless alike).
BLOCK_SECTION = {"EA": 1e6, "kGA": 1e6, "GJ": 1e2, "EI2": 1e2, "EI3": 1e2, "rhoA": 0.1,
                 "rhoI2": 1.0 * 0.02 / 12, "rhoI3": 1.0 * 0.02 / 12}
RAIL_SECTION = {"EA": 1e7, "kGA": 1e7, "GJ": 1e4, "EI2": 1e4, "EI3": 1e4, "rhoA": 1.0, "rhoI2": 1e-3, "rhoI3": 1e-3}


def block(root, mu: float, t_end: float = 1.0, dt: float = 1e-3, integrator: str = "energy-momentum",
          start: str | None = None) -> slidebeam.Scene:
    """The shipped block on its 30 degree rail, with friction mu."""
    sets = [f"analysis.t_end={t_end}", f"analysis.dt={dt}", f'analysis.integrator="{integrator}"']
    if start:
        sets.append(f'analysis.start="{start}"')
    scene = slidebeam.load_scene(root / BLOCK, sets)
    data = dict(scene.data)
    data["friction"] = [{"beam": "block", "mu": mu}]
    return slidebeam.scene_from_dict(data, file=str(root / BLOCK), base_dir=str(root / "runs" / "effects"))


def s_history(scene: slidebeam.Scene) -> tuple[np.ndarray, np.ndarray, list]:
    records = slidebeam.Simulation(scene).run_dynamic().records
    return np.array([r.t for r in records]), np.array([r.joints[0].s for r in records]), records


def tilting_rail(alpha_deg: float, tilt_deg: float, mu: float, t_end: float) -> slidebeam.Scene:
    """A 1 kg block at s = 3 m on a rigid 4 m rail at alpha, which a fixed support with a motion
    turns about its start by tilt over 0.1 s .. 0.3 s (a smooth ramp: no jolt that would ring in
    the undamped step)."""
    a = math.radians(alpha_deg)
    t = np.array([math.cos(a), math.sin(a), 0.0])
    c = 3.0 * t
    return slidebeam.scene_from_dict({
        "scene": {"name": "tilting_rail"},
        "analysis": {"type": "dynamic", "integrator": "energy-momentum", "t_end": t_end, "dt": 1e-3},
        "beam": [{"name": "rail", "start": [0.0, 0.0, 0.0], "end": list(4 * t), "d2": [0.0, 0.0, 1.0], "spans": 4,
                  "section": RAIL_SECTION},
                 {"name": "block", "start": list(c - 0.05 * t), "end": list(c + 0.05 * t), "d2": [0.0, 0.0, 1.0],
                  "spans": 1, "section": BLOCK_SECTION}],
        "support": [{"type": "fixed", "beam": "rail",
                     "motion": {"rotation": [0.0, 0.0, math.radians(tilt_deg)],
                                "time_function": {"type": "smooth_ramp", "t0": 0.1, "t1": 0.3}}}],
        "sliding_joint": [{"slider": "block", "at": 0.05, "carrier": "rail"}],
        "point_mass": [{"beam": "block", "at": 0.05, "mass": 1.0}],
        "friction": [{"beam": "block", "mu": mu}],
        "gravity": {"g": [0.0, -G, 0.0]},
        "output": {"every": 1},
    }, file="tilting_rail.toml", base_dir=".")


def arc_rail(mu: float, t_end: float, integrator: str = "energy-momentum", dt: float = 2e-3, spans: int = 32,
             pendulum: bool = False, form: str | None = None, **analysis: float) -> slidebeam.Scene:
    """A rigid quarter-circle rail of radius 1 m in the vertical plane, from 45 degrees left of
    its lowest point to 45 degrees right of it; on it, at 40 degrees left, a 1 kg block (a short
    beam whose middle slides and carries the mass) or a flexible pendulum (0.5 m, EA = 1e5, a
    1 kg bob) whose top slides. The start is the equilibrium with the slider held, so that the
    first step starts from rest on the rail."""
    th0, a0 = math.radians(-40.0), math.radians(-45.0)
    p = np.array([math.sin(th0), -math.cos(th0), 0.0])
    tangent = np.array([math.cos(th0), math.sin(th0), 0.0])
    if pendulum:
        slider = {"name": "block", "start": list(p), "end": list(p + [0.0, -0.5, 0.0]), "d2": [0.0, 0.0, 1.0],
                  "spans": 4, "section": {**BLOCK_SECTION, "EA": 1e5, "kGA": 1e5, "GJ": 10.0, "EI2": 10.0,
                                          "EI3": 10.0, "rhoA": 0.5, "rhoI2": 1e-5, "rhoI3": 1e-5}}
        joint_at, mass_at = 0.0, 0.5
    else:
        slider = {"name": "block", "start": list(p - 0.01 * tangent), "end": list(p + 0.01 * tangent),
                  "d2": [0.0, 0.0, 1.0], "spans": 1, "section": BLOCK_SECTION}
        joint_at, mass_at = 0.01, 0.01
    joint = {"slider": "block", "at": joint_at, "carrier": "rail", "tolerance": 1e-3}
    if form:
        joint["form"] = form
    return slidebeam.scene_from_dict({
        "scene": {"name": "arc_rail"},
        "analysis": {"type": "dynamic", "integrator": integrator, "t_end": t_end, "dt": dt, "start": "equilibrium",
                     **analysis},
        "beam": [{"name": "rail", "arc": {"center": [0.0, 0.0, 0.0], "radius": 1.0, "normal": [0.0, 0.0, 1.0],
                                          "start": [math.sin(a0), -math.cos(a0), 0.0], "angle": 90.0},
                  "d2": [0.0, 0.0, 1.0], "spans": spans, "section": RAIL_SECTION},
                 slider],
        "support": [{"type": "fixed", "beam": "rail"}],
        "sliding_joint": [joint],
        "point_mass": [{"beam": "block", "at": mass_at, "mass": 1.0}],
        "friction": [{"beam": "block", "mu": mu}],
        "gravity": {"g": [0.0, -G, 0.0]},
        "output": {"every": 1},
    }, file="arc_rail.toml", base_dir=".")


def arc_turning_points(theta0: float, mu: float, g_over_r: float) -> list[float]:
    """Closed form of a point mass on a circle (angle theta from the lowest point) with Coulomb
    friction, N = m (g cos theta + R theta'^2): on each swing u = theta'^2 obeys the linear
    du/dtheta + 2 sig mu u = -2 (g/R) (sin theta + sig mu cos theta) (sig: the direction), solved
    exactly; a swing ends where u = 0, and the mass stays there once |tan theta| <= mu. Returns
    the start, the turning points and (last) the rest angle."""
    th, sig = theta0, 1.0 if theta0 < 0 else -1.0
    points = [th]
    while abs(math.tan(th)) > mu:
        k = 1.0 + 4.0 * mu * mu
        b = g_over_r * (2.0 - 4.0 * mu * mu) / k
        a = -6.0 * sig * mu * g_over_r / k
        c = -(a * math.sin(th) + b * math.cos(th)) * math.exp(2.0 * sig * mu * th)

        def u(x: float) -> float:
            return c * math.exp(-2.0 * sig * mu * x) + a * math.sin(x) + b * math.cos(x)

        lo = th + 1e-3 * sig
        while u(lo + 1e-3 * sig) > 0.0:
            lo += 1e-3 * sig
        hi = lo + 1e-3 * sig
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if u(mid) > 0.0 else (lo, mid)
        th = 0.5 * (lo + hi)
        points.append(th)
        sig = -sig
    return points


@pytest.mark.parametrize("integrator", ("energy-momentum", "midpoint"))
@pytest.mark.one_case_in_parallel
def test_a_block_held_by_friction_stays_put(root, integrator):
    """mu = 0.7 > tan 30 deg: the block does not move at all (no creep), friction takes the whole
    tangential load, and nothing is dissipated."""
    t, s, records = s_history(block(root, 0.7, t_end=0.5, integrator=integrator))
    assert np.abs(s - s[0]).max() <= 1e-12
    assert all(r.dissipated == 0.0 for r in records)
    assert all(r.newton_iterations <= 5 for r in records)


def test_a_load_exactly_at_the_limit_sticks(root):
    """tan(alpha) = mu from the equilibrium start (the load at the limit from the first step),
    for 1 s: with a tie of 1e-8 mu N the block alternated between stick and slip at t = 0.357 s
    until Newton gave up."""
    _, s, records = s_history(block(root, math.tan(ALPHA), t_end=1.0, start="equilibrium"))
    assert records[-1].t == pytest.approx(1.0)
    assert np.abs(s - s[0]).max() <= 1e-12
    assert records[-1].dissipated == 0.0


def test_a_sliding_block_accelerates_as_the_closed_form(root):
    """mu = 0.3 < tan 30 deg: s'' = -g (sin a - mu cos a) from the first step (the force is mu N
    exactly, no regularisation), measured by a parabola through s(t) (the midpoint-type step
    integrates a constant force exactly); the dissipation is mu N |s - s0| and the balance closes."""
    t, s, records = s_history(block(root, 0.3))
    exact = -G * (math.sin(ALPHA) - 0.3 * math.cos(ALPHA))
    late = t >= 0.2
    c = np.polyfit(t[late] - 0.6, s[late], 2)
    assert abs(2 * c[0] - exact) <= 1e-9 * G, 2 * c[0] - exact
    assert np.abs(np.polyval(c, t[late] - 0.6) - s[late]).max() <= 1e-10
    K = max(r.kinetic_energy for r in records)
    assert max(r.energy_balance_error for r in records) <= 1e-10 * K
    m = 1.0 + 0.1 * 0.1  # the point mass and the block beam
    D = [r.dissipated for r in records]
    assert all(b >= a for a, b in zip(D, D[1:]))
    assert D[-1] == pytest.approx(0.3 * m * G * math.cos(ALPHA) * abs(s[-1] - s[0]), rel=1e-6)


def test_tilting_the_rail_past_mu_starts_the_slide():
    """At 20 degrees with mu = 0.4 the block sticks; a driven support turns the rail by 5 degrees
    (tan 25 deg = 0.466 > mu): the block slips and, once the rail is still, slides down with
    s'' = -g (sin 25 - mu cos 25) to 1e-9 g. Energy balance with the support's work and friction's
    dissipation."""
    t, s, records = s_history(tilting_rail(20.0, 5.0, 0.4, 0.8))
    assert np.abs(s[t <= 0.1] - 3.0).max() == 0.0
    assert s[-1] < 3.0 - 0.05
    exact = -G * (math.sin(math.radians(25.0)) - 0.4 * math.cos(math.radians(25.0)))
    late = t >= 0.4
    c = np.polyfit(t[late] - 0.6, s[late], 2)
    assert abs(2 * c[0] - exact) <= 1e-9 * G, 2 * c[0] - exact
    assert records[-1].work > 0.0 and records[-1].dissipated > 0.0
    scale = max(abs(records[-1].work), max(r.kinetic_energy for r in records))
    assert max(r.energy_balance_error for r in records) <= 1e-9 * scale


@pytest.mark.skip_in_parallel  # a closed form; the pendulum on this rail runs on 2 ranks below
@pytest.mark.parametrize("floor_stop", [False, True], ids=["", "floor_stop"])
def test_a_block_on_a_circular_rail_comes_to_rest_where_the_closed_form_says(floor_stop):
    """mu = 0.1, released at -40 degrees: swings to 26.0, back to -13.6, on to 2.08 degrees and
    stays there (tan 2.08 deg < mu) from t = 3.03 s. The rest angle within 1e-5 rad of the closed form (the
    rail's 32-span spline and dt = 2 ms), each turning point passed, and the balance at the
    Newton tolerance. Newton: 3.16 iterations per step, 6 at the first reversal (where |F|
    needs two iterations at its roundoff floor to be seen stagnating); with -sb_floor_stop
    (the floor measured on earlier steps) 2.89, at most 5."""
    from test_condensation import petsc_options

    points = arc_turning_points(math.radians(-40.0), 0.1, G)
    with petsc_options(**({"sb_floor_stop": "true"} if floor_stop else {})):
        _, s, records = s_history(arc_rail(0.1, 3.3))
    theta = math.radians(-45.0) + s  # R = 1 m
    assert len(points) == 4
    assert theta.max() == pytest.approx(points[1], abs=1e-4)
    assert theta[theta.argmax():].min() == pytest.approx(points[2], abs=1e-4)
    assert theta[-1] == pytest.approx(points[3], abs=1e-5)
    assert np.abs(theta[-100:] - theta[-1]).max() == 0.0  # at rest, not creeping
    its = [r.newton_iterations for r in records[1:]]
    assert np.mean(its) <= (3.0 if floor_stop else 3.3) and max(its) <= (5 if floor_stop else 6)
    K = max(r.kinetic_energy for r in records)
    assert max(r.energy_balance_error for r in records) <= 1e-10 * K


# (undamped Newmark runs this pendulum with friction to 3 s; without friction it blows up at
# t = 2.2 s, a limit of the scheme with sliding joints)
PENDULUM_RUNS = (("energy-momentum", "frame", {}), ("energy-momentum", "spatial", {}), ("midpoint", "frame", {}),
                 ("newmark", "spatial", {}), ("newmark", "frame", {"newmark_gamma": 0.6, "newmark_beta": 0.3025}),
                 ("hht", "frame", {}))


@pytest.mark.parametrize("integrator, form, analysis", PENDULUM_RUNS,
                         ids=[f"{i}{'-damped' if a else ''}-{f}" for i, f, a in PENDULUM_RUNS])
@pytest.mark.one_case_in_parallel
def test_a_flexible_pendulum_on_the_circular_rail_runs_to_the_end(integrator, form, analysis):
    """A pendulum hanging from the slider sticks and slips as it swings (the normal force swings
    with it); the run reaches its end without a rejected step and, under energy-momentum, with the
    balance at the Newton tolerance. Under mpirun -n 2 on two ranks."""
    sim = slidebeam.Simulation(arc_rail(0.1, 1.0, integrator=integrator, pendulum=True, form=form, **analysis))
    records = sim.run_dynamic().records
    assert records[-1].t == pytest.approx(1.0)
    assert records[-1].rejected_steps == 0
    s = np.array([r.joints[0].s for r in records])
    assert np.any(np.diff(s) == 0.0) and np.any(np.diff(s) != 0.0)  # both stick and slip
    if integrator == "energy-momentum":
        scale = max(max(r.kinetic_energy for r in records), records[-1].dissipated)
        assert max(r.energy_balance_error for r in records) <= 1e-9 * scale


def seed_with_friction(root, integrator: str, form: str, mu: float = 0.4) -> slidebeam.Scene:
    """The seed's flexible carrier and director slider (a swinging beam whose tip slides): the
    normal force depends on the multipliers, the slider's directors and the carrier's tangent."""
    scene = slidebeam.load_scene(root / SEED, [f'analysis.integrator="{integrator}"', "analysis.t_end=0.1"])
    data = dict(scene.data)
    data["sliding_joint"] = [{**data["sliding_joint"][0], "form": form}]
    data["friction"] = [{"beam": "CM", "mu": mu}]
    return slidebeam.scene_from_dict(data, file=str(root / SEED), base_dir=str(root / "runs" / "seed"))


def set_branch(sim, x1, i_s: int, i_f: int, h: float, branch: str) -> None:
    """Put the trial state x1 (not assembled) well inside a branch of the friction law: stick at
    rest with F = 0 (|z| = 0 < mu N), slip with a force far beyond mu N and a consistent rate
    (|z| > mu N whatever r); then check the branch by F's residual (stick: r sdot = 0). s_n is
    read from the prepared step's start (sim.joint_states() would set the model's step start
    back to the last step's)."""
    from mpi4py import MPI

    sdot, force = {"stick": (0.0, 0.0), "slip+": (-0.5, 1e4), "slip-": (0.5, -1e4)}[branch]
    lo, hi = x1.getOwnershipRange()
    x_n = sim.integrator.x
    s0 = MPI.COMM_WORLD.allreduce(x_n.getValue(i_s) if lo <= i_s < hi else 0.0)
    for i, v in ((i_s, s0 + h * sdot), (i_f, force)):
        if lo <= i < hi:
            x1.setValue(i, v)
    x1.assemble()
    R = x1.duplicate()
    sim.integrator.step_residual(x1, R)
    r_f = R.getValue(i_f) if lo <= i_f < hi else None
    if r_f is not None:
        assert (r_f == 0.0) == (branch == "stick"), (branch, r_f)
        if branch != "stick":
            assert abs(r_f - force) < 0.5 * abs(force)  # F - (+-mu N), mu N well below |F|


@pytest.mark.parametrize("branch", ("stick", "slip+", "slip-"))
@pytest.mark.parametrize("form", ("frame", "spatial"))
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_friction_step_jacobian(root, integrator, form, branch):
    """The step Jacobian of each branch of the law: stick (s row r / h), slip either way (F's row
    over the unknowns N depends on: the multipliers, the slider's directors, the carrier around s).
    The trial state is put well inside its branch so that the differences do not cross a kink."""
    sim = slidebeam.Simulation(seed_with_friction(root, integrator, form))
    friction = [i for i, e in enumerate(sim.active_effects) if e.type == "friction"]
    assert friction
    x1 = trial_end_state(sim, steps=3, h=0.01, seed=5)
    lo, hi = x1.getOwnershipRange()
    i_s = sim.sliding_coordinate_index()
    i_f = sim._model.extra_offset(friction[0])
    set_branch(sim, x1, i_s, i_f, 0.01, branch)
    worst, scale = step_jacobian_error(sim, x1)
    assert worst <= 1e-6 * scale, f"{integrator}: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"
    # the rows and columns of s and F on their own scale (eps = 1e-5 keeps the roundoff of the
    # position rows' residuals, ~1e3, in the s column at 1e-8)
    worst, scale = step_jacobian_error(sim, x1, 1e-5, [i_s, i_f])
    assert scale > 0.1
    assert worst <= 1e-6 * scale, f"{integrator}, s and F: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"


def seed_cables_with_friction(integrator: str, cables: tuple[str, ...], mu: float = 0.3) -> slidebeam.Scene:
    """The inclined seed scene (S2-incl, 1+4) with the carrier AB, the slider CM or both as ANCF
    cables (test_ancf_sliding.py), and friction on the slider: N from a cable's r' tangent, a
    cable slider's spatial joint."""
    import tomllib

    from test_ancf_sliding import SEED as SEED_DIR, as_cables

    with open(SEED_DIR / "free_fall_inclined_1+4.toml", "rb") as f:
        data = as_cables(tomllib.load(f), cables)
    data["analysis"].update({"integrator": integrator, "dt": 0.01, "t_end": 0.3})
    data["friction"] = [{"beam": "CM", "mu": mu}]
    return slidebeam.scene_from_dict(data, file=f"S2-incl (cables {', '.join(cables)})", base_dir=str(SEED_DIR))


@pytest.mark.parametrize("branch", ("stick", "slip-"))
@pytest.mark.parametrize("integrator", ("energy-momentum", "hht"))
@pytest.mark.parametrize("cables", ("AB", "CM", "AB+CM"))
def test_friction_step_jacobian_on_cables(cables, integrator, branch):
    """Friction with ANCF carriers and sliders: the step Jacobian of each branch."""
    sim = slidebeam.Simulation(seed_cables_with_friction(integrator, tuple(cables.split("+"))))
    friction = [i for i, e in enumerate(sim.active_effects) if e.type == "friction"]
    x1 = trial_end_state(sim, steps=2, h=0.01, seed=3)
    lo, hi = x1.getOwnershipRange()
    i_s, i_f = sim.sliding_coordinate_index(), sim._model.extra_offset(friction[0])
    set_branch(sim, x1, i_s, i_f, 0.01, branch)
    worst, scale = step_jacobian_error(sim, x1)
    assert worst <= 1e-6 * scale, f"{cables} {integrator}: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"
    worst, scale = step_jacobian_error(sim, x1, 1e-5, [i_s, i_f])
    assert worst <= 1e-6 * scale, f"{cables} {integrator}, s and F: |J - FD| = {worst:.3e}, |J| = {scale:.3e}"


@pytest.mark.parametrize("cables", ("AB", "CM", "AB+CM"))
def test_friction_on_cables_dissipates_and_the_balance_closes(cables):
    """Energy-momentum with friction on cable carriers and sliders: friction takes energy (it
    slides), never gives it back, and H - H0 - W + D stays at the Newton tolerance."""
    records = slidebeam.Simulation(seed_cables_with_friction("energy-momentum", tuple(cables.split("+")))).run_dynamic().records
    D = [r.dissipated for r in records]
    K = max(r.kinetic_energy for r in records)
    assert D[-1] > 1e-3 * K and all(b >= a for a, b in zip(D, D[1:]))
    assert max(r.energy_balance_error for r in records) <= 1e-9 * max(K, D[-1])


def test_friction_block_serial_equals_parallel(root):
    """Meaningful under mpirun -n 2: the joint and its friction on one rank, the rail on both."""
    pairs = distributed_and_serial_records(block(root, 0.3, t_end=0.05))
    for a, b in pairs:
        assert abs(a.dissipated - b.dissipated) <= 1e-10 * max(1.0, abs(b.dissipated))
        assert abs(a.joints[0].s - b.joints[0].s) <= 1e-10


@pytest.mark.parametrize("friction, words", [
    ({"beam": "block", "mu": -0.1}, "mu"),
    ({"beam": "block", "mu": 0.3, "regularization": 1e-3}, "regularization"),
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
    the [[sliding_joint]] they act on find it, and the run is the same. With the drive, friction
    adds to the drive's force (mu N against the prescribed rate) and dissipates mu N |ds|."""
    scene = block(root, mu=0.3, t_end=0.05)
    first = {"friction": scene.data["friction"],
             "slider_drive": [{"beam": "block", "speed": 0.1, "start": 0.01, "stop": 0.04, "ramp": 0.01}],
             **{k: v for k, v in scene.data.items() if k != "friction"}}
    last = {**{k: v for k, v in first.items() if k not in ("friction", "slider_drive")},
            "friction": first["friction"], "slider_drive": first["slider_drive"]}
    assert list(first)[0] == "friction" and list(last)[-1] == "slider_drive"
    runs = []
    for data in (first, last):
        sc = slidebeam.scene_from_dict(data, file=str(root / BLOCK), base_dir=str(root / "runs" / "effects"))
        t, s, records = s_history(sc)
        runs.append(s)
    assert np.array_equal(runs[0], runs[1]) and runs[0][-1] != runs[0][0]
    m = 1.0 + 0.1 * 0.1
    assert records[-1].dissipated == pytest.approx(0.3 * m * G * math.cos(ALPHA) * abs(s[-1] - s[0]), rel=1e-6)
