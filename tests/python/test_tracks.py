# SPDX-License-Identifier: MIT
"""A slider passing from one carrier onto the next (issue 38): `[[sliding_joint]] carrier` as a
list of beams joined end to end, one sliding coordinate along them. The seed's S2 scene with
its carrier AB cut at mid-span into two carriers welded there (the second one drawn either
way): exact step Jacobians of every integrator with s crossing the junction; energy exact under
energy-momentum through the crossing; as ANCF cables the welded pair is the one cable it was
cut from, so the slider's run is that cable's to the Newton tolerance; 1 = 2 ranks; bad tracks
refused, naming the key."""
from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

import slidebeam

from checks import check_joint_step_jacobian, distributed_and_serial_records
from test_ancf_sliding import INTEGRATORS, as_cables

ROOT = Path(__file__).resolve().parents[2]
SEED = ROOT / "runs" / "seed" / "free_fall_inclined_1+4.toml"


def seed_data(formulation: str) -> dict:
    """The inclined S2 scene (the slider CM's tip C at s = 0.4 of the 2 m carrier AB, sliding
    down towards B), both beams as `formulation`."""
    with open(SEED, "rb") as f:
        data = tomllib.load(f)
    return as_cables(data, ("AB", "CM")) if formulation == "ancf" else data


def track_data(formulation: str, reversed_second: bool = False, analysis: dict | None = None) -> dict:
    """S2 with AB cut at mid-span M into AM (2 spans) and MB (2 spans; drawn from B to M when
    reversed_second), welded at M, and the slider running on the track [AM, MB]. formulation
    "mixed": AM a director beam, MB an ANCF cable (the slider a director beam)."""
    data = seed_data("director" if formulation == "mixed" else formulation)
    ab = data["beam"][0]
    a, b = np.array(ab["start"]), np.array(ab["end"])
    m = 0.5 * (a + b)
    first = dict(copy.deepcopy(ab), name="AM", start=list(a), end=list(m), spans=2)
    second = dict(copy.deepcopy(ab), name="MB", start=list(b if reversed_second else m),
                  end=list(m if reversed_second else b), spans=2)
    data["beam"] = [first, second, data["beam"][1]]
    if formulation == "mixed":
        as_cables(data, ("MB",))
    data["support"] = [{"type": "spherical", "beam": "AM", "at": "start"},
                       {"type": "spherical", "beam": "MB", "at": "start" if reversed_second else "end"}]
    data["joint"] = [{"type": "rigid", "beams": ["AM", "MB"], "at": ["end", "end" if reversed_second else "start"]}]
    data["sliding_joint"][0]["carrier"] = ["AM", "MB"]
    data["analysis"].update(analysis or {})
    return data


def scene(data: dict, label: str) -> slidebeam.Scene:
    return slidebeam.scene_from_dict(data, file=f"{label}.toml", base_dir=str(SEED.parent))


CASES = [(f, i, False, ds) for f in ("director", "ancf") for i in INTEGRATORS for ds in (0.03, 0.65, 1.3)] + \
        [(f, i, True, 0.71) for f in ("director", "ancf", "mixed") for i in INTEGRATORS] + \
        [("mixed", i, False, 0.65) for i in INTEGRATORS]


@pytest.mark.one_case_in_parallel
@pytest.mark.parametrize("formulation,integrator,reversed_second,ds", CASES)
def test_step_jacobian_is_exact_across_the_junction(formulation, integrator, reversed_second, ds):
    """s_n = 0.4 and s_n+1 = s_n + ds on the track of two 1 m carriers: within the first (0.03),
    just onto the second (0.65), across the junction and a knot of the second (1.3), onto a
    second carrier drawn the other way (0.71)."""
    sim = slidebeam.Simulation(scene(track_data(formulation, reversed_second, {"integrator": integrator, "dt": 0.01}),
                                     f"track {formulation} {integrator}"))
    check_joint_step_jacobian(sim, ds, f"{formulation} {integrator} reversed={reversed_second}")


@pytest.mark.one_case_in_parallel
@pytest.mark.parametrize("integrator", INTEGRATORS)
def test_friction_on_a_track_has_an_exact_step_jacobian(integrator):
    """[[friction]] on the slider: its normal force reads the carrier blocks of whichever carrier
    s is on; s_n+1 just onto the reversed second carrier."""
    data = track_data("director", True, {"integrator": integrator, "dt": 0.01})
    data["friction"] = [{"beam": "CM", "mu": 0.3}]
    sim = slidebeam.Simulation(scene(data, f"track friction {integrator}"))
    check_joint_step_jacobian(sim, 0.65, f"friction on a track, {integrator}")


@pytest.mark.skip_in_parallel
def test_a_driven_slider_runs_along_the_track():
    """[[slider_drive]] prescribes s along the whole track: 1 m by a smooth ramp over 0.5 s from
    s = 0.4, across the junction; s = 1.4 after it to 1e-9, and the balance closes with the
    drive's work."""
    data = track_data("director", True, {"t_end": 0.6, "dt": 2e-3})
    data["slider_drive"] = [{"beam": "CM", "distance": 1.0, "time_function": {"type": "smooth_ramp", "t0": 0.0, "t1": 0.5}}]
    sim = slidebeam.Simulation(scene(data, "driven on a track"))
    result = sim.run_dynamic()
    assert sim.joint_states()[0].s == pytest.approx(1.4, abs=1e-9)
    last = result.records[-1]
    kinetic = max(r.kinetic_energy for r in result.records)
    assert abs(last.energy_balance_error) <= 1e-9 * kinetic, last.energy_balance_error / kinetic


@pytest.mark.skip_in_parallel
def test_an_iterate_that_ran_away_is_not_accepted():
    """A slider driven at 2 m/s that stops dead (no ramp) on the reversed second carrier: the
    stop's steps are hard (one Newton iterate ran away to |F| ~ 1e154, where the roundoff level
    eps || |J| |x| || of the iterate is as large, and the roundoff test took it as converged).
    Every accepted step has a residual at the Newton tolerance, and the run reaches its end
    (past the run-away at t = 0.511)."""
    data = track_data("director", True, {"t_end": 0.53, "dt": 2e-3})
    data["slider_drive"] = [{"beam": "CM", "speed": 2.0, "start": 0.0, "stop": 0.5}]
    data["output"] = dict(data.get("output", {}), every=1)
    result = slidebeam.Simulation(scene(data, "dead stop")).run_dynamic()
    assert result.records[-1].t == pytest.approx(0.53)
    worst = max(r.residual_norm for r in result.records if r.converged)
    assert worst < 1e-6, worst


def run_records(data: dict, label: str, t_end: float) -> list:
    data["analysis"].update({"t_end": t_end})
    data["output"] = dict(data.get("output", {}), every=1)
    return slidebeam.Simulation(scene(data, label)).run_dynamic().records


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("formulation,reversed_second", [("director", False), ("director", True), ("ancf", False),
                                                         ("ancf", True), ("mixed", True)])
def test_energy_is_exact_through_the_crossing(formulation, reversed_second):
    """Energy-momentum, dt = 1 ms, 0.6 s: the slider runs from s = 0.4 across the junction at
    s = 1; the energy stays within 10x the Newton tolerance of the largest kinetic energy."""
    sim = slidebeam.Simulation(scene(track_data(formulation, reversed_second, {"t_end": 0.6}), "crossing"))
    result = sim.run_dynamic()
    s = [j.s for j in sim.joint_states()]
    assert result.records[-1].t == pytest.approx(0.6)
    assert s[0] > 1.05, f"the slider did not cross the junction: s = {s[0]}"
    energy = np.array([r.total_energy for r in result.records])
    kinetic = max(r.kinetic_energy for r in result.records)
    assert np.abs(energy - energy[0]).max() <= 1e-9 * kinetic, np.abs(energy - energy[0]).max() / kinetic


@pytest.mark.skip_in_parallel
@pytest.mark.parametrize("reversed_second", [False, True])
def test_welded_cables_run_as_the_one_cable(reversed_second):
    """As ANCF cables, two carriers welded at a node (position and slope) are the cable of four
    elements they were cut from: the slider's run across the junction is that cable's to the
    Newton tolerance."""
    whole = run_records(seed_data("ancf"), "whole cable", 0.6)
    cut = run_records(track_data("ancf", reversed_second), "cut cable", 0.6)
    assert len(whole) == len(cut)
    a = np.array([r.tracked for r in whole])
    b = np.array([r.tracked for r in cut])
    assert np.abs(a - b).max() < 1e-8, np.abs(a - b).max()


@pytest.mark.one_case_in_parallel
def test_distributed_equals_serial():
    """The track on every rank and alone on each (meaningful under mpirun -n 2)."""
    distributed_and_serial_records(scene(track_data("director", True, {"t_end": 0.05}), "track on ranks"))


def test_carriers_that_do_not_meet_are_refused():
    data = track_data("director")
    data["beam"][1]["start"] = [0.9, -0.5, 0.0]  # 3.4 cm off AM's end
    data["support"] = [data["support"][0]]
    data.pop("joint")
    with pytest.raises(slidebeam.SceneError, match=r"carrier.*'MB' does not begin where 'AM' ends"):
        slidebeam.Simulation(scene(data, "gap"))


def test_a_carrier_twice_is_refused():
    data = track_data("director")
    data["sliding_joint"][0]["carrier"] = ["AM", "MB", "AM"]
    with pytest.raises(slidebeam.SceneError, match=r"carrier.*'AM' is twice on the track"):
        slidebeam.Simulation(scene(data, "twice"))


def test_the_end_of_the_track_stops_the_run():
    """The slider leaves the track at the far end of its second carrier: the run stops there
    and says which carrier's end it reached."""
    data = track_data("director", True, {"t_end": 3.0, "dt": 2e-3})
    sim = slidebeam.Simulation(scene(data, "end of track"))
    result = sim.run_dynamic()
    assert result.stopped is not None and "the start of carrier 'MB', the end of its track" in result.stopped, result.stopped
    assert sim.joint_states()[0].s == pytest.approx(2.0, abs=1e-6)
