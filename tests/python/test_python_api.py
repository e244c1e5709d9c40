# SPDX-License-Identifier: MIT
"""Python scripting: PETSc objects shared with the core, residual/Jacobian access, the example."""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from petsc4py import PETSc

import slidebeam


def small_scene():
    return slidebeam.scene_from_dict({
        "analysis": {"steps": 2},
        "beam": [{"name": "b", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 4,
                  "section": {"EA": 1e4, "kGA": 1e4, "GJ": 10.0, "EI2": 10.0, "EI3": 10.0}}],
        "support": [{"type": "clamp", "beam": "b", "at": "start"}],
        "load": [{"type": "force", "beam": "b", "at": "end", "value": [0, 2.0, 1.0]}],
    })


def test_petsc_objects_are_shared_not_copied():
    sim = slidebeam.Simulation(small_scene())
    x1, x2 = sim.x, sim.x
    assert isinstance(x1, PETSc.Vec) and x1.handle == x2.handle
    assert sim.snes.getFunction()[0].handle == sim.residual_vector.handle
    assert sim.snes.getJacobian()[0].handle == sim.jacobian.handle
    # Writing through petsc4py changes what the core assembles.
    r0 = sim.residual(t=1.0).norm()  # full load on the unloaded reference state
    assert r0 > 0
    ones = sim.x.duplicate()
    ones.set(1.0)
    sim.x.axpy(1e-3, ones)  # perturb every unknown from Python
    assert sim.residual(t=1.0).norm() != pytest.approx(r0)
    # The Python reference keeps the vector alive after the simulation is gone.
    x = sim.x
    del sim
    assert np.isfinite(x.norm())


def test_a_control_point_out_of_range_is_refused():
    """control_point_unknowns of a point the model does not have raises IndexError (it read past
    the numbering and returned whatever was there)."""
    sim = slidebeam.Simulation(small_scene())
    n = sim.first_control_point("b") + 6  # 4 spans: 6 control points
    assert sim.control_point_unknowns(n - 1)[1] == 12
    for cp in (n, n + 40, -1):
        with pytest.raises(IndexError, match="out of range"):
            sim.control_point_unknowns(cp)


def test_scripted_steps_equal_load_stepping():
    a = slidebeam.Simulation(small_scene())
    rec = a.solve_static()
    b = slidebeam.Simulation(small_scene())
    b.use_predictor = False
    for t in (0.5, 1.0):
        assert b.solve_step(t).converged
    assert np.abs(a.control_points(0) - b.control_points(0)).max() < 1e-9
    assert rec[-1].strain_energy > 0


def test_load_stepper_lands_on_the_clock_and_refuses_no_steps():
    """The core's LoadStepper: 10 steps to t_end = 0.7 at t = n (t_end / 10) exactly (the clock's
    t_0 + n h, which a running sum of h misses here), the last on t_end; no cuts, no
    continuation on a clamped beam."""
    sim = slidebeam.Simulation(small_scene())
    stepper = slidebeam._core.LoadStepper(sim._model, sim._solver, 0.7, 10, 8)
    times = []
    while not stepper.done:
        adv = stepper.advance()
        assert adv.status == "accepted" and adv.result.converged and not adv.continued
        times.append(adv.t)
    h = 0.7 / 10
    assert times == [n * h for n in range(1, 10)] + [0.7] and stepper.time == 0.7
    assert list(np.cumsum([h] * 9)) != times[:9]  # the check can tell a sum from the clock
    assert stepper.cuts == 0 and stepper.continuations == 0
    with pytest.raises(ValueError, match="steps >= 1"):
        slidebeam._core.LoadStepper(sim._model, sim._solver, 1.0, 0, 8)


def test_jacobian_matches_finite_differences_through_petsc4py():
    sim = slidebeam.Simulation(small_scene())
    sim.solve_static()
    x = sim.x.copy()
    v = x.duplicate()
    lo, hi = v.getOwnershipRange()
    values = np.sin(np.arange(lo, hi) * 1.3)
    v.setArray(values)
    J = sim.assemble_jacobian(1.0, x)
    Jv = x.duplicate()
    J.mult(v, Jv)
    h = 1e-6
    xp, xm = x.copy(), x.copy()
    xp.axpy(h, v)
    xm.axpy(-h, v)
    Fp = sim.residual(1.0, xp).copy()
    Fm = sim.residual(1.0, xm).copy()
    fd = (Fp - Fm) / (2 * h)
    assert (fd - Jv).norm() < 1e-6 * Jv.norm()


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("np_", [1, pytest.param(2, marks=pytest.mark.spawns_ranks)])
def test_scripting_example_runs(root, np_, tmp_path):
    cmd = [sys.executable, str(root / "runs" / "scripting_example.py"), str(tmp_path / "out"),
           "-sb_static_snes_max_it", "30"]
    if np_ > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(np_), *cmd]
    env = {"PYTHONPATH": str(root / "python"), "PATH": "/usr/bin:/bin", "OMPI_ALLOW_RUN_AS_ROOT": "1",
           "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "HOME": "/tmp"}
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "load step 4" in out.stdout and "strain energy" in out.stdout
    assert "complete = True" in out.stdout and "never used" not in out.stderr
    assert {"history.csv", "final_configuration.csv", "summary.json"} <= {p.name for p in (tmp_path / "out").iterdir()}


def test_scene_options_do_not_leak_into_the_next_scene(root):
    """A scene's [petsc] table fills the options database for its Simulation; the next
    Simulation of a script must not inherit it (options set by the user stay)."""
    opts = PETSc.Options()
    assert not opts.hasName("sb_jacobian_reuse")
    opts.setValue("sb_user_marker", "1")
    try:
        slidebeam.Simulation(slidebeam.load_scene(root / "runs" / "pendulum16.toml"))  # [petsc] sb_jacobian_reuse
        assert opts.getBool("sb_jacobian_reuse")
        slidebeam.Simulation(slidebeam.load_scene(root / "runs" / "flying_spaghetti_2d.toml"))
        assert not opts.hasName("sb_jacobian_reuse")
        assert opts.hasName("sb_user_marker")
    finally:
        opts.delValue("sb_user_marker")
