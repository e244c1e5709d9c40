# SPDX-License-Identifier: MIT
"""The effect registry is the one description of an effect type: the scene parser validates the
tables it declares from the specs the build writes (effect_specs.json), and the energy balance
reads each effect's role from it."""
from __future__ import annotations

import json

import pytest

import slidebeam
from slidebeam import _core
from slidebeam.scene.effect_tables import SPECS_FILE, effect_specs, table_specs
from slidebeam.scene import SceneError

from test_dynamics import everything_scene


def test_the_shipped_specs_are_the_registry_s():
    """effect_specs.json is written by the build; a stale copy would validate scenes against an
    old schema."""
    assert json.loads(SPECS_FILE.read_text()) == json.loads(_core.effect_specs_json())


def test_every_model_effect_has_a_registered_role():
    sim = slidebeam.Simulation(everything_scene("energy-momentum", "full"))
    specs = effect_specs()
    roles = {e.type: specs[e.type].role for e in sim.active_effects}
    assert roles["beam_elastic"] == "stored" and roles["clamp"] == "constraint" and roles["moment"] == "external"
    assert "damping" in table_specs() and table_specs()["damping"][0].role == "dissipative"


@pytest.mark.parametrize("entry, words", [
    ({"beam": "b", "retardation_tme": 0.1}, "unknown key 'retardation_tme'"),
    ({"retardation_time": 0.1}, "missing required key"),
    ({"beam": "b", "retardation_time": -1.0}, "must be >= 0 s"),
    ({"beam": "b", "retardation_times": [0.1, 0.2]}, "array of 6 numbers"),
    ({"beam": "nope"}, "beam 'nope' does not exist"),
])
def test_registry_tables_are_validated_from_their_spec(entry, words):
    data = dict(everything_scene("energy-momentum", "full").data)
    data["damping"] = [entry]
    with pytest.raises(SceneError) as err:
        slidebeam.scene_from_dict(data)
    assert "[[damping]] #1" in str(err.value) and words in str(err.value)
