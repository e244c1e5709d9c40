# SPDX-License-Identifier: MIT
"""Static benchmarks (the roll-up into a circle and the 45-degree bend; docs/verification.md) against
closed-form and published values, and unloaded
arcs of any angle that stay stress-free (issue 22)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from mpi4py import MPI

import slidebeam
from checks import static_scene_text
from test_condensation import petsc_options

L, EI = 10.0, 100.0


def rollup_tip(root, spans: int, lam: float, strain: str = "simo-reissner", quadrature: str = "full",
               comm=None) -> np.ndarray:
    scene = slidebeam.load_scene(root / "runs" / "rollup.toml", [
        f"beam.0.spans={spans}", f"beam.0.strain={strain}", f"beam.0.quadrature={quadrature}",
        f"load.0.value=[0,0,{lam * 2 * math.pi * EI / L!r}]", "analysis.steps=10"])
    sim = slidebeam.Simulation(scene, comm)
    records = sim.solve_static()
    assert records[-1].converged and records[-1].t == 1.0
    return np.array(records[-1].tracked[0])


def circle_tip(lam: float) -> np.ndarray:
    th = 2 * math.pi * lam
    R = L / th
    return np.array([R * math.sin(th), R * (1 - math.cos(th)), 0.0])


def test_rollup_reproduces_reference_errors_and_second_order(root):
    """|tip - circle| at lambda = 0.25 from an independent implementation (docs/verification.md, "Benchmarks"),
    8/16/32/64 spans: 1.2e-1, 5.9e-2, 1.6e-2, 4.2e-3 (to two digits)."""
    reference = {8: 1.2e-1, 16: 5.9e-2, 32: 1.6e-2, 64: 4.2e-3}
    errors = {n: float(np.linalg.norm(rollup_tip(root, n, 0.25) - circle_tip(0.25))) for n in reference}
    for n, ref in reference.items():
        assert float(f"{errors[n]:.1e}") == ref, f"{n} spans: error {errors[n]:.3e}, reference {ref:.1e}"
    order = math.log2(errors[32] / errors[64])
    assert order > 1.8, f"observed order {order:.2f}"


def test_rollup_seed_measure_converges_to_its_own_continuum_tip(root):
    """With the seed's strains the continuum tip is (6.36148, 6.36642), not the circle
    (docs/theory.md, "Strain measures")."""
    seed_tip = np.array([6.36148, 6.36642, 0.0])
    tips = {n: rollup_tip(root, n, 0.25, strain="seed") for n in (16, 32, 64)}
    err = {n: float(np.linalg.norm(t - seed_tip)) for n, t in tips.items()}
    assert math.log2(err[16] / err[32]) > 1.5 and math.log2(err[32] / err[64]) > 1.5, err
    richardson = tips[64] + (tips[64] - tips[32]) / 3.0
    assert np.linalg.norm(richardson - seed_tip) < 1.5e-3
    assert np.linalg.norm(richardson - circle_tip(0.25)) > 3e-3  # and it is not the circle


@pytest.mark.parametrize("quadrature", ["full", "reduced"])
def test_bend45_converges_to_published_tip(root, quadrature):
    """B3 at P = 600: Simo & Vu-Quoc (1986) report (47.23, 15.79, 53.37) with 8 elements; the
    converged value depends on the element by a few tenths (Exudyn: (46.90, 15.56, 53.60))."""
    published = np.array([47.23, 15.79, 53.37])
    tips = {}
    for n in (8, 16, 32):
        scene = slidebeam.load_scene(root / "runs" / "bend45.toml", [f"beam.0.spans={n}", f"beam.0.quadrature={quadrature}"])
        records = slidebeam.Simulation(scene).solve_static()
        assert records[-1].converged
        tips[n] = np.array(records[-1].tracked[0])
    assert np.linalg.norm(tips[32] - published) < 0.35  # 0.6% of the tip displacement
    # converging: full quadrature fast, reduced at about first order (differences halve)
    assert np.linalg.norm(tips[32] - tips[16]) < 0.6 * np.linalg.norm(tips[16] - tips[8])


def test_distributed_equals_serial(root):
    """The same solve distributed over all ranks (COMM_WORLD, -sb_statics_on_rank_0 false) and on
    each rank alone (COMM_SELF) agree to 1e-10. Meaningful under mpirun -n 2, where the beams are
    split over ranks."""
    for scene_file, sets in (("rollup.toml", ["beam.0.spans=12", "analysis.steps=4"]),
                             ("bend45.toml", ["beam.0.spans=9", "analysis.steps=6"])):
        scene = slidebeam.load_scene(root / "runs" / scene_file, sets)
        with petsc_options(sb_statics_on_rank_0="false"):
            world = slidebeam.Simulation(scene, MPI.COMM_WORLD)
            rec_w = world.solve_static()
        q_w = world.control_points(0)
        alone = slidebeam.Simulation(scene, MPI.COMM_SELF)
        rec_s = alone.solve_static()
        q_s = alone.control_points(0)
        assert len(rec_w) == len(rec_s)
        assert np.abs(q_w - q_s).max() < 1e-10
        for a, b in zip(rec_w, rec_s):
            assert np.abs(np.array(a.tracked) - np.array(b.tracked)).max() < 1e-10
            assert abs(a.strain_energy - b.strain_energy) <= 1e-10 * max(1.0, abs(b.strain_energy))



@pytest.mark.skipif(MPI.COMM_WORLD.Get_size() < 2, reason="under mpirun")
def test_a_distributed_simulation_solves_statics_on_rank_0(root, tmp_path):
    """Simulation(scene, COMM_WORLD).solve_static() under mpirun (-sb_statics_on_rank_0, the
    default): rank 0 solves it alone with the serial solver, and every rank gets the serial
    solve's records and state bit for bit; on_step sees the same records on every rank. A
    trolley hung on a rope, a hard first load step (distributed, MUMPS took it elsewhere)."""
    (tmp_path / "zip_line.toml").write_text(static_scene_text(root / "runs" / "cables" / "zip_line.toml", steps=3))
    scene = slidebeam.load_scene(tmp_path / "zip_line.toml", ["beam.0.spans=24", 'sliding_joint.0.static="free"'])
    world = slidebeam.Simulation(scene, MPI.COMM_WORLD)
    assert world.x.getOwnershipRange()[1] > world.x.getOwnershipRange()[0]  # every rank owns a part
    seen: list[slidebeam.StepRecord] = []
    rec_w = world.solve_static(seen.append)
    alone = slidebeam.Simulation(scene, MPI.COMM_SELF)
    rec_s = alone.solve_static()
    assert rec_w == rec_s and seen == rec_s[1:]
    assert (world.t, world.load_step_cuts, world.stopped) == (alone.t, alone.load_step_cuts, alone.stopped)
    assert np.array_equal(world.control_points(0), alone.control_points(0))
    assert world.joint_states() == alone.joint_states()
    # rank 0's copy is built with the options the simulation was built with, not those of the
    # moment: plain Newton takes more iterations on the roll-up than Newton on the manifold
    rollup = slidebeam.load_scene(root / "runs" / "rollup.toml", ["beam.0.spans=16", "analysis.steps=4"])
    with petsc_options(sb_condense_directors="false"):
        plain_world = slidebeam.Simulation(rollup, MPI.COMM_WORLD)
        plain_alone = slidebeam.Simulation(rollup, MPI.COMM_SELF)
    plain = plain_world.solve_static()
    assert plain == plain_alone.solve_static()
    manifold = slidebeam.Simulation(rollup, MPI.COMM_SELF).solve_static()
    assert sum(r.newton_iterations for r in plain) > sum(r.newton_iterations for r in manifold)


ARC_NORMAL = np.array([1.0, 2.0, 2.0]) / 3.0  # an arc in a tilted plane, about an off-origin centre
ARC_CENTER = np.array([0.5, -1.0, 2.0])
ARC_START = ARC_CENTER + 1.5 * np.array([2.0, -1.0, 0.0]) / math.sqrt(5.0)  # radius 1.5


def arc_scene(angle: float, spans: int, analysis: dict) -> slidebeam.Scene:
    """An unloaded arc clamped at its start, nothing else: it must not move."""
    return slidebeam.scene_from_dict({
        "analysis": analysis,
        "beam": [{"name": "arc", "spans": spans,
                  "arc": {"center": ARC_CENTER.tolist(), "radius": 1.5, "normal": ARC_NORMAL.tolist(),
                          "start": ARC_START.tolist(), "angle": angle},
                  "section": {"EA": 1e4, "kGA": 5e3, "GJ": 8.0, "EI2": 10.0, "EI3": 12.0,
                              "rhoA": 1.0, "rhoI2": 0.01, "rhoI3": 0.012}}],
        "support": [{"type": "clamp", "beam": "arc", "at": "start"}],
        "output": {"track": [{"beam": "arc", "at": "end"}]},
    })


# Issue 22: at +-180 degrees the last director was the minimal rotation between antiparallel
# tangents (ill-conditioned: not orthonormal by 4e-3); 33 spans put a Greville point exactly at
# the half turn of a full circle (the frame construction refused it)
ARC_CASES = [(a, n) for a in (180.0, -180.0, 179.0, 270.0, -270.0, 360.0, -360.0) for n in (32, 33)]


@pytest.mark.parametrize("angle, spans", ARC_CASES)
def test_arc_reference_frames_are_exact_at_any_angle(angle, spans):
    from slidebeam.run.geometry import reference_coordinates

    beam = arc_scene(angle, spans, {"steps": 1}).beams[0]
    q = reference_coordinates(beam)
    frames = q[:, 3:12].reshape(-1, 3, 3)  # rows d1, d2, d3
    t0 = np.asarray(beam.geometry.tangent_at_start())
    for a, frame in enumerate(frames):
        assert np.abs(frame @ frame.T - np.eye(3)).max() < 1e-14, a
        phi = math.copysign(slidebeam._core.greville(spans, a) * beam.geometry.length / 1.5, angle)
        tangent = t0 * math.cos(phi) + np.cross(ARC_NORMAL, t0) * math.sin(phi)
        assert np.abs(frame[0] - tangent).max() < 1e-14, a
        # transported about the arc's axis: the section keeps its angle to the normal
        assert frame[1] @ ARC_NORMAL == pytest.approx(frames[0][1] @ ARC_NORMAL, abs=1e-14), a


@pytest.mark.parametrize("angle, spans", ARC_CASES)
def test_an_unloaded_arc_is_stress_free_and_stays_put(angle, spans):
    sim = slidebeam.Simulation(arc_scene(angle, spans, {"type": "static", "steps": 2}))
    reference = sim.control_points(0).copy()
    assert sim.residual(t=1.0).norm() < 1e-11
    records = sim.solve_static()
    assert all(r.converged for r in records)
    assert np.abs(sim.control_points(0) - reference).max() < 1e-12


@pytest.mark.parametrize("angle", [180.0, -180.0, 360.0])
def test_an_unloaded_arc_stays_at_rest(angle):
    sim = slidebeam.Simulation(arc_scene(angle, 33, {"type": "dynamic", "dt": 0.01, "t_end": 0.05}))
    outcome = sim.run_dynamic()
    assert outcome.complete
    start = np.array(outcome.records[0].tracked[0])
    for rec in outcome.records:
        assert rec.constraint_residual < 1e-12
        assert np.abs(np.array(rec.tracked[0]) - start).max() < 1e-12
        assert rec.kinetic_energy < 1e-20
