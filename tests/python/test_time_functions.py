# SPDX-License-Identifier: MIT
"""Time functions `sine`, `table` and `spline` (inline or from a CSV file) and a time function on gravity:
their values, the core's values through a run (the momentum a free rod gains under
energy-momentum is exactly sum h F(t_n+1/2)), the scene errors, and the energy balance closing
with a sine-modulated gravity and a tabulated force."""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

import slidebeam
from slidebeam.scene import parse as sc
from slidebeam.scene import TimeFunction
from test_dynamics import everything_scene

SINE = {"type": "sine", "amplitude": 0.8, "frequency": 1.5, "phase": 0.4, "offset": 0.3}
RAMPED = {**SINE, "ramp": 0.25}  # faded in over the first 0.25 s of the rods' 0.4
TABLE = {"type": "table", "times": [0.0, 0.1, 0.25, 0.3], "values": [0.0, 2.0, -1.0, 0.5]}
SPLINE = {**TABLE, "type": "spline"}


def test_values_of_sine_and_table():
    f = sc.TimeFunction("sine", amplitude=0.8, frequency=1.5, phase=0.4, offset=0.3)
    for t in (0.0, 0.2, 1.7):
        assert f.value(t) == pytest.approx(0.3 + 0.8 * math.sin(2 * math.pi * 1.5 * t + 0.4), abs=1e-15)
    r = sc.TimeFunction("sine", t1=2.0, amplitude=0.8, frequency=1.5, phase=0.4, offset=0.3)  # ramp = 2 s
    for t, fade in ((-1.0, 0.0), (0.0, 0.0), (1.0, 0.5), (1.5, 0.896484375), (2.0, 1.0), (3.0, 1.0)):
        assert r.value(t) == pytest.approx(0.3 + 0.8 * fade * math.sin(2 * math.pi * 1.5 * t + 0.4), abs=1e-15)
    g = sc.TimeFunction("table", times=(0.0, 0.1, 0.25, 0.3), values=(0.0, 2.0, -1.0, 0.5))
    assert [g.value(t) for t in (-1.0, 0.0, 0.05, 0.1, 0.2, 0.3, 5.0)] == pytest.approx(
        [0.0, 0.0, 1.0, 2.0, 0.0, 0.5, 0.5], abs=1e-15)


def test_the_spline_is_smooth_through_its_points_and_starts_and_ends_at_rest():
    """Through every point, zero slope at both ends and constant beyond, rate and acceleration
    continuous at the inner points; two points: the smooth step 3u^2 - 2u^3."""
    times, values = (0.0, 0.1, 0.25, 0.3, 0.7), (0.0, 2.0, -1.0, 0.5, 0.5)
    f = sc.TimeFunction("spline", times=times, values=values)
    assert [f.value(t) for t in times] == pytest.approx(values, abs=1e-14)
    d = 1e-6
    rate = lambda t: (f.value(t + d) - f.value(t - d)) / (2 * d)  # noqa: E731
    for t, side in ((times[0], 1), (times[-1], -1)):  # the difference quotient into the spline falls with d: no slope
        quotient = [(f.value(t + side * e) - f.value(t)) / e for e in (1e-4, 1e-5)]
        assert abs(quotient[1]) < 0.11 * abs(quotient[0]) and abs(quotient[0]) < 1.0
    assert f.value(-1.0) == 0.0 and f.value(2.0) == 0.5
    for t in times[1:-1]:
        left = (f.value(t) - 2 * f.value(t - d) + f.value(t - 2 * d)) / d ** 2
        right = (f.value(t + 2 * d) - 2 * f.value(t + d) + f.value(t)) / d ** 2
        assert rate(t - 1e-9) == pytest.approx(rate(t + 1e-9), abs=1e-5)
        assert left == pytest.approx(right, rel=1e-3, abs=1e-2)
    assert max(abs(rate(t)) for t in (0.05, 0.18, 0.27)) > 10.0  # it moves
    step = sc.TimeFunction("spline", times=(1.0, 3.0), values=(0.0, 2.0))
    for u in (0.0, 0.25, 0.5, 0.9, 1.0):
        assert step.value(1.0 + 2.0 * u) == pytest.approx(2.0 * (3 * u * u - 2 * u ** 3), abs=1e-14)


def free_rod(integrator: str = "energy-momentum", **parts: object) -> dict:
    """A free rod (L = 1 m, rhoA = 2 kg/m: 2 kg), no supports, at rest."""
    return {
        "analysis": {"type": "dynamic", "integrator": integrator, "dt": 0.01, "t_end": 0.4},
        "beam": [{"name": "rod", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 2,
                  "section": {"EA": 1e4, "kGA": 1e4, "GJ": 10.0, "EI2": 10.0, "EI3": 10.0,
                              "rhoA": 2.0, "rhoI2": 1e-4, "rhoI3": 1e-4}}],
        **parts,
    }


def impulses(f: sc.TimeFunction, records) -> list[float]:
    """sum over the steps up to each record of h f(t_n + h/2) (energy-momentum's load time)."""
    out, total, t = [], 0.0, 0.0
    for r in records:
        while t < r.t - 1e-12:
            total += r.dt * f.value(t + 0.5 * r.dt)
            t += r.dt
        out.append(total)
    return out


@pytest.mark.parametrize("tf", [SINE, RAMPED, TABLE, SPLINE], ids=["sine", "ramped sine", "table", "spline"])
def test_the_core_evaluates_what_the_scene_says(tf):
    """A force F0 f(t) and a gravity g f(t) on free rods: under energy-momentum the momentum is
    exactly F0 sum h f(t_n+1/2) (m g sum h f), so the core's values match the scene's to the
    Newton tolerance."""
    force = free_rod(load=[{"type": "force", "beam": "rod", "at": 0.5, "value": [0.0, 3.0, 0.0], "time_function": tf}])
    scene = slidebeam.scene_from_dict(force)
    records = slidebeam.Simulation(scene).run_dynamic().records
    f = TimeFunction.of_entry(scene.entries("load")[0])
    assert f.type == tf["type"]
    for r, J in zip(records, impulses(f, records)):
        assert r.linear_momentum[1] == pytest.approx(3.0 * J, abs=1e-9)
    assert max(abs(r.linear_momentum[1]) for r in records) > 0.1

    weight = slidebeam.scene_from_dict(free_rod(gravity={"g": [0.0, 0.0, -9.81], "time_function": tf}))
    assert TimeFunction.of_entry(weight.entries("gravity")[0]) == f
    records = slidebeam.Simulation(weight).run_dynamic().records
    for r, J in zip(records, impulses(f, records)):
        assert r.linear_momentum[2] == pytest.approx(-2.0 * 9.81 * J, abs=1e-9)


def test_table_from_a_csv_file_relative_to_the_scene(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "gust.csv").write_text("# a gust\nt,value\n0.0, 0.0\n0.1,2.0\n\n0.25,-1.0\n0.3,0.5\n")
    text = ('[analysis]\ntype = "dynamic"\ndt = 0.01\nt_end = 0.4\n'
            '[[beam]]\nname = "rod"\nstart = [0, 0, 0]\nend = [1, 0, 0]\nspans = 2\n'
            'section = { EA = 1e4, kGA = 1e4, GJ = 10.0, EI2 = 10.0, EI3 = 10.0, rhoA = 2.0, rhoI2 = 1e-4, rhoI3 = 1e-4 }\n'
            '[[load]]\ntype = "force"\nbeam = "rod"\nat = 0.5\nvalue = [0, 3, 0]\n'
            'time_function = { type = "table", file = "data/gust.csv" }\n')
    (tmp_path / "scene.toml").write_text(text)
    from_file = slidebeam.load_scene(tmp_path / "scene.toml")
    inline = slidebeam.scene_from_dict(free_rod(load=[{"type": "force", "beam": "rod", "at": 0.5,
                                                       "value": [0.0, 3.0, 0.0], "time_function": TABLE}]))
    assert from_file.entries("load") == inline.entries("load")
    a = slidebeam.Simulation(from_file).run_dynamic().records
    b = slidebeam.Simulation(inline).run_dynamic().records
    assert [r.linear_momentum for r in a] == [r.linear_momentum for r in b]


@pytest.mark.parametrize("tf, csv, parts", [
    ({"type": "sine", "frequency": 0.0}, None, ("key 'frequency'", "> 0")),
    ({"type": "sine", "amplitude": 1.0}, None, ("key 'frequency'", "missing required key")),
    ({"type": "sine", "frequency": 1.0, "t0": 1.0}, None, ("unknown key 't0'",)),
    ({"type": "table", "times": [0.0, 0.2, 0.2], "values": [1.0, 2.0, 3.0]}, None,
     ("key 'times'", "strictly increasing, got 0.2 then 0.2")),
    ({"type": "table", "times": [0.0, 0.2], "values": [1.0]}, None, ("key 'values'", "as many entries as times (2)")),
    ({"type": "table", "times": [], "values": []}, None, ("key 'times'", "at least one point")),
    ({"type": "table", "values": [1.0]}, None, ("key 'times'", "missing required key")),
    ({"type": "table", "file": "missing.csv"}, None, ("key 'file'", "cannot read", "missing.csv")),
    ({"type": "table", "file": "f.csv"}, "t,value\n0,1\n1,x\n", ("key 'file'", "f.csv, line 3", "'1,x'")),
    ({"type": "table", "file": "f.csv"}, "0,1\n1,2,3\n", ("key 'file'", "f.csv, line 2")),
    ({"type": "table", "file": "f.csv"}, "0,1\n2,2\n1,3\n", ("key 'file'", "f.csv: times must be strictly increasing")),
    ({"type": "table", "file": "f.csv", "times": [0.0]}, "0,1\n", ("key 'file'", "not both")),
])
@pytest.mark.parametrize("where", ["load", "gravity"])
def test_scene_errors_name_file_table_and_key(tmp_path, tf, csv, parts, where):
    if csv is not None:
        (tmp_path / "f.csv").write_text(csv)
    if where == "load":
        data = free_rod(load=[{"type": "force", "beam": "rod", "at": 0.5, "value": [0.0, 3.0, 0.0], "time_function": tf}])
        table = "[[load]] #1.time_function"
    else:
        data = free_rod(gravity={"g": [0.0, 0.0, -9.81], "time_function": tf})
        table = "[gravity].time_function"
    with pytest.raises(slidebeam.SceneError) as err:
        slidebeam.scene_from_dict(data, file="scene.toml", base_dir=str(tmp_path))
    text = str(err.value)
    for part in ("scene.toml", table, *parts):
        assert part in text, (part, text)


def test_gravity_keeps_its_defaults():
    """Without a time function gravity is ramped with the load steps in statics and constant in
    dynamics (model.py); [gravity] takes no other new key."""
    (gravity,) = slidebeam.scene_from_dict(free_rod(gravity={"g": [0, 0, -9.81]})).entries("gravity")
    assert gravity.text["tf_type"] == "constant"  # dynamic
    with pytest.raises(slidebeam.SceneError, match="unknown key 'tf'"):
        slidebeam.scene_from_dict(free_rod(gravity={"g": [0, 0, -9.81], "tf": {}}))
    static = free_rod(gravity={"g": [0, 0, -9.81]}, support=[{"type": "clamp", "beam": "rod", "at": "start"}])
    static["analysis"] = {"type": "static", "steps": 4, "t_end": 1.0}
    static["beam"][0]["section"].update(EI2=1e3, EI3=1e3)  # small deflection (2.5 mm): linear
    records = slidebeam.Simulation(slidebeam.scene_from_dict(static)).solve_static()
    V = {r.t: r.potential_energy for r in records}
    # a linear cantilever under a ramped load: V ~ t^2 (deflection and load both grow with t)
    assert V[1.0] < 0 and V[0.25] == pytest.approx(V[1.0] / 16, rel=1e-3)


def test_energy_balance_closes_with_a_sine_gravity_and_a_tabulated_force():
    """Gravity modulated by a sine and the tip force by a table: both are time-dependent
    potentials, so their explicit change over each step is work; under energy-momentum H - H_0 -
    W + D stays at the Newton tolerance."""
    data = dict(everything_scene("energy-momentum", "full").data)
    data["beam"] = [{k: v for k, v in b.items() if k not in ("velocity", "angular_velocity")} for b in data["beam"]]
    data["gravity"] = {"g": [0.0, 0.0, -9.81], "time_function": {"type": "sine", "amplitude": 0.5, "frequency": 2.0,
                                                                 "offset": 1.0}}
    data["load"] = [dict(data["load"][0], time_function={"type": "table", "times": [0.0, 0.3, 0.6, 1.0],
                                                          "values": [0.0, 3.0, -2.0, 1.0]}), data["load"][1]]
    scene = slidebeam.scene_from_dict(data)
    scene = dataclasses.replace(scene, analysis=dataclasses.replace(scene.analysis, t_end=1.0, dt=0.01))
    sim = slidebeam.Simulation(scene)
    records = sim.run_dynamic().records
    labels = sim.energy_flow_labels()
    assert "gravity.work" in labels and any(lab.startswith("force[") for lab in labels)
    K = max(r.kinetic_energy for r in records)
    gravity_work = [r.flows[labels.index("gravity.work")] for r in records]
    assert max(abs(w) for w in gravity_work) > 1e-2 * K
    worst = max(r.energy_balance_error for r in records)
    assert worst <= 1e-9 * K, f"|H - H0 - W + D| = {worst:.3e} of max K {K:.3e}"
