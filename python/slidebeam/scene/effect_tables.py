# SPDX-License-Identifier: MIT
"""Scene tables of effects declared in the core's registry.

An effect type registered with a table name (C++: ``EffectSpec::table``) is created by the
scene's ``[[table]]`` entries (or by its single ``[table]``); effect types that share a table are
its variants, picked by the entry's ``type`` key (``[[support]] type = "clamp"``). Which keys a table takes, their kinds, units, defaults and
bounds come from the registry's specs, which the build writes to ``effect_specs.json`` beside
this module: nothing here names an effect. Stdlib only (the scene parser must import without
the core); parse.py validates the entries with these specs.
"""
from __future__ import annotations

import functools
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

SPECS_FILE = Path(__file__).parents[1] / "effect_specs.json"  # the package's, beside _core


@dataclass(frozen=True)
class ParamSpec:
    key: str
    kind: str          # number, integer, vector, choice, beam, track, point, end, position, motion, beams, ends,
                       # points, time_function, name (see ParamSpec::Kind in src/model/effect.hpp)
    unit: str
    meaning: str
    default: str       # TOML text; "" = required
    min: float
    max: float
    min_open: bool
    size: int
    choices: tuple[str, ...]   # choice: the values; beam, beams: the formulations allowed (empty: any)
    optional: bool = False     # may be left out (the core then decides)
    on: str = ""               # point, end, position: the beam parameter it lies on ("": "beam")


@dataclass(frozen=True)
class EffectSpec:
    type: str
    table: str
    variant: str       # the entry's `type` value that picks this effect ("": the table's only one)
    single: bool       # a single [table] rather than an array [[table]]
    meaning: str
    role: str          # stored, constraint, external, dissipative, driving
    stored: str        # for stored effects: strain, potential or kinetic energy
    params: tuple[ParamSpec, ...]


@dataclass(frozen=True)
class EffectEntry:
    """One scene entry of a registry table, as the core's EffectParams."""

    type: str
    label: str
    table: str = ""
    index: int = 0     # the entry's number in its table, from 0
    variant: str = ""
    place: str = ""    # how messages name the entry: "[[support]] #2", "[gravity]"
    num: dict[str, float] = field(default_factory=dict)
    vec: dict[str, list[float]] = field(default_factory=dict)
    text: dict[str, str] = field(default_factory=dict)


def _bound(v: Any) -> float:
    return float(v) if not isinstance(v, str) else (math.inf if v == "inf" else -math.inf)


@functools.lru_cache(maxsize=None)
def effect_specs() -> dict[str, EffectSpec]:
    """Every registered effect type's spec, by type (empty if the core is not built yet)."""
    if not SPECS_FILE.is_file():
        return {}
    out = {}
    for d in json.loads(SPECS_FILE.read_text()):
        params = tuple(ParamSpec(p["key"], p["kind"], p["unit"], p["meaning"], p["default"], _bound(p["min"]),
                                 _bound(p["max"]), p["min_open"], p["size"], tuple(p["choices"]), p["optional"], p["on"])
                       for p in d["params"])
        out[d["type"]] = EffectSpec(d["type"], d["table"], d["variant"], d["single"], d["meaning"], d["role"],
                                    d.get("stored", ""), params)
    return out


def table_specs() -> dict[str, tuple[EffectSpec, ...]]:
    """The specs of effects a scene creates through a table, by table name: one, or the table's
    variants."""
    out: dict[str, list[EffectSpec]] = {}
    for s in effect_specs().values():
        if s.table:
            out.setdefault(s.table, []).append(s)
    return {table: tuple(specs) for table, specs in out.items()}
