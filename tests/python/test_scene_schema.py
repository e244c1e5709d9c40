# SPDX-License-Identifier: MIT
"""The scene reference cannot go stale: every key scene.py accepts is described in
scene/schema.py (and nothing else is), the documented defaults are the parser's, and the
committed docs/scene-reference.md is what scripts/scene_reference.py writes."""
from __future__ import annotations

import ast
import importlib.util
import tomllib
from pathlib import Path

import pytest

from slidebeam.scene import parse as sc
from slidebeam.scene import schema
from slidebeam.scene.effect_tables import table_specs

ROOT = Path(__file__).resolve().parents[2]

# the schema's tables and the keys scene.py accepts in each
ACCEPTED = {
    "scene": set(sc._SCENE_KEYS),
    "analysis": set(sc._ANALYSIS_KEYS),
    "analysis.adapt": set(sc._ADAPT_KEYS),
    "beam": set(sc._BEAM_KEYS),
    "body": set(sc._BODY_KEYS),
    "beam.arc": set(sc._ARC_KEYS),
    "beam.section": set(sc._SHAPE_KEYS + sc._EXPLICIT_KEYS + sc._ANCF_SHAPE_KEYS + sc._ANCF_EXPLICIT_KEYS),
    "output": set(sc._OUTPUT_KEYS),
    "output.track": set(sc._TRACK_KEYS),
    "petsc": {"options_file", "<option>"},  # any PETSc option besides options_file
    "time_function": {"type"} | {k for keys in sc._TF_PARAMS.values() for k in keys},
    "motion": set(sc._MOTION_KEYS),
}
# module constants of scene.py that hold accepted keys (each must be covered by ACCEPTED above)
KEY_CONSTANTS = {"_TOP_KEYS", "_SCENE_KEYS", "_ANALYSIS_KEYS", "_ADAPT_KEYS", "_BEAM_KEYS", "_BODY_KEYS", "_ARC_KEYS", "_SHAPE_KEYS",
                 "_EXPLICIT_KEYS", "_ANCF_SHAPE_KEYS", "_ANCF_EXPLICIT_KEYS", "_OUTPUT_KEYS", "_TRACK_KEYS",
                 "_TF_PARAMS", "_MOTION_KEYS"}


def _tables() -> dict[str, schema.Table]:
    return {t.name: t for t in schema.TABLES}


def test_every_accepted_key_is_documented_and_every_documented_key_accepted():
    tables = _tables()
    assert set(tables) == set(ACCEPTED)
    for name, keys in ACCEPTED.items():
        documented = [k.key for k in tables[name].keys]
        assert len(documented) == len(set(documented)), f"{name}: a key is described twice"
        assert keys - set(documented) == set(), f"[{name}] accepts keys the schema does not describe"
        assert set(documented) - keys == set(), f"[{name}]: the schema describes keys scene.py refuses"


def test_top_level_tables_are_documented():
    own = {name for name in ACCEPTED if "." not in name and name not in ("time_function", "motion")}
    assert own == set(sc._TOP_KEYS)
    # the effect tables come from the registry, not from the schema, and are not the scene's own
    assert not own & set(table_specs())


def test_time_function_variants_are_the_parsers():
    assert dict(_tables()["time_function"].variants) == sc._TF_PARAMS


def test_check_keys_takes_only_documented_constants():
    """Every `check_keys(...)` in scene.py names its keys through the constants above (a new
    literal key list would bypass the schema)."""
    tree = ast.parse((ROOT / "python" / "slidebeam" / "scene" / "parse.py").read_text())
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)
             and n.func.attr == "check_keys" and n.args]
    assert len(calls) >= 10
    for call in calls:
        for node in ast.walk(call.args[0]):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                assert node.value in ("type", "rotation"), \
                    f"scene.py line {call.lineno}: literal key '{node.value}' in check_keys: add it to a constant " \
                    f"and to scene/schema.py"
            if isinstance(node, ast.Name) and node.id.lstrip("_").isupper():
                assert node.id in KEY_CONSTANTS, f"scene.py line {call.lineno}: {node.id} is not in the schema test"


def test_every_key_has_a_meaning_and_units_are_si():
    allowed_units = {"", "m", "s", "m/s", "rad", "rad/s", "Hz", "N", "N m^2", "Pa", "kg/m", "kg m", "kg/m^3",
                     "degree", "GB", "kg", "kg m^2"}
    for t in schema.TABLES:
        assert t.meaning
        for k in t.keys:
            assert k.meaning, f"{t.name}.{k.key}"
            assert k.unit in allowed_units, f"{t.name}.{k.key}: unit {k.unit!r}"
    for specs in table_specs().values():
        for s in specs:
            for p in s.params:
                assert p.meaning, f"{s.type}.{p.key}"


def _scene(dynamic: bool) -> sc.Scene:
    analysis = {"type": "dynamic", "dt": 0.01} if dynamic else {}
    return sc.scene_from_dict({
        "analysis": analysis,
        "beam": [{"name": "a", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 2,
                  "section": {"EA": 1.0, "kGA": 1.0, "GJ": 1.0, "EI2": 1.0, "EI3": 1.0, "rhoA": 1.0}}],
    })


@pytest.mark.parametrize("table, attr", [("analysis", "analysis"), ("output", "output")])
def test_documented_literal_defaults_are_the_parsers(table, attr):
    """A default written as a plain TOML value is the value scene.py fills in."""
    checked = 0
    for k in _tables()[table].keys:
        try:
            value = tomllib.loads(f"v = {k.default}")["v"]
        except tomllib.TOMLDecodeError:
            continue  # prose: depends on other keys
        for dynamic in (False, True):
            if dynamic and k.key in ("type", "dt"):  # given by the dynamic scene
                continue
            parsed = getattr(getattr(_scene(dynamic), attr), k.key)
            assert parsed == value, f"[{table}] {k.key}: documented {k.default}, parsed {parsed!r}"
        checked += 1
    assert checked >= 3


def test_documented_beam_defaults_are_the_parsers():
    beam = _scene(False).beams[0]
    for k in _tables()["beam"].keys:
        try:
            value = tomllib.loads(f"v = {k.default}")["v"]
        except tomllib.TOMLDecodeError:
            continue
        parsed = getattr(beam, k.key)
        if k.key == "quadrature" and value == "auto":  # resolved per beam from its span slenderness
            value = sc.auto_quadrature(beam.section, beam.geometry.length / beam.spans)
        assert (list(parsed) if isinstance(parsed, tuple) else parsed) == value, k.key
    assert sc.default_every(_scene(True).analysis) == max(1, round(1.0 / 0.01) // sc.RECORDS_BY_DEFAULT)


def _reference_script():
    spec = importlib.util.spec_from_file_location("scene_reference", ROOT / "scripts" / "scene_reference.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_committed_scene_reference_is_current():
    text = _reference_script().render()
    committed = (ROOT / "docs" / "scene-reference.md").read_text()
    assert committed == text, "docs/scene-reference.md is out of date: run scripts/scene_reference.py"


def test_scene_reference_names_every_table_and_key():
    text = (ROOT / "docs" / "scene-reference.md").read_text()
    for t in schema.TABLES:
        assert f"### {t.name}\n" in text
        for k in t.keys:
            assert f"| `{k.key}` |" in text
    for table, specs in table_specs().items():
        assert f"### {table}\n" in text
        for s in specs:
            for p in s.params:
                assert f"| `{p.key}` |" in text
