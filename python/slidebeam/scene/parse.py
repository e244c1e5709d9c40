"""Scene files: load a TOML (or dict) scene description and validate it.

The result is a tree of frozen dataclasses with every default filled in and
every ``at`` normalised to an arc length ``s`` in ``[0, L]``.

Error messages name the file, the table and the key. Tables of arrays are
numbered from 1 in messages (``[[beam]] #1``), while ``--set`` overrides
index them from 0 (``beam.0.spans=32``), like Python.

Section defaults: the shear correction factor ``k`` defaults to 5/6 for a
rectangle and 0.9 for a circle.

This module must stay importable on its own (stdlib + numpy only).
"""

from __future__ import annotations

import difflib
import functools
import math
import os
import re
import tomllib
import copy
import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

try:
    from .effect_tables import EffectEntry, EffectSpec, ParamSpec, table_specs
except ImportError:  # loaded on its own, outside the package: its sibling by path
    import importlib.util as _importlib_util
    import sys as _sys

    _et_spec = _importlib_util.spec_from_file_location("slidebeam_effect_tables", Path(__file__).with_name("effect_tables.py"))
    _et = _importlib_util.module_from_spec(_et_spec)
    _sys.modules[_et_spec.name] = _et
    _et_spec.loader.exec_module(_et)
    EffectEntry, EffectSpec, ParamSpec, table_specs = _et.EffectEntry, _et.EffectSpec, _et.ParamSpec, _et.table_specs

Vec3 = tuple[float, float, float]

_MISSING: Any = object()


# ----------------------------------------------------------------------------
# errors


class SceneError(Exception):
    """Bad scene input; ``str(err)`` names file, table and key."""

    def __init__(
        self,
        message: str,
        file: str | None = None,
        table: str | None = None,
        key: str | None = None,
    ) -> None:
        self.detail = message
        self.file = file
        self.table = table
        self.key = key
        super().__init__(self._compose())

    def _compose(self) -> str:
        where = ", ".join(
            part
            for part in (self.table, f"key '{self.key}'" if self.key is not None else None)
            if part
        )
        text = f"{where}: {self.detail}" if where else self.detail
        return f"{self.file}: {text}" if self.file else text


# ----------------------------------------------------------------------------
# dataclasses


@dataclass(frozen=True)
class Section:
    """Cross-section resultant stiffnesses and inertias."""

    EA: float
    kGA2: float
    kGA3: float
    GJ: float
    EI2: float
    EI3: float
    rhoA: float
    rhoI2: float
    rhoI3: float


@dataclass(frozen=True)
class Geometry:
    """Reference centreline: a line, a polyline or a circular arc."""

    kind: str
    points: tuple[Vec3, ...]
    center: Vec3 | None
    radius: float | None
    normal: Vec3 | None  # unit vector (arc only)
    start: Vec3 | None
    angle_deg: float | None
    length: float

    def point_at(self, s: float) -> Vec3:
        """Reference position at arc length s (clamped to [0, L])."""
        s = min(max(s, 0.0), self.length)
        if self.kind == "arc":
            c, n, p0 = (np.asarray(v) for v in (self.center, self.normal, self.start))
            assert self.radius is not None and self.angle_deg is not None
            phi = math.copysign(s / self.radius, self.angle_deg)
            return _vec(c + _rotate(p0 - c, n, phi))
        pts = [np.asarray(p) for p in self.points]
        for a, b in zip(pts[:-1], pts[1:]):
            seg = float(np.linalg.norm(b - a))
            if s <= seg:
                return _vec(a + (s / seg) * (b - a))
            s -= seg
        return _vec(pts[-1])

    def tangent_at(self, s: float) -> Vec3:
        """Unit tangent at arc length s (clamped to [0, L]); at a polyline's corner the mean of its
        two sides' directions."""
        if self.kind == "arc":
            assert self.radius is not None and self.angle_deg is not None
            n = np.asarray(self.normal)
            return _vec(_rotate(np.asarray(self.tangent_at_start()), n, math.copysign(s / self.radius, self.angle_deg)))
        pts = [np.asarray(p) for p in self.points]
        sides = [(b - a) / float(np.linalg.norm(b - a)) for a, b in zip(pts[:-1], pts[1:])]
        corner = 1e-12 * self.length
        s = min(max(s, 0.0), self.length)
        for k, (a, b) in enumerate(zip(pts[:-1], pts[1:])):
            seg = float(np.linalg.norm(b - a))
            if s < seg - corner or k == len(sides) - 1:
                return _vec(sides[k])
            if s <= seg + corner:
                mean = sides[k] + sides[k + 1]
                return _vec(mean / np.linalg.norm(mean))
            s -= seg
        return _vec(sides[-1])

    def tangent_at_start(self) -> Vec3:
        """Unit tangent of the centreline at s = 0."""
        if self.kind == "arc":
            c, n, p0 = (np.asarray(v) for v in (self.center, self.normal, self.start))
            assert self.angle_deg is not None
            t = np.cross(n, p0 - c) * math.copysign(1.0, self.angle_deg)
        else:
            t = np.asarray(self.points[1]) - np.asarray(self.points[0])
        return _vec(t / np.linalg.norm(t))


@dataclass(frozen=True)
class Beam:
    name: str
    index: int
    geometry: Geometry
    d2: Vec3 | None  # unit vector, or None for the default
    spans: int
    quadrature: str
    strain: str
    formulation: str
    section: Section
    velocity: Vec3
    angular_velocity: Vec3
    rotation_center: Vec3 | None  # point the angular velocity turns about; None: the beam's start
    # > 0: the stress-free state is straight and untwisted, of this length (the drawing is where
    # the beam starts); 0: the drawing is the stress-free state
    unstretched_length: float = 0.0


@dataclass(frozen=True)
class Support:
    """A [[support]] entry, as the diagnostics read it."""

    type: str
    beam: int
    at: float | None  # None for "fixed"


def _spline_curvatures(times: tuple[float, ...], values: tuple[float, ...]) -> np.ndarray:
    """Second derivatives at the times of the cubic spline through (times, values) with zero slope
    at both ends: the core's TimeFunction::spline_curvatures (the same tridiagonal solve)."""
    n = len(times)
    m = np.zeros(n)
    if n < 2:
        return m
    h = np.diff(np.asarray(times, dtype=float))
    slope = np.diff(np.asarray(values, dtype=float)) / h
    diag, upper, rhs = np.zeros(n), np.zeros(n), np.zeros(n)
    diag[0], upper[0], rhs[0] = 2 * h[0], h[0], 6 * slope[0]
    diag[1:-1], upper[1:-1], rhs[1:-1] = 2 * (h[:-1] + h[1:]), h[1:], 6 * (slope[1:] - slope[:-1])
    diag[-1], rhs[-1] = 2 * h[-1], -6 * slope[-1]
    for i in range(1, n):
        w = upper[i - 1] / diag[i - 1]
        diag[i] -= w * upper[i - 1]
        rhs[i] -= w * rhs[i - 1]
    m[-1] = rhs[-1] / diag[-1]
    for i in range(n - 2, -1, -1):
        m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i]
    return m


def _spline_value(times: tuple[float, ...], values: tuple[float, ...], m: np.ndarray, t: float) -> float:
    if t <= times[0]:
        return float(values[0])
    if t >= times[-1]:
        return float(values[-1])
    i = int(np.searchsorted(times, t, side="right"))
    h = times[i] - times[i - 1]
    b = (t - times[i - 1]) / h
    a = 1.0 - b
    return float(a * values[i - 1] + b * values[i] + ((a ** 3 - a) * m[i - 1] + (b ** 3 - b) * m[i]) * h * h / 6.0)


def _smooth_blend(u: float) -> float:
    """10u^3 - 15u^4 + 6u^5: from 0 at u = 0 to 1 at u = 1, its rate and acceleration 0 at both."""
    return u * u * u * (10.0 + u * (-15.0 + 6.0 * u))


@dataclass(frozen=True)
class TimeFunction:
    """Load multiplier; unused parameters are math.inf (or 0 for t0).

    sine: offset + amplitude r(t) sin(2 pi frequency t + phase), r a smooth ramp from 0 to 1 over
    [0, t1] (none if t1 is infinite); table: piecewise linear through
    (times, values), constant beyond the ends; spline: the cubic spline through them with zero
    slope at both ends, constant beyond them (the core's TimeFunction, the same formulas)."""

    type: str
    t0: float = 0.0
    t1: float = math.inf
    t2: float = math.inf
    amplitude: float = 1.0
    frequency: float = 0.0
    phase: float = 0.0
    offset: float = 0.0
    times: tuple[float, ...] = ()
    values: tuple[float, ...] = ()

    def value(self, t: float) -> float:
        if self.type == "constant":
            return 1.0
        if self.type == "sine":  # faded in over [0, t1] (the ramp) if t1 is finite
            u = 1.0 if math.isinf(self.t1) else min(max(t / self.t1, 0.0), 1.0)
            return self.offset + self.amplitude * _smooth_blend(u) * math.sin(2.0 * math.pi * self.frequency * t + self.phase)
        if self.type == "table":
            return float(np.interp(t, self.times, self.values))
        if self.type == "spline":
            return _spline_value(self.times, self.values, self._spline_curvatures, t)
        if self.type == "step":
            return 1.0 if self.t0 <= t < self.t1 else 0.0
        if t <= self.t0:
            return 0.0
        if self.type == "ramp":
            return 1.0 if t >= self.t1 else (t - self.t0) / (self.t1 - self.t0)
        if self.type == "smooth_ramp":
            if t >= self.t1:
                return 1.0
            return _smooth_blend((t - self.t0) / (self.t1 - self.t0))
        if self.type == "hat":
            if t >= self.t2:
                return 0.0
            if t <= self.t1:
                return (t - self.t0) / (self.t1 - self.t0)
            return (self.t2 - t) / (self.t2 - self.t1)
        raise ValueError(f"unknown time function type {self.type!r}")

    @functools.cached_property
    def _spline_curvatures(self) -> np.ndarray:
        """The spline's second derivatives at its times (solved once, not at every value)."""
        return _spline_curvatures(self.times, self.values)

    def params(self) -> tuple[dict[str, float], dict[str, list[float]], dict[str, str]]:
        """The core's EffectParams of this function (num, vec, text: the tf_* keys)."""
        num = {"tf_t0": self.t0, "tf_t1": self.t1, "tf_t2": self.t2}
        vec: dict[str, list[float]] = {}
        if self.type == "sine":
            num.update({"tf_amplitude": self.amplitude, "tf_frequency": self.frequency, "tf_phase": self.phase,
                        "tf_offset": self.offset})
        if self.type in ("table", "spline"):
            vec = {"tf_times": list(self.times), "tf_values": list(self.values)}
        return num, vec, {"tf_type": self.type}

    @classmethod
    def of_entry(cls, entry: EffectEntry) -> TimeFunction:
        """The time function of an effect table's entry (its tf_* parameters)."""
        n, v = entry.num, entry.vec
        return cls(entry.text["tf_type"], n["tf_t0"], n["tf_t1"], n["tf_t2"], n.get("tf_amplitude", 1.0),
                   n.get("tf_frequency", 0.0), n.get("tf_phase", 0.0), n.get("tf_offset", 0.0),
                   tuple(v.get("tf_times", ())), tuple(v.get("tf_values", ())))


@dataclass(frozen=True)
class SlidingJoint:
    """A point of the slider beam (arc length `at`) kept on the carrier's centre line, free to
    slide along it and to rotate (docs/theory.md, "The sliding joint")."""

    slider: int
    at: float
    carrier: int
    discrete_gradient: str   # 'exact' (conserving across knots) or 'midpoint' (the seed's form)
    at_carrier_end: str      # 'stop' (the run ends, exit 0) or 'fail' (the run fails, exit 1)
    tolerance: float | None  # largest slider-carrier distance at the start (None: 1e-6 L_carrier)
    static: str = "held"     # in the equilibrium start: 'held' (s kept) or 'free' (s slides to equilibrium)
    # 'frame': the constraint in the slider's director frame, e_i . (c(s) - p) = 0 (director
    # sliders, the default: energy, linear and angular momentum exact under energy-momentum);
    # 'spatial': c(s) - p = 0 (ANCF sliders, which have no directors, and the seed's midpoint
    # form discrete_gradient = 'midpoint' by default: angular momentum not exact)
    form: str = "frame"
    # the track: the carriers along s (carrier first), each beginning where the one before ends;
    # () for the carrier alone
    carriers: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        if not self.carriers:
            object.__setattr__(self, "carriers", (self.carrier,))


@dataclass(frozen=True)
class Adapt:
    """[analysis] adapt: steps chosen by their local error (src/time/error_control.hpp)."""

    rtol: float                 # on directions, and atol's default scale
    atol: float | None          # on points and sliding coordinates [m]; None: rtol x the longest beam
    dt_max: float               # no step above it


@dataclass(frozen=True)
class Analysis:
    type: str
    steps: int
    t_end: float
    dt: float | None
    integrator: str
    newmark_beta: float
    newmark_gamma: float
    hht_alpha: float
    dt_min: float | None
    em_dissipation: float = 0.0  # energy-momentum: xi of the energy-decaying variant (0: conserving)
    start: str = "reference"     # dynamic: 'reference' (the scene's geometry) or 'equilibrium' (static first)
    adapt: Adapt | None = None   # dynamic: error-controlled steps (the run then starts at dt / 100)

    @property
    def dt_max_step(self) -> float:
        """The largest step the step control may take: dt, or adapt.dt_max."""
        assert self.dt is not None
        return self.adapt.dt_max if self.adapt is not None else self.dt

    def planned_steps(self, t0: float = 0.0) -> int:
        """Time steps from t0 to t_end: t_end / dt, or under adapt an estimate (20 steps per
        dt_max: the sizes are chosen in the run), for progress lines and output size estimates."""
        assert self.dt is not None
        h = self.dt if self.adapt is None else self.adapt.dt_max / 20
        return max(1, math.ceil((self.t_end - t0) / h - 1e-9))


@dataclass(frozen=True)
class TrackPoint:
    beam: int
    at: float


@dataclass(frozen=True)
class Body:
    """A [[body]]: a rigid body. ``index`` is its place among the core's beams (after every
    [[beam]]); ``inertia`` the inertia tensor J about its centre of mass in its own frame."""

    name: str
    index: int
    mass: float
    inertia: tuple[Vec3, Vec3, Vec3]
    position: Vec3
    frame: tuple[Vec3, Vec3, Vec3]  # d1, d2, d3 in the drawing
    velocity: Vec3
    angular_velocity: Vec3

    @property
    def euler(self) -> list[float]:
        """E = int X X^T dm = tr(J)/2 I - J, row-major: the body's director inertia."""
        J = np.array(self.inertia)
        return (0.5 * np.trace(J) * np.eye(3) - J).ravel().tolist()

    def q_ref(self) -> list[float]:
        return [*self.position, *(v for d in self.frame for v in d)]


@dataclass(frozen=True)
class Output:
    every: int  # steps between records (dynamic; default: default_every)
    track: tuple[TrackPoint, ...]
    samples_per_span: int
    checkpoint_every: int = 0  # steps between checkpoints (0: only when the run ends)
    xdmf: bool = True          # write beams.xdmf/sliders.xdmf/masses.xdmf
    warn_size_gb: float = 1.0  # warn before a run whose output is estimated larger (0: never)
    interval: float = 0.0      # dynamic: seconds between records, instead of every (0: by steps)

    def records(self, steps: int | float, span: float) -> float:
        """About how many records a dynamic run of `steps` steps over `span` seconds writes
        (besides its first and last)."""
        return span / self.interval if self.interval > 0 else steps / max(1, self.every)


@dataclass(frozen=True)
class Scene:
    """A validated scene (``load_scene``, ``scene_from_dict``): the TOML file's tables as typed,
    checked values with every default filled in (``analysis``, ``beams``, ``output``, the effect
    tables in ``effects``), plus the file it came from and the raw data."""

    name: str
    description: str
    file: str
    base_dir: str
    analysis: Analysis
    beams: tuple[Beam, ...]
    petsc_options: dict[str, str]
    petsc_options_file: str | None
    output: Output
    # the scene as read, overrides applied (what a checkpoint keeps, to restart the same run)
    data: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)
    overrides: tuple[str, ...] = ()  # the --set overrides applied to the file, in order
    # what is allowed but probably not meant (a support that repeats another): for the user to read
    warnings: tuple[str, ...] = ()
    # the entries of the effect tables the core's registry declares ([[support]], [gravity],
    # [[damping]], ...), tables in file order
    effects: tuple[EffectEntry, ...] = ()
    bodies: tuple[Body, ...] = ()  # [[body]], in file order

    def entries(self, table: str) -> tuple[EffectEntry, ...]:
        """The entries of one table, in file order."""
        return tuple(e for e in self.effects if e.table == table)

    @functools.cached_property
    def sliding_joints(self) -> tuple[SlidingJoint, ...]:
        """The [[sliding_joint]] entries, whose run control (the carrier's end, the equilibrium
        start, output per joint) the Python layer does."""
        out = []
        for e in self.entries("sliding_joint"):
            slider = int(e.num["slider"])
            gradient = e.text["discrete_gradient"]
            default_form = "spatial" if self.beams[slider].formulation == "ancf" or gradient == "midpoint" else "frame"
            carriers = tuple(int(b) for b in e.vec.get("carrier_track", [e.num["carrier"]]))
            out.append(SlidingJoint(slider, e.num["slider_s"], carriers[0], gradient, e.text["at_carrier_end"],
                                    e.num.get("tolerance"), e.text["static"], e.text.get("form", default_form),
                                    carriers))
        return tuple(out)

    @functools.cached_property
    def sliding_joint_labels(self) -> tuple[str, ...]:
        """Each sliding joint's name in the output: <slider>_on_<carrier>, numbered when repeated."""
        names = [f"{self.beams[j.slider].name}_on_{self.beams[j.carrier].name}" for j in self.sliding_joints]
        return tuple(n if names.count(n) == 1 else f"{n}_{i + 1}" for i, n in enumerate(names))

    @functools.cached_property
    def supports(self) -> tuple[Support, ...]:
        """The [[support]] entries (type: the entry's variant)."""
        return _supports(self.effects)

    def body_at(self, index: int) -> Body | None:
        """The [[body]] at a core index (bodies come after the beams), or None for a beam."""
        return self.bodies[index - len(self.beams)] if index >= len(self.beams) else None

    def beam_index(self, name: str) -> int:
        for beam in self.beams:
            if beam.name == name:
                return beam.index
        raise SceneError(
            f"beam '{name}' does not exist (beams: {', '.join(b.name for b in self.beams)})",
            file=self.file,
        )


# ----------------------------------------------------------------------------
# small vector helpers


def _vec(a: Any) -> Vec3:
    return (float(a[0]), float(a[1]), float(a[2]))


def _rotate(v: np.ndarray, n: np.ndarray, phi: float) -> np.ndarray:
    """Rodrigues rotation of v about unit axis n by phi."""
    return v * math.cos(phi) + np.cross(n, v) * math.sin(phi) + n * np.dot(n, v) * (1 - math.cos(phi))


def _coincident(a: np.ndarray, b: np.ndarray) -> bool:
    scale = max(float(np.linalg.norm(a)), float(np.linalg.norm(b)))
    return float(np.linalg.norm(b - a)) <= 1e-12 * scale


# ----------------------------------------------------------------------------
# typed access to one table


class _Table:
    """A raw dict plus where it came from, with typed getters."""

    def __init__(self, data: Any, file: str, label: str, parent_key: str | None = None) -> None:
        self.file = file
        self.label = label
        if not isinstance(data, dict):
            raise SceneError(f"must be a table, got {_type_name(data)}", file, label, parent_key)
        self.data: dict[str, Any] = data

    def error(self, key: str | None, message: str) -> SceneError:
        return SceneError(message, self.file, self.label, key)

    def check_keys(self, allowed: list[str] | tuple[str, ...]) -> None:
        for key in self.data:
            if key not in allowed:
                raise self.error(key, _unknown_key_message(key, allowed, self.label))

    def has(self, key: str) -> bool:
        return key in self.data

    def raw(self, key: str, default: Any = _MISSING) -> Any:
        if key in self.data:
            return self.data[key]
        if default is _MISSING:
            raise self.error(key, "missing required key")
        return default

    def sub(self, key: str, label: str) -> _Table:
        return _Table(self.raw(key), self.file, label, key)

    def string(self, key: str, default: Any = _MISSING) -> str:
        value = self.raw(key, default)
        if not isinstance(value, str):
            raise self.error(key, f"must be a string, got {_show(value)}")
        return value

    def choice(self, key: str, options: tuple[str, ...], default: Any = _MISSING) -> str:
        value = self.string(key, default)
        if value not in options:
            hint = _did_you_mean(value, options)
            raise self.error(key, f"must be one of {_quoted(options)}, got '{value}'{hint}")
        return value

    def integer(self, key: str, default: Any = _MISSING, positive: bool = True) -> int:
        value = self.raw(key, default)
        # bool is an int subclass in Python; a TOML true is never a count
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(key, f"must be an integer, got {_show(value)}")
        if positive and value <= 0:
            raise self.error(key, f"must be a positive integer, got {value}")
        return value

    def number(
        self,
        key: str,
        default: Any = _MISSING,
        check: Callable[[float], bool] | None = None,
        requirement: str = "",
        allow_inf: bool = False,
    ) -> float:
        value = self.raw(key, default)
        if value is None:  # only reachable through a None default
            return value
        x = self._to_float(key, value, allow_inf)
        if check is not None and not check(x):
            raise self.error(key, f"must be {requirement}, got {_show(value)}")
        return x

    def _to_float(self, key: str, value: Any, allow_inf: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(key, f"must be a number, got {_show(value)}")
        x = float(value)
        if math.isnan(x) or (math.isinf(x) and not (allow_inf and x > 0)):
            raise self.error(key, f"must be a finite number, got {_show(value)}")
        return x

    def vec3(self, key: str, default: Any = _MISSING) -> Vec3:
        return self.vec3_value(key, self.raw(key, default))

    def vec3_value(self, key: str, value: Any) -> Vec3:
        if not isinstance(value, list) or len(value) != 3:
            raise self.error(key, f"must be an array of 3 numbers, got {_show(value)}")
        return tuple(self._to_float(key, v) for v in value)  # type: ignore[return-value]


_TYPE_NAMES = ((bool, "a boolean"), (int, "an integer"), (float, "a float"), (str, "a string"), (list, "an array"),
               (dict, "a table"))  # bool before int: a bool is an int


def _type_name(value: Any) -> str:
    return next((name for kind, name in _TYPE_NAMES if isinstance(value, kind)), type(value).__name__)


def _show(value: Any) -> str:
    if isinstance(value, (dict, list)):
        return _type_name(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f"{_type_name(value)} {value!r}"
    return f"{_type_name(value)} {value!r}"


def _quoted(options: tuple[str, ...] | list[str]) -> str:
    return ", ".join(f"'{o}'" for o in options)


def _did_you_mean(word: str, options: tuple[str, ...] | list[str]) -> str:
    close = difflib.get_close_matches(word, list(options), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


# keys a table read in an earlier version, with what to do instead: the error says so, not only
# "unknown"
_RETIRED_KEYS = {
    ("[[friction]]", "regularization"): "friction sticks now (Coulomb's law with stick, nothing to tune): "
                                        "remove the key",
}


def _unknown_key_message(key: str, allowed: tuple[str, ...] | list[str], table: str = "") -> str:
    retired = _RETIRED_KEYS.get((table.split(" ")[0], key))
    if retired:
        return f"'{key}' is no longer read: {retired}"
    hint = _did_you_mean(key, allowed)
    return f"unknown key '{key}'" + (hint or f" (allowed: {_quoted(allowed)})")


def _array_of_tables(data: dict[str, Any], key: str, file: str) -> list[Any]:
    value = data.get(key, [])
    if not isinstance(value, list):
        raise SceneError(f"must be an array of tables [[{key}]], got {_type_name(value)}", file, "top level", key)
    return value


# ----------------------------------------------------------------------------
# schema constants

# tables of the scene's own; effect tables ([[support]], [gravity], ...) come from the core's registry
_TOP_KEYS = ("scene", "analysis", "petsc", "beam", "body", "output")
_BODY_KEYS = ("name", "mass", "inertia", "position", "orientation", "velocity", "angular_velocity")
_SCENE_KEYS = ("name", "description")
_ANALYSIS_KEYS = (
    "type", "steps", "t_end", "dt", "integrator", "newmark_beta", "newmark_gamma", "hht_alpha", "dt_min",
    "em_dissipation", "start", "adapt",
)
_ADAPT_KEYS = ("rtol", "atol", "dt_max")
_INTEGRATORS = ("energy-momentum", "midpoint", "newmark", "hht")
_BEAM_KEYS = (
    "name", "start", "end", "polyline", "arc", "d2", "spans", "quadrature", "strain",
    "formulation", "velocity", "angular_velocity", "rotation_center", "section", "unstretched_length", "pretension",
    "horizontal_tension", "sag",
)
_ARC_KEYS = ("center", "radius", "normal", "start", "angle")
_SHAPE_KEYS = ("shape", "b", "h", "r", "E", "nu", "rho", "k")
_EXPLICIT_KEYS = ("EA", "kGA", "kGA2", "kGA3", "GJ", "EI2", "EI3", "rhoA", "rhoI2", "rhoI3")
# formulation = "ancf" (the gradient-deficient ANCF cable): axial and one bending stiffness, mass
_ANCF_EXPLICIT_KEYS = ("EA", "EI", "rhoA")
_ANCF_SHAPE_KEYS = ("shape", "b", "h", "r", "E", "rho")
# beam keys that describe what a cable does not have (section frame, director strains, B-spline quadrature)
_DIRECTOR_ONLY_BEAM_KEYS = ("d2", "quadrature", "strain")
_SHEAR_FACTOR = {"rectangle": 5.0 / 6.0, "circle": 0.9}
_TF_PARAMS = {"constant": (), "ramp": ("t0", "t1"), "smooth_ramp": ("t0", "t1"), "hat": ("t0", "t1", "t2"), "step": ("t0", "t1"),
              "sine": ("amplitude", "frequency", "phase", "offset", "ramp"), "table": ("times", "values", "file"),
              "spline": ("times", "values", "file")}
# sub-tables an override may create when absent
_OUTPUT_KEYS = ("every", "interval", "track", "samples_per_span", "checkpoint_every", "xdmf", "warn_size_gb")
_TRACK_KEYS = ("beam", "at", "body")
_MOTION_KEYS = ("displacement", "rotation", "time_function")  # rotation: clamps and fixed beams only (6 components)
# every key above is described, with its unit and default, in schema.py (the scene reference;
# tests/python/test_scene_schema.py keeps the two in step)
_CREATABLE = {"scene", "analysis", "petsc", "output", "section", "arc", "time_function"}


def _single_tables() -> set[str]:
    """Registry tables written as one [table] (gravity): an override may create them too."""
    return {table for table, specs in table_specs().items() if specs[0].single}

_ZERO: Vec3 = (0.0, 0.0, 0.0)


# ----------------------------------------------------------------------------
# public entry points


def load_scene(path: str | os.PathLike[str], overrides: list[str] | None = None) -> Scene:
    """Read a TOML scene file, apply overrides as ``slidebeam run --set`` does (``"KEY=VALUE"``
    strings, e.g. ``"beam.0.spans=32"`` or ``"analysis.t_end=2"``), validate, and return the
    :class:`Scene`. Raises SceneError naming the file, table and key at fault."""
    file = os.fspath(path)
    try:
        with open(file, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise SceneError(f"cannot read scene file: {exc.strerror or exc}", file) from exc
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"TOML syntax error: {exc}", file) from exc
    for override in overrides or []:
        apply_override(data, override, file)
    scene = scene_from_dict(data, file=file, base_dir=str(Path(file).resolve().parent))
    return dataclasses.replace(scene, overrides=tuple(overrides or ()))


def scene_from_dict(data: dict[str, Any], file: str = "<dict>", base_dir: str = ".") -> Scene:
    """Validate a scene given as a dict with the layout of the TOML file (tables as dicts,
    arrays of tables as lists of dicts) and return the :class:`Scene`; relative paths in it
    are taken from base_dir. Raises SceneError."""
    top = _Table(data, file, "top level")
    registry_tables = table_specs()
    top.check_keys(_TOP_KEYS + tuple(sorted(registry_tables)))

    meta = _Table(top.raw("scene", {}), file, "[scene]", "scene")
    meta.check_keys(_SCENE_KEYS)
    default_name = Path(file).stem if file != "<dict>" else "scene"

    analysis = _parse_analysis(_Table(top.raw("analysis", {}), file, "[analysis]", "analysis"))
    beams = _parse_beams(_array_of_tables(data, "beam", file), file, _gravity_hint(data))
    if analysis.type == "dynamic":
        for b in beams:
            if not b.section.rhoA > 0:
                raise SceneError(f"a dynamic analysis needs mass: give rho (shape sections) or rhoA > 0 "
                                 f"(explicit resultants)", file, f"[[beam]] #{b.index + 1} ('{b.name}').section",
                                 "rhoA")
    bodies = _parse_bodies(_array_of_tables(data, "body", file), file, beams)
    entries = _with_gravity_for_buoyancy(_parse_effect_tables(data, registry_tables, beams, analysis, file, base_dir,
                                                              bodies), file)
    options, options_file = _parse_petsc(_Table(top.raw("petsc", {}), file, "[petsc]", "petsc"), base_dir)
    output = _parse_output(_Table(top.raw("output", {}), file, "[output]", "output"), beams, analysis, bodies)

    return Scene(
        name=meta.string("name", default_name),
        description=meta.string("description", ""),
        file=file,
        base_dir=base_dir,
        analysis=analysis,
        beams=beams,
        petsc_options=options,
        petsc_options_file=options_file,
        output=output,
        data=copy.deepcopy(data),
        warnings=_support_warnings(entries, beams),
        effects=entries,
        bodies=bodies,
    )


def _with_gravity_for_buoyancy(entries: tuple[EffectEntry, ...], file: str) -> tuple[EffectEntry, ...]:
    """[[buoyancy]] without its own g weighs the water under [gravity]'s."""
    gravity = next((e.vec["g"] for e in entries if e.type == "gravity"), None)
    out = []
    for e in entries:
        if e.type == "buoyancy" and not any(e.vec["g"]):
            if gravity is None or not any(gravity):
                raise SceneError("buoyancy needs gravity: add [gravity] (or give the entry its own g)", file,
                                 e.place, "g")
            e = dataclasses.replace(e, vec={**e.vec, "g": list(gravity)})
        out.append(e)
    return tuple(out)


def _supports(entries: tuple[EffectEntry, ...]) -> tuple[Support, ...]:
    return tuple(Support(e.variant, int(e.num["beam"]), e.num.get("s")) for e in entries if e.table == "support")


def _support_warnings(entries: tuple[EffectEntry, ...], beams: tuple[Beam, ...]) -> tuple[str, ...]:
    """Supports that repeat what another already holds: allowed (the motion is the same), but
    both report the reaction of the point they share, so the reactions count it twice."""
    supports = _supports(entries)
    # fixed holds everything, a clamp what a hinge holds, a hinge a spherical support's point
    holds = {"fixed": 4, "clamp": 3, "revolute": 2, "universal": 2, "spherical": 1}
    out = []
    for j, b in enumerate(supports):
        for i, a in enumerate(supports[:j]):
            if a.beam != b.beam or a.beam >= len(beams):  # (supports on a body hold points of it: not compared)
                continue
            same_point = a.at is None or b.at is None or (
                abs(a.at - b.at) <= 1e-12 * beams[a.beam].geometry.length)
            if not same_point:
                continue
            wider, narrower = (a, b) if holds[a.type] >= holds[b.type] else (b, a)
            where = "" if wider.type == "fixed" else f" at s = {narrower.at:g}"
            out.append(f"[[support]] #{j + 1} ({b.type}) repeats what [[support]] #{i + 1} ({a.type}) holds on beam "
                       f"'{beams[a.beam].name}'{where}: the {narrower.type} adds nothing to the {wider.type}, and "
                       f"both report the reaction there (remove one)")
            break
    return tuple(out)


# ----------------------------------------------------------------------------
# overrides


def apply_override(data: dict[str, Any], override: str, file: str = "<overrides>") -> None:
    """Apply one ``dotted.key=value`` override to a raw scene dict in place."""
    label = f"override '{override}'"
    path_text, sep, value_text = override.partition("=")
    parts = [p.strip() for p in path_text.strip().split(".")]
    if not sep or not all(parts):
        raise SceneError("must look like 'dotted.key=value'", file, label)
    value = _parse_override_value(value_text.strip())

    node: Any = data
    for depth, part in enumerate(parts[:-1]):
        node = _override_step(node, part, depth, file, label)
    _override_set(node, parts[-1], value, file, label)


def _parse_override_value(text: str) -> Any:
    # a TOML value if it parses, else the bare text (so beam.0.quadrature=reduced works)
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def _override_step(node: Any, part: str, depth: int, file: str, label: str) -> Any:
    if isinstance(node, dict):
        if part not in node:
            singles = _single_tables()
            if part not in _CREATABLE | singles or (depth == 0 and part not in _TOP_KEYS + tuple(singles)):
                raise SceneError("unknown path: no such table", file, label, part)
            node[part] = {}
        child = node[part]
        if not isinstance(child, (dict, list)):
            raise SceneError(f"unknown path: '{part}' is not a table", file, label, part)
        return child
    if isinstance(node, list):
        return node[_list_index(node, part, file, label)]
    raise SceneError("unknown path", file, label, part)


def _list_index(node: list[Any], part: str, file: str, label: str) -> int:
    if part.isdigit():
        index = int(part)
        if index >= len(node):
            raise SceneError(f"unknown path: index {index} out of range (have {len(node)})", file, label, part)
        return index
    for index, item in enumerate(node):
        if isinstance(item, dict) and item.get("name") == part:
            return index
    raise SceneError("unknown path: no element with that index or name", file, label, part)


def _override_set(node: Any, part: str, value: Any, file: str, label: str) -> None:
    if isinstance(node, dict):
        node[part] = value
    elif isinstance(node, list):
        node[_list_index(node, part, file, label)] = value
    else:
        raise SceneError("unknown path", file, label, part)


# ----------------------------------------------------------------------------
# [analysis], [petsc], [gravity], [output]


def _parse_analysis(t: _Table) -> Analysis:
    t.check_keys(_ANALYSIS_KEYS)
    kind = t.choice("type", ("static", "dynamic"), "static")
    positive = dict(check=lambda x: x > 0, requirement="> 0")
    dt = t.number("dt", None, **positive)  # type: ignore[arg-type]
    t_end = t.number("t_end", 1.0, **positive)
    adapt = _adapt(t, kind, t_end)
    if adapt is not None and dt is None:
        dt = 1e-4 * t_end
    if kind == "dynamic" and dt is None:
        raise t.error("dt", "missing required key (required when type = \"dynamic\" without adapt)")
    if adapt is not None and dt > adapt.dt_max:
        raise t.error("dt", f"is the first step under adapt: must not exceed adapt.dt_max = {adapt.dt_max}, got {dt}")
    dt_min = t.number("dt_min", None, **positive)  # type: ignore[arg-type]
    if dt_min is None and kind == "dynamic":
        dt_min = dt / 16.0 if adapt is None else 1e-6 * dt
    if dt is not None and dt_min is not None and dt_min > dt:
        raise t.error("dt_min", f"must not exceed dt = {dt}, got {dt_min}")
    integrator = t.choice("integrator", _INTEGRATORS, "energy-momentum")
    # (the schemes' own keys may stay in a scene run with another: --set analysis.integrator switches)
    if kind == "dynamic" and t.has("steps"):
        raise t.error("steps", 'is the load steps of type = "static": a dynamic analysis steps by t_end and dt, '
                               "which say the same; give those")
    alpha = t.number("hht_alpha", -0.1, check=lambda a: -1.0 / 3.0 <= a <= 0.0, requirement="in [-1/3, 0]")
    # Newmark: the trapezoidal rule; HHT: its standard companions, second order and
    # unconditionally stable for linear problems (Hilber, Hughes & Taylor 1977).
    hht = integrator == "hht"
    beta = t.number("newmark_beta", (1.0 - alpha) ** 2 / 4.0 if hht else 0.25, check=lambda b: b > 0,
                    requirement="> 0")
    gamma = t.number("newmark_gamma", 0.5 - alpha if hht else 0.5, check=lambda g: g >= 0.5, requirement=">= 1/2")
    if hht and alpha != 0.0 and gamma < 0.5 - alpha - 1e-12:
        # e.g. the trapezoidal beta = 1/4, gamma = 1/2 kept from a Newmark scene: first order, and
        # with constraints the energy grows until Newton fails
        raise t.error("newmark_gamma", f"HHT with alpha = {alpha:g} needs gamma >= 1/2 - alpha = {0.5 - alpha:g} "
                                       f"(got {gamma:g}); leave newmark_beta and newmark_gamma unset for the "
                                       f"standard companions")
    return Analysis(
        type=kind,
        steps=t.integer("steps", 10),
        t_end=t_end,
        dt=dt,
        integrator=integrator,
        newmark_beta=beta,  # type: ignore[arg-type]
        newmark_gamma=gamma,  # type: ignore[arg-type]
        hht_alpha=alpha,  # type: ignore[arg-type]
        dt_min=dt_min,
        em_dissipation=_em_dissipation(t, integrator),
        start=_start(t, kind),
        adapt=adapt,
    )


def _adapt(t: _Table, kind: str, t_end: float) -> Adapt | None:
    if not t.has("adapt") or t.raw("adapt") is False:  # (false: fixed steps, e.g. --set analysis.adapt=false)
        return None
    if kind != "dynamic":
        raise t.error("adapt", 'applies to type = "dynamic" only')
    a = t.sub("adapt", "[analysis].adapt")
    a.check_keys(_ADAPT_KEYS)
    rtol = a.number("rtol", check=lambda x: 0 < x < 1, requirement="in (0, 1)")
    atol = a.number("atol", None, check=lambda x: x > 0, requirement="> 0")
    dt_max = a.number("dt_max", 0.1 * t_end, check=lambda x: x > 0, requirement="> 0")
    return Adapt(rtol, atol, dt_max)


def _start(t: _Table, kind: str) -> str:
    start = t.choice("start", ("reference", "equilibrium"), "reference")
    if start == "equilibrium" and kind != "dynamic":
        raise t.error("start", 'applies to type = "dynamic" only (a static analysis is an equilibrium already)')
    return start


def _em_dissipation(t: _Table, integrator: str) -> float:
    xi = t.number("em_dissipation", 0.0, check=lambda x: 0.0 <= x <= 1.0, requirement="in [0, 1]")
    if xi > 0 and integrator != "energy-momentum":
        raise t.error("em_dissipation", f"applies to integrator = \"energy-momentum\" only (got \"{integrator}\")")
    return xi


def _parse_petsc(t: _Table, base_dir: str) -> tuple[dict[str, str], str | None]:
    options: dict[str, str] = {}
    options_file: str | None = None
    for key, value in t.data.items():
        if key == "options_file":
            options_file = _resolve_options_file(t, base_dir)
            continue
        if key.startswith("-"):
            raise t.error(key, f"write PETSc options without the leading dash: '{key.lstrip('-')}'")
        if isinstance(value, bool):
            if value:
                options[key] = ""  # a flag; false means leave it out
        elif isinstance(value, str):
            options[key] = value
        elif isinstance(value, int):
            options[key] = str(value)
        elif isinstance(value, float):
            options[key] = repr(t._to_float(key, value))
        else:
            raise t.error(key, f"must be a string, number or boolean, got {_type_name(value)}")
    return options, options_file


def _resolve_options_file(t: _Table, base_dir: str) -> str:
    path = Path(base_dir) / t.string("options_file")
    if not path.is_file():
        raise t.error("options_file", f"file not found: {path}")
    return str(path.resolve())


RECORDS_BY_DEFAULT = 200  # a dynamic run without output.every records at least this many steps


def default_every(analysis: Analysis) -> int:
    """output.every when the scene leaves it out: every step of a static run; about
    RECORDS_BY_DEFAULT records (200 to 399) of a dynamic one, so that the output stays small
    next to the solve however many steps the run takes."""
    if analysis.type != "dynamic" or not analysis.dt or analysis.adapt is not None:
        return 1  # (adapt: the number of steps is not known before the run: default_interval)
    steps = round(analysis.t_end / analysis.dt)
    return max(1, steps // RECORDS_BY_DEFAULT)


def default_interval(analysis: Analysis) -> float:
    """output.interval when the scene gives neither it nor output.every: under adapt, about
    RECORDS_BY_DEFAULT records evenly over the run (the steps are not known before it); else 0
    (records by steps)."""
    if analysis.type != "dynamic" or analysis.adapt is None:
        return 0.0
    return analysis.t_end / RECORDS_BY_DEFAULT


def _parse_output(t: _Table, beams: tuple[Beam, ...], analysis: Analysis, bodies: tuple[Body, ...] = ()) -> Output:
    t.check_keys(_OUTPUT_KEYS)
    xdmf = t.raw("xdmf", True)
    if not isinstance(xdmf, bool):
        raise t.error("xdmf", f"must be true or false, got {_show(xdmf)}")
    if t.has("track"):
        raw = t.raw("track")
        if not isinstance(raw, list):
            raise t.error("track", f"must be an array of tables {{ beam = ..., at = ... }}, got {_type_name(raw)}")
        track = tuple(_parse_track_point(_Table(item, t.file, f"[output].track #{i + 1}", "track"), beams, bodies)
                      for i, item in enumerate(raw))
    else:
        track = tuple(TrackPoint(b.index, b.geometry.length) for b in beams) + tuple(
            TrackPoint(b.index, 0.0) for b in bodies)
    if t.has("interval"):
        if t.has("every"):
            raise t.error("interval", "give every (steps between records) or interval (seconds), not both")
        if analysis.type != "dynamic":
            raise t.error("interval", 'applies to type = "dynamic" only (a static run records by load steps: every)')
        interval = t.number("interval", 0.0, lambda x: x > 0, "a time in s > 0")
    else:
        interval = 0.0 if t.has("every") else default_interval(analysis)
    return Output(
        every=t.integer("every", default_every(analysis)),
        interval=interval,
        track=track,
        samples_per_span=t.integer("samples_per_span", 8),
        checkpoint_every=_non_negative_integer(t, "checkpoint_every"),
        xdmf=xdmf,
        warn_size_gb=t.number("warn_size_gb", 1.0, lambda x: x >= 0, "a size in GB >= 0 (0: never warn)"),
    )


def _non_negative_integer(t: _Table, key: str) -> int:
    value = t.integer(key, 0, positive=False)
    if value < 0:
        raise t.error(key, f"must be 0 (off) or a positive integer, got {value}")
    return value


def _parse_track_point(t: _Table, beams: tuple[Beam, ...], bodies: tuple[Body, ...] = ()) -> TrackPoint:
    t.check_keys(_TRACK_KEYS)
    if t.has("body"):  # its centre of mass
        if t.has("beam") or t.has("at"):
            raise t.error("body", "a tracked body is its centre of mass: give body alone, without beam or at")
        name = t.string("body")
        body = _body_named(bodies, name)
        if body is not None:
            return TrackPoint(body.index, 0.0)
        known = [b.name for b in bodies]
        raise t.error("body", f"body '{name}' does not exist (bodies: {', '.join(known) or 'none'})"
                              f"{_did_you_mean(name, known)}")
    index = _named_beam(t, "beam", beams)
    return TrackPoint(index, _parse_at(t, beams[index].geometry.length))


# ----------------------------------------------------------------------------
# [[beam]]


def _gravity_hint(data: dict[str, Any]) -> np.ndarray | None:
    """[gravity] g when the scene has a usable one (checked later with the rest of [gravity]):
    where a slack rope drawn straight sags, and what a rope given by its sag or horizontal
    tension weighs."""
    g = data.get("gravity", {}).get("g") if isinstance(data.get("gravity"), dict) else None
    if isinstance(g, list) and len(g) == 3 and all(isinstance(v, (int, float)) and math.isfinite(v) for v in g):
        if any(g):
            return np.asarray(g, dtype=float)
    return None


def _parse_bodies(raws: list[Any], file: str, beams: tuple[Beam, ...]) -> tuple[Body, ...]:
    """[[body]]: rigid bodies, numbered after the beams in the core."""
    bodies: list[Body] = []
    for k, raw in enumerate(raws):
        t = _Table(raw, file, f"[[body]] #{k + 1}", "body")
        t.check_keys(_BODY_KEYS)
        name = t.string("name")
        if not name:
            raise t.error("name", "must be a non-empty string")
        for other in [*beams, *bodies]:
            if other.name == name:
                raise t.error("name", f"duplicate name '{name}' (a [[beam]] or [[body]] has it already)")
        mass = t.number("mass", check=lambda v: v > 0, requirement="> 0 kg")
        values = t.raw("inertia")
        if not (isinstance(values, list) and len(values) in (3, 6)):
            raise t.error("inertia", f"must be [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Iyz, Izx] (kg m^2, about the "
                                     f"centre of mass, in the body's axes), got {_show(values)}")
        I = [t._to_float("inertia", v) for v in values] + [0.0] * (6 - len(values))
        J = np.array([[I[0], I[3], I[5]], [I[3], I[1], I[4]], [I[5], I[4], I[2]]])
        E = 0.5 * np.trace(J) * np.eye(3) - J  # int X X^T dm: positive semi-definite for a real body
        scale = max(abs(x) for x in I) or 1.0
        if np.linalg.eigvalsh(J).min() <= 0 or np.linalg.eigvalsh(E).min() < -1e-12 * scale:
            raise t.error("inertia", f"is not a body's inertia: positive moments that meet the triangle inequality "
                                     f"(Ixx <= Iyy + Izz, ...) are needed, got {_show(values)}")
        turn = np.asarray(t.vec3("orientation", list(_ZERO)))
        angle = float(np.linalg.norm(turn))
        axis = turn / angle if angle > 0.0 else turn
        frame = tuple(_vec(_rotate(e, axis, angle)) for e in np.eye(3))
        bodies.append(Body(name, len(beams) + k, mass, tuple(tuple(float(v) for v in row) for row in J),
                           t.vec3("position"), frame, t.vec3("velocity", list(_ZERO)),
                           t.vec3("angular_velocity", list(_ZERO))))
    return tuple(bodies)


def _parse_beams(raws: list[Any], file: str, gravity: np.ndarray | None = None) -> tuple[Beam, ...]:
    if not raws:
        raise SceneError("at least one [[beam]] is required", file, "top level", "beam")
    beams: list[Beam] = []
    for index, raw in enumerate(raws):
        t = _Table(raw, file, f"[[beam]] #{index + 1}", "beam")
        beam = _parse_beam(t, index, gravity)
        for other in beams:
            if other.name == beam.name:
                raise t.error("name", f"duplicate beam name '{beam.name}' (also [[beam]] #{other.index + 1})")
        beams.append(beam)
    return tuple(beams)


def _parse_beam(t: _Table, index: int, gravity: np.ndarray | None) -> Beam:
    name = t.string("name")
    if not name.strip():
        raise t.error("name", "must be a non-empty string")
    t.label = f"{t.label} ('{name}')"
    t.check_keys(_BEAM_KEYS)
    geometry = _parse_geometry(t)
    if not t.has("section"):
        raise t.error("section", "missing required table [beam.section]")
    formulation = t.choice("formulation", ("director", "ancf"), "director")
    if formulation == "ancf":
        return _parse_ancf_beam(t, index, name, geometry, gravity)
    section = _parse_section(t.sub("section", f"{t.label}.section"))
    spans = t.integer("spans")
    quadrature = t.choice("quadrature", ("auto", "full", "reduced", "assumed_strain"), "auto")
    if quadrature == "auto":
        quadrature = auto_quadrature(section, geometry.length / max(spans, 1))
    strain = t.choice("strain", ("simo-reissner", "seed"), "simo-reissner")
    unstretched, geometry = _parse_rope(t, geometry, section, strain, quadrature, gravity)
    return Beam(
        name=name,
        index=index,
        geometry=geometry,
        d2=_parse_d2(t, geometry),
        spans=spans,
        quadrature=quadrature,
        strain=strain,
        formulation=formulation,
        section=section,
        velocity=t.vec3("velocity", list(_ZERO)),
        angular_velocity=t.vec3("angular_velocity", list(_ZERO)),
        rotation_center=t.vec3("rotation_center") if t.has("rotation_center") else None,
        unstretched_length=unstretched,
    )


_DOWN = np.array([0.0, 0.0, -1.0])
_ROPE_KEYS = ("unstretched_length", "pretension", "horizontal_tension", "sag")


def _parse_unstretched_length(t: _Table, geometry: Geometry, section: Section, strain: str, quadrature: str,
                              gravity: np.ndarray | None) -> float:
    """A rope given by its length at rest (``unstretched_length``), its tension where drawn
    (``pretension``), or as it hangs under [gravity] between the ends of its straight drawing: by
    its horizontal tension or its mid-span sag (the elastic catenary's). Its unstretched length,
    0 when none of them is given."""
    given = [k for k in _ROPE_KEYS if t.has(k)]
    if not given:
        return 0.0
    if len(given) > 1:
        raise t.error(given[1], f"give one of {', '.join(_ROPE_KEYS)}, not {' and '.join(given)} (one fixes the others)")
    key = given[0]
    if strain != "simo-reissner":
        raise t.error(key, "needs strain = \"simo-reissner\" (the seed measure is not linear in the stretch)")
    value = t.number(key)
    if key == "unstretched_length":
        if not (value > 0.0 and math.isfinite(value)):
            raise t.error(key, f"must be a length > 0, got {_show(value)}")
        return value
    if key == "pretension":
        if not (math.isfinite(value) and 0.0 <= value < section.EA):
            raise t.error(key, f"must be a tension >= 0 and below EA = {section.EA:g} N, got {_show(value)}")
        return geometry.length / stretch_at_tension(value / section.EA, quadrature == "assumed_strain")
    if not (value > 0.0 and math.isfinite(value)):
        raise t.error(key, f"must be > 0, got {_show(value)}")
    if geometry.kind != "line":
        raise t.error(key, "needs a straight drawing (start + end): the rope hangs between its ends")
    if gravity is None or not section.rhoA > 0.0:
        raise t.error(key, "a rope hangs by its weight: needs [gravity] and a section with mass (rho or rhoA)")
    up = -gravity / np.linalg.norm(gravity)
    chord = np.subtract(geometry.points[-1], geometry.points[0])
    rise = float(chord @ up)
    span = float(np.linalg.norm(chord - rise * up))
    if span < 1e-9 * geometry.length:
        raise t.error(key, "the rope's ends are one above the other: it does not sag")
    from .catenary import unstretched_length_at

    w = section.rhoA * float(np.linalg.norm(gravity))
    try:
        return unstretched_length_at(span, rise, section.EA, w, **({"H": value} if key == "horizontal_tension"
                                                                    else {"sag": value}))
    except (ValueError, np.linalg.LinAlgError, OverflowError) as err:
        raise t.error(key, f"no hanging rope has this {key.replace('_', ' ')} between these ends ({err})") from None


def _parse_rope(t: _Table, geometry: Geometry, section: Section, strain: str, quadrature: str,
                gravity: np.ndarray | None) -> tuple[float, Geometry]:
    """The beam's unstretched length (0: the drawing is stress free) and where it starts: a rope
    drawn straight but longer than its chord starts as the arc of its length sagging along gravity
    (drawn straight it would be a compressed strut)."""
    unstretched = _parse_unstretched_length(t, geometry, section, strain, quadrature, gravity)
    if geometry.kind == "line" and unstretched > geometry.length:
        geometry = sagging_arc(geometry, unstretched, _DOWN if gravity is None else gravity)
    return unstretched, geometry


def stretch_at_tension(tension_over_EA: float, centre_line_axial: bool) -> float:
    """The stretch lambda (drawn over unstretched length) at which a straight rope carries the
    tension T = tension_over_EA EA in the element's own law: T = EA (lambda - 1) for the strain
    d1 . phi' - 1, T = EA lambda (lambda^2 - 1) / 2 for the centre line's 1/2 (phi'.phi' - 1) of
    assumed strains (its force along the stretched tangent)."""
    lam = 1.0 + tension_over_EA
    if not centre_line_axial:
        return lam
    for _ in range(60):  # Newton on lam^3 - lam - 2 T / EA, from the linear law's lambda
        step = (lam**3 - lam - 2.0 * tension_over_EA) / (3.0 * lam**2 - 1.0)
        lam -= step
        if abs(step) <= 1e-16 * lam:
            break
    return lam


# Span slenderness EA h^2 / EI from which quadrature = "auto" takes assumed strains.
AUTO_SLENDERNESS = 300.0


def span_slenderness(section: Section, span_length: float) -> float:
    """max(EA, kGA) h^2 / EI of a director beam's knot span h: how strongly full quadrature locks
    (its membrane and shear strains, sampled at three points a span, stiffen bending by about
    this factor)."""
    return max(section.EA, min(section.kGA2, section.kGA3)) * span_length**2 / min(section.EI2, section.EI3)


def auto_quadrature(section: Section, span_length: float) -> str:
    """quadrature = "auto": assumed strains on slender spans (span_slenderness >= 300: ropes,
    cables, hangers, wires, slender rods and booms, where full quadrature locks: 0.9 % on a
    clamped wire's deflection at 400, 10 % on a cantilever elastica at 1.6e3, 16 % on a hanging
    rope's tension at 4.6e4), full quadrature on stocky ones (where it locks little and assumed
    strains are softer on coarse, strongly bent meshes); docs/theory.md, "Where assumed strains
    lose, and the default"."""
    return "assumed_strain" if span_slenderness(section, span_length) >= AUTO_SLENDERNESS else "full"


def _parse_ancf_beam(t: _Table, index: int, name: str, geometry: Geometry, gravity: np.ndarray | None) -> Beam:
    """A [[beam]] with formulation = "ancf": the gradient-deficient ANCF cable, `spans` equal
    elements (spans + 1 nodes with r and r'), stress free when straight: drawn straight, or drawn
    as an arc with its unstretched length given."""
    for key in _DIRECTOR_ONLY_BEAM_KEYS:
        if t.has(key):
            raise t.error(key, f"not used by formulation = 'ancf' (the cable has no section frame, director "
                               f"strains or B-spline quadrature); remove '{key}' or use formulation = 'director'")
    section = _parse_ancf_section(t.sub("section", f"{t.label}.section"))
    # the cable's axial strain is the centre line's 1/2 (r'.r' - 1): its law is the assumed strains'
    unstretched, geometry = _parse_rope(t, geometry, section, "simo-reissner", "assumed_strain", gravity)
    if geometry.kind in ("polyline", "arc") and not unstretched:
        raise t.error(geometry.kind, "formulation = 'ancf' needs a straight stress-free state: draw it straight "
                                     "('start' + 'end'), or give unstretched_length or pretension, with which "
                                     "an arc or a polyline is only where the cable starts (its bending energy "
                                     "|r'' - r0''|^2 is frame-indifferent only for a straight stress-free state)")
    return Beam(
        name=name,
        index=index,
        geometry=geometry,
        d2=None,
        spans=t.integer("spans"),
        quadrature="full",
        strain="green-cable",
        formulation="ancf",
        section=section,
        velocity=t.vec3("velocity", list(_ZERO)),
        angular_velocity=t.vec3("angular_velocity", list(_ZERO)),
        rotation_center=t.vec3("rotation_center") if t.has("rotation_center") else None,
        unstretched_length=unstretched,
    )


def _parse_ancf_section(t: _Table) -> Section:
    """Section of an ANCF cable: EA, one bending stiffness EI and rhoA, explicit or from a shape
    with equal bending stiffness about every axis (circle, square). Shear, torsion and rotary
    inertia do not exist in the cable, so their keys are errors rather than silently ignored."""
    for key in _SHAPE_KEYS + _EXPLICIT_KEYS:
        if t.has(key) and key not in _ANCF_SHAPE_KEYS + _ANCF_EXPLICIT_KEYS:
            raise t.error(key, f"not used by formulation = 'ancf' (the cable has no shear, torsion or rotary "
                               f"inertia); give {_quoted(_ANCF_EXPLICIT_KEYS)} or a shape with "
                               f"{_quoted(_ANCF_SHAPE_KEYS)}")
    shape_keys, explicit_keys = _shape_or_explicit(t, _ANCF_SHAPE_KEYS, _ANCF_EXPLICIT_KEYS)
    if explicit_keys:
        EA = t.number("EA", check=lambda x: x > 0, requirement="> 0")
        EI = t.number("EI", check=lambda x: x > 0, requirement="> 0")
        rhoA = t.number("rhoA", 0.0, check=lambda x: x >= 0, requirement=">= 0")
    else:
        if not shape_keys:
            raise t.error("shape", "section needs either 'shape' (+ E, rho) or explicit EA, EI, rhoA")
        shape, size = _shape_dimensions(t)
        if shape == "rectangle" and size[0] != size[1]:
            raise t.error("h", f"the ANCF cable has one bending stiffness: a rectangle needs b == h, got "
                               f"b = {size[0]}, h = {size[1]}")
        area, i2, _, _ = rectangle_properties(*size) if shape == "rectangle" else circle_properties(*size)
        E = t.number("E", check=lambda x: x > 0, requirement="> 0")
        rho = t.number("rho", 0.0, check=lambda x: x >= 0, requirement=">= 0")
        EA, EI, rhoA = E * area, E * i2, rho * area
    # EI2 = EI3 = EI; the director-only resultants are zero (never read for a cable)
    return Section(EA=EA, kGA2=0.0, kGA3=0.0, GJ=0.0, EI2=EI, EI3=EI, rhoA=rhoA, rhoI2=0.0, rhoI3=0.0)


def _parse_geometry(t: _Table) -> Geometry:
    kinds = [k for k, keys in (("line", ("start", "end")), ("polyline", ("polyline",)), ("arc", ("arc",)))
             if any(t.has(key) for key in keys)]
    if not kinds:
        raise t.error(None, "missing geometry: give exactly one of 'start' + 'end', 'polyline' or 'arc'")
    if len(kinds) > 1:
        raise t.error(kinds[1], f"geometry given twice ({' and '.join(kinds)}); "
                              "give exactly one of 'start' + 'end', 'polyline' or 'arc'")
    if kinds[0] == "line":
        return _parse_line(t)
    if kinds[0] == "polyline":
        return _parse_polyline(t)
    return _parse_arc(t.sub("arc", f"{t.label}.arc"))


def _parse_line(t: _Table) -> Geometry:
    for key, other in (("start", "end"), ("end", "start")):
        if not t.has(key):
            raise t.error(key, f"missing required key ('{other}' needs both 'start' and 'end')")
    a, b = t.vec3("start"), t.vec3("end")
    if _coincident(np.asarray(a), np.asarray(b)):
        raise t.error("end", "start and end coincide (zero length beam)")
    length = float(np.linalg.norm(np.subtract(b, a)))
    return Geometry("line", (a, b), None, None, None, None, None, length)


def _parse_polyline(t: _Table) -> Geometry:
    raw = t.raw("polyline")
    if not isinstance(raw, list) or len(raw) < 2:
        raise t.error("polyline", f"must be an array of at least 2 points, got {_show(raw)}")
    points = tuple(t.vec3_value("polyline", p) for p in raw)
    length = 0.0
    for i, (a, b) in enumerate(zip(points[:-1], points[1:])):
        if _coincident(np.asarray(a), np.asarray(b)):
            raise t.error("polyline", f"points {i + 1} and {i + 2} coincide (zero length segment)")
        length += float(np.linalg.norm(np.subtract(b, a)))
    return Geometry("polyline", points, None, None, None, None, None, length)


def _parse_arc(t: _Table) -> Geometry:
    t.check_keys(_ARC_KEYS)
    center, start = t.vec3("center"), t.vec3("start")
    radius = t.number("radius", check=lambda r: r > 0, requirement="> 0")
    angle = t.number("angle", check=lambda a: a != 0 and abs(a) <= 360,
                     requirement="nonzero with |angle| <= 360 (degrees)")
    n = np.asarray(t.vec3("normal"))
    if float(np.linalg.norm(n)) == 0.0:
        raise t.error("normal", "must be a nonzero vector")
    n = n / np.linalg.norm(n)
    arm = np.subtract(start, center)
    distance = float(np.linalg.norm(arm))
    if abs(distance - radius) > 1e-9 * radius:
        raise t.error("start", f"must lie at distance radius = {radius} from center, got {distance}")
    if abs(float(np.dot(arm, n))) > 1e-9 * radius:
        raise t.error("start", "must lie in the plane through center normal to 'normal'")
    return Geometry("arc", (), center, radius, _vec(n), start, angle, radius * math.radians(abs(angle)))


def sagging_arc(line: Geometry, length: float, sag: np.ndarray) -> Geometry:
    """A circular arc of ``length`` on the chord of ``line``, bulging along ``sag`` made normal to
    the chord (another normal where sag is along it): where a slack rope given by its unstretched
    length starts. Drawn straight, it would start as a strut in compression, from which Newton
    and the equilibrium start find the inverted catenary (an arch), not the hanging rope."""
    a, b = (np.asarray(p, dtype=float) for p in (line.points[0], line.points[-1]))
    chord = b - a
    d = float(np.linalg.norm(chord))
    c = chord / d
    down = sag - np.dot(sag, c) * c
    if float(np.linalg.norm(down)) < 1e-6 * float(np.linalg.norm(sag)):  # sag along the chord
        down = np.cross(c, np.eye(3)[int(np.argmin(np.abs(c)))])
    down /= np.linalg.norm(down)
    # sin(x) / x = d / length for x the half angle, by Newton from the small-sag series
    ratio = d / length
    x = math.sqrt(6.0 * (1.0 - ratio))
    for _ in range(50):
        f, df = math.sin(x) - ratio * x, math.cos(x) - ratio
        x_new = min(max(x - f / df, 1e-12), math.pi)
        if abs(x_new - x) < 1e-15:
            break
        x = x_new
    radius = length / (2.0 * x)
    center = 0.5 * (a + b) - down * radius * math.cos(x)
    normal = np.cross(a - center, c)
    normal /= np.linalg.norm(normal)
    angle = math.degrees(2.0 * x)
    arc = Geometry("arc", (), _vec(center), radius, _vec(normal), _vec(a), angle, length)
    if not np.allclose(arc.point_at(length), b, atol=1e-9 * length):
        arc = dataclasses.replace(arc, angle_deg=-angle)
    return arc


def _parse_d2(t: _Table, geometry: Geometry) -> Vec3 | None:
    if not t.has("d2"):
        return None
    d2 = np.asarray(t.vec3("d2"))
    norm = float(np.linalg.norm(d2))
    if norm == 0.0:
        raise t.error("d2", "must be a nonzero vector")
    cos = float(np.dot(d2 / norm, geometry.tangent_at_start()))
    if abs(cos) >= 1.0 - 1e-8:
        raise t.error("d2", "must not be parallel to the beam axis at its start")
    return _vec(d2 / norm)


# ----------------------------------------------------------------------------
# [beam.section]


def _shape_or_explicit(t: _Table, shapes: tuple[str, ...], explicit: tuple[str, ...]) -> tuple[list[str], list[str]]:
    """The section's shape-based and explicit keys present (only known keys, not both kinds)."""
    t.check_keys(shapes + explicit)
    shape_keys = [k for k in shapes if t.has(k)]
    explicit_keys = [k for k in explicit if t.has(k)]
    if shape_keys and explicit_keys:
        raise t.error(explicit_keys[0], "explicit resultants cannot be mixed with shape-based keys "
                                        f"({', '.join(shape_keys)}); give one or the other")
    return shape_keys, explicit_keys


def _parse_section(t: _Table) -> Section:
    if t.has("EI"):
        raise t.error("EI", "EI (one bending stiffness) is for formulation = 'ancf'; a director beam needs "
                            "EI2 and EI3")
    shape_keys, explicit_keys = _shape_or_explicit(t, _SHAPE_KEYS, _EXPLICIT_KEYS)
    if explicit_keys:
        return _explicit_section(t)
    if not shape_keys:
        raise t.error("shape", "section needs either 'shape' (+ E, nu, ...) or explicit resultants (EA, kGA, GJ, ...)")
    return _shape_section(t)


def _explicit_section(t: _Table) -> Section:
    positive = dict(check=lambda x: x > 0, requirement="> 0")
    non_negative = dict(check=lambda x: x >= 0, requirement=">= 0")
    per_axis = t.has("kGA2") and t.has("kGA3")
    if per_axis and t.has("kGA"):
        raise t.error("kGA", "given with both kGA2 and kGA3, which say the same: give kGA (both axes) or "
                             "kGA2 and kGA3")
    kGA = t.number("kGA", None if per_axis else _MISSING, **positive)  # type: ignore[arg-type]
    return Section(
        EA=t.number("EA", **positive),  # type: ignore[arg-type]
        kGA2=t.number("kGA2", kGA, **positive),  # type: ignore[arg-type]
        kGA3=t.number("kGA3", kGA, **positive),  # type: ignore[arg-type]
        GJ=t.number("GJ", **positive),  # type: ignore[arg-type]
        EI2=t.number("EI2", **positive),  # type: ignore[arg-type]
        EI3=t.number("EI3", **positive),  # type: ignore[arg-type]
        rhoA=t.number("rhoA", 0.0, **non_negative),  # type: ignore[arg-type]
        rhoI2=t.number("rhoI2", 0.0, **non_negative),  # type: ignore[arg-type]
        rhoI3=t.number("rhoI3", 0.0, **non_negative),  # type: ignore[arg-type]
    )


def _shape_dimensions(t: _Table) -> tuple[str, list[float]]:
    """The section's shape and its dimensions (b, h or r), other dimensions refused."""
    shape = t.choice("shape", ("rectangle", "circle"))
    dims = ("b", "h") if shape == "rectangle" else ("r",)
    for key in ("b", "h", "r"):
        if key not in dims and t.has(key):
            raise t.error(key, f"not allowed for shape '{shape}' (needs {_quoted(dims)})")
    return shape, [t.number(k, check=lambda x: x > 0, requirement="> 0") for k in dims]


def _shape_section(t: _Table) -> Section:
    shape, size = _shape_dimensions(t)
    area, i2, i3, j = (rectangle_properties(*size) if shape == "rectangle" else circle_properties(*size))
    E = t.number("E", check=lambda x: x > 0, requirement="> 0")
    nu = t.number("nu", check=lambda x: -1.0 < x < 0.5, requirement="in (-1, 0.5)")
    rho = t.number("rho", 0.0, check=lambda x: x >= 0, requirement=">= 0")
    k = t.number("k", _SHEAR_FACTOR[shape], check=lambda x: x > 0, requirement="> 0")
    G = E / (2.0 * (1.0 + nu))
    return Section(
        EA=E * area, kGA2=k * G * area, kGA3=k * G * area, GJ=G * j,
        EI2=E * i2, EI3=E * i3, rhoA=rho * area, rhoI2=rho * i2, rhoI3=rho * i3,
    )


def rectangle_properties(b: float, h: float) -> tuple[float, float, float, float]:
    """(A, I2, I3, J) of a b x h rectangle; b along d2, h along d3; J after Roark."""
    a, c = max(b, h), min(b, h)
    j = a * c**3 * (1.0 / 3.0 - 0.21 * (c / a) * (1.0 - c**4 / (12.0 * a**4)))
    return b * h, b * h**3 / 12.0, h * b**3 / 12.0, j


def circle_properties(r: float) -> tuple[float, float, float, float]:
    """(A, I2, I3, J) of a solid circle of radius r."""
    return math.pi * r**2, math.pi * r**4 / 4.0, math.pi * r**4 / 4.0, math.pi * r**4 / 2.0


# ----------------------------------------------------------------------------
# beam points ([output] track, effect tables)


def _parse_at(t: _Table, length: float, key: str = "at", value: Any = _MISSING) -> float:
    """'start' | 'end' | arc length in [0, L] -> arc length s."""
    if value is _MISSING:
        value = t.raw(key)
    if isinstance(value, str):
        if value not in ("start", "end"):
            raise t.error(key, f"must be 'start', 'end' or an arc length in [0, {length}], got '{value}'")
        return 0.0 if value == "start" else length
    s = t._to_float(key, value)
    slack = 1e-12 * length  # round-off from users typing L by hand
    if not -slack <= s <= length + slack:
        raise t.error(key, f"must be in [0, L] with L = {length!r} (reference length), got {value!r}")
    return min(max(s, 0.0), length)


def _snap_to_end(t: _Table, s: float, length: float, key: str = "at") -> float:
    tol = 1e-12 * length
    if abs(s) <= tol:
        return 0.0
    if abs(s - length) <= tol:
        return length
    raise t.error(key, f"must be 'start' or 'end' (s = 0 or L = {length!r}), got {s!r}")


def _parse_time_function(t: _Table, base_dir: str = ".") -> TimeFunction:
    kind = t.choice("type", tuple(_TF_PARAMS))
    t.check_keys(("type",) + _TF_PARAMS[kind])
    if kind == "sine":
        ramp = t.number("ramp", 0.0, check=lambda r: r >= 0, requirement=">= 0 (s)")
        return TimeFunction(kind, t1=ramp if ramp > 0 else math.inf, amplitude=t.number("amplitude", 1.0),
                            frequency=t.number("frequency", check=lambda f: f > 0, requirement="> 0 (Hz)"),
                            phase=t.number("phase", 0.0), offset=t.number("offset", 0.0))
    if kind in ("table", "spline"):
        times, values = _time_table(t, base_dir)
        return TimeFunction(kind, times=times, values=values)
    t0 = t.number("t0", 0.0)
    if kind == "constant":
        return TimeFunction(kind)
    if kind == "step":
        t1 = t.number("t1", math.inf, allow_inf=True)
    else:
        t1 = t.number("t1")
    if not t1 > t0:
        raise t.error("t1", f"must be > t0 = {t0}, got {t1}")
    if kind != "hat":
        return TimeFunction(kind, t0, t1, math.inf)
    t2 = t.number("t2")
    if not t2 > t1:
        raise t.error("t2", f"must be > t1 = {t1}, got {t2}")
    return TimeFunction(kind, t0, t1, t2)


def _csv_number(cell: str) -> float | None:
    try:
        return float(cell)
    except ValueError:
        return None


def _time_table(t: _Table, base_dir: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """(times, values) of a table time function: inline arrays, or a CSV file (relative to the
    scene) of two columns t,value (an optional header line, '#' comments and blank lines allowed)."""
    if t.has("file"):
        if t.has("times") or t.has("values"):
            raise t.error("file", "give either file or times and values, not both")
        path = Path(base_dir) / t.string("file")
        try:
            text = path.read_text()
        except OSError as exc:
            raise t.error("file", f"cannot read {path}: {exc.strerror or exc}") from exc
        times: list[float] = []
        values: list[float] = []
        rows = [(n, line.split("#")[0].strip()) for n, line in enumerate(text.splitlines(), 1)]
        rows = [(n, line) for n, line in rows if line]
        for k, (n, line) in enumerate(rows):
            cells = [c.strip() for c in line.split(",")]
            numbers = [_csv_number(c) for c in cells]
            if k == 0 and len(cells) == 2 and numbers == [None, None]:  # a header line such as "t,value"
                continue
            if len(cells) != 2 or None in numbers:
                raise t.error("file", f"{path}, line {n}: expected two numbers 't,value', got '{line}'")
            tv, vv = numbers
            if not (math.isfinite(tv) and math.isfinite(vv)):
                raise t.error("file", f"{path}, line {n}: expected finite numbers, got '{line}'")
            times.append(tv)
            values.append(vv)
        where = f"{path}: "
        key = "file"
    else:
        for key in ("times", "values"):
            value = t.raw(key)
            if not isinstance(value, list):
                raise t.error(key, f"must be an array of numbers, got {_show(value)}")
        times = [t._to_float("times", v) for v in t.raw("times")]
        values = [t._to_float("values", v) for v in t.raw("values")]
        if len(values) != len(times):
            raise t.error("values", f"must have as many entries as times ({len(times)}), got {len(values)}")
        where = ""
        key = "times"
    if not times:
        raise t.error(key, f"{where}a table needs at least one point (t, value)")
    for a, b in zip(times, times[1:]):
        if not b > a:
            raise t.error(key, f"{where}times must be strictly increasing, got {a:g} then {b:g}")
    return tuple(times), tuple(values)


def _named_beam(t: _Table, key: str, beams: tuple[Beam, ...], name: str | None = None) -> int:
    """The index of the beam that key names (or `name`, one of the names key lists)."""
    name = t.string(key) if name is None else name
    for beam in beams:
        if beam.name == name:
            return beam.index
    known = [b.name for b in beams]
    raise t.error(key, f"beam '{name}' does not exist (beams: {', '.join(known)}){_did_you_mean(name, known)}")


# ----------------------------------------------------------------------------
# tables of the core's effect registry


def _spec_default(p: ParamSpec) -> Any:
    return tomllib.loads(f"v = {p.default}")["v"]


_FORMULATIONS = {"director": "a director beam", "ancf": "an ANCF cable"}


def _parse_effect_tables(data: dict[str, Any], tables: dict[str, tuple[EffectSpec, ...]], beams: tuple[Beam, ...],
                         analysis: Analysis, file: str, base_dir: str,
                         bodies: tuple[Body, ...] = ()) -> tuple[EffectEntry, ...]:
    """Every entry of every registry table, tables in file order (the order the model adds them)."""
    entries: list[EffectEntry] = []
    for table in (key for key in data if key in tables):
        specs = tables[table]
        if specs[0].single:
            raw = data[table]
            if not isinstance(raw, dict):
                raise SceneError(f"must be a table [{table}], got {_type_name(raw)}", file, "top level", table)
            raws, labels = [raw], [f"[{table}]"]
        else:
            raws = _array_of_tables(data, table, file)
            labels = [f"[[{table}]] #{i + 1}" for i in range(len(raws))]
        for i, (raw, label) in enumerate(zip(raws, labels)):
            t = _Table(raw, file, label, table)
            entries.append(_parse_registry_entry(t, _variant(t, specs), beams, analysis, base_dir, i, bodies))
    return _unique_labels(entries)


def _variant(t: _Table, specs: tuple[EffectSpec, ...]) -> EffectSpec:
    """The spec of an entry: the table's only one, or the variant its `type` key names."""
    if len(specs) == 1 and not specs[0].variant:
        return specs[0]
    kind = t.choice("type", tuple(s.variant for s in specs))
    return next(s for s in specs if s.variant == kind)


def _unique_labels(entries: list[EffectEntry]) -> tuple[EffectEntry, ...]:
    """Two entries that would share a label (two [[damping]] on one beam) are numbered, so that
    their history columns stay apart."""
    seen: dict[str, int] = {}
    out = []
    for e in entries:
        n = seen[e.label] = seen.get(e.label, 0) + 1
        out.append(e if n == 1 else dataclasses.replace(e, label=f"{e.label}#{n}"))
    return tuple(out)


def _where(beam: Beam, s: float) -> str:
    if s == 0.0:
        return f"{beam.name}@start"
    if s == beam.geometry.length:
        return f"{beam.name}@end"
    return f"{beam.name}@s={s:g}"


def _check_formulation(t: _Table, key: str, beam: Beam, p: ParamSpec, spec: EffectSpec) -> None:
    if p.choices and beam.formulation not in p.choices:
        what = f"[[{spec.table}]] type = '{spec.variant}'" if spec.variant else f"[[{spec.table}]]"
        allowed = " or ".join(_FORMULATIONS[c] for c in p.choices)
        raise t.error(key, f"beam '{beam.name}' is {_FORMULATIONS[beam.formulation]}: a {what} needs {allowed} "
                           f"({p.meaning})")


def _parse_registry_entry(t: _Table, spec: EffectSpec, beams: tuple[Beam, ...], analysis: Analysis,
                          base_dir: str = ".", index: int = 0, bodies: tuple[Body, ...] = ()) -> EffectEntry:
    """Validate one entry of a registry table ([[support]], [[damping]], ...) against its spec
    (kinds, units, defaults and bounds from the core) and turn it into the effect's parameters."""
    t.check_keys((("type",) if spec.variant else ()) + tuple(p.key for p in spec.params))
    num: dict[str, float] = {}
    vec: dict[str, list[float]] = {}
    text: dict[str, str] = {}
    on: dict[str, int] = {}      # beam parameters: key -> beam index
    at: dict[str, float] = {}    # points: beam parameter -> s
    pair: list[int] = []         # a `beams` parameter's two beams
    label_parts: dict[str, str] = {}
    for p in spec.params:
        if not t.has(p.key) and p.optional:
            continue
        if not t.has(p.key) and not p.default and p.kind != "time_function":
            raise t.error(p.key, f"missing required key ({p.meaning})")
        if p.kind == "name":
            text[p.key] = _entry_name(t, p.key, spec.table, index)
            label_parts.setdefault(p.key, text[p.key])
            continue
        value = t.raw(p.key) if t.has(p.key) else (_spec_default(p) if p.default and p.default != "load" else None)
        body = _named_body(t, p, spec, bodies)
        if body is not None:  # a [[support]] or [[load]] on a body
            on[p.key] = body.index
            num[p.key] = float(body.index)
            label_parts[p.key] = body.name
        elif p.kind in ("point", "end", "position") and on.get(p.on or "beam", -1) >= len(beams):
            host = p.on or "beam"
            part = bodies[on[host] - len(beams)]
            if p.kind == "end":
                raise t.error(p.key, f"body '{part.name}' has no ends: hold it by a point (a spherical support, or "
                                     f"type = \"fixed\" for the whole body) or by a [[joint]]")
            if p.kind == "point":  # where on the body, as drawn
                if isinstance(value, str):
                    raise t.error(p.key, f"body '{part.name}' has no ends: give the point of the body where it is "
                                         f"drawn, [x, y, z], got {_show(value)}")
                point = t.vec3_value(p.key, value)
                vec["point"] = list(point)
                num["s" if host == "beam" else f"{host}_s"] = 0.0
                label_parts[host] = f"{part.name}@({', '.join(f'{v:g}' for v in point)})"
        elif p.kind == "beam":
            if t.has(p.key) and _body_named(bodies, t.raw(p.key)) is not None:
                raise t.error(p.key, f"'{t.raw(p.key)}' is a [[body]]: a [[{spec.table}]] takes beams only"
                                     + (" (a mass on a body is part of its mass and inertia)"
                                        if spec.table == "point_mass" else ""))
            index_b = _named_beam(t, p.key, beams)
            _check_formulation(t, p.key, beams[index_b], p, spec)
            on[p.key] = index_b
            num[p.key] = float(index_b)
            label_parts[p.key] = beams[index_b].name
        elif p.kind == "track":
            names = t.raw(p.key)
            if isinstance(names, list):
                if len(names) < 1 or not all(isinstance(n, str) for n in names):
                    raise t.error(p.key, f"must be a beam's name or a list of beams' names, got {_show(names)}")
                track = [_named_beam(t, p.key, beams, n) for n in names]
                if len(track) > 1:
                    vec[f"{p.key}_track"] = [float(b) for b in track]
            else:
                track = [_named_beam(t, p.key, beams)]
            on[p.key] = track[0]
            num[p.key] = float(track[0])
            label_parts[p.key] = "+".join(beams[b].name for b in track)
        elif p.kind in ("point", "end"):
            host = p.on or "beam"
            beam = beams[on[host]]
            s = _parse_at(t, beam.geometry.length, p.key, value)
            if p.kind == "end":
                s = _snap_to_end(t, s, beam.geometry.length, p.key)
            at[host] = s
            num["s" if host == "beam" else f"{host}_s"] = s
            label_parts[host] = _where(beam, s)
        elif p.kind == "position":
            host = p.on or "beam"
            _check_position(t, p.key, beams[on[host]], at[host])
        elif p.kind == "motion":
            _parse_motion(t.sub(p.key, f"{t.label}.{p.key}"), p.size, base_dir, num, vec, text)
        elif p.kind == "beams":
            pair = _parse_beam_pair(t, p, beams, spec, bodies)
            stem = p.key.removesuffix("s")
            num.update({f"{stem}_a": float(pair[0]), f"{stem}_b": float(pair[1])})
            label_parts[p.key] = "-".join(_part(beams, bodies, b).name for b in pair)
        elif p.kind in ("ends", "points"):
            parts = [_part(beams, bodies, b) for b in pair]
            if p.kind == "ends":
                for part in parts:
                    if isinstance(part, Body):
                        raise t.error(p.key, f"body '{part.name}' has no ends: join it with a [[joint]] at a point "
                                             f"of the body")
                ends = _parse_ends(t, p.key, value, parts)  # type: ignore[arg-type]
            else:
                ends = _parse_points(t, p.key, value, parts)
            for side, part, where in zip("ab", parts, ends):
                if isinstance(part, Body):  # a point of the body, where it is drawn
                    vec[f"point_{side}"] = list(where)  # type: ignore[arg-type]
            num.update({f"s_{side}": (0.0 if isinstance(part, Body) else where)  # type: ignore[misc]
                        for side, part, where in zip("ab", parts, ends)})
            label_parts["beams"] = "-".join(part.name if isinstance(part, Body) else _where(part, where)  # type: ignore[arg-type]
                                            for part, where in zip(parts, ends))
        elif p.kind == "time_function":
            if t.has(p.key):
                tf = _parse_time_function(t.sub(p.key, f"{t.label}.{p.key}"), base_dir)
            elif p.default == "load" and analysis.type == "static":  # loads grow with the load steps
                tf = TimeFunction("ramp", 0.0, analysis.t_end, math.inf)
            else:
                tf = TimeFunction("constant")
            tf_num, tf_vec, tf_text = tf.params()
            num.update(tf_num)
            vec.update(tf_vec)
            text.update(tf_text)
        elif p.kind in ("number", "integer"):
            num[p.key] = _bounded_number(t, p, value)
        elif p.kind == "vector":
            any_length = p.size == 0  # a list of 2 or more (a profile's heights)
            if not isinstance(value, list) or (
                    (len(value) < 2 if any_length else len(value) != p.size) and not (value == [] and p.default == "[]")):
                raise t.error(p.key, f"must be an array of {'2 or more' if any_length else p.size} numbers"
                                     f"{f' ({p.unit})' if p.unit else ''}, got {_show(value)}")
            xs = [t._to_float(p.key, v) for v in value]
            if any(not (x > p.min if p.min_open else x >= p.min) or x > p.max for x in xs):
                raise t.error(p.key, f"every entry must be >= {p.min:g}, got {_show(value)}")
            vec[p.key] = xs
        elif p.kind == "choice":
            if not isinstance(value, str) or value not in p.choices:
                hint = _did_you_mean(value, p.choices) if isinstance(value, str) else ""
                raise t.error(p.key, f"must be one of {_quoted(p.choices)}, got {_show(value)}{hint}")
            text[p.key] = value
        else:
            raise t.error(p.key, f"internal: unknown parameter kind '{p.kind}'")
    where = " on ".join(label_parts.values())
    return EffectEntry(spec.type, f"{spec.type}[{where}]" if where else spec.type, spec.table, index, spec.variant,
                       t.label, num, vec, text)


_NAME = re.compile(r"[A-Za-z0-9_-]+")


def _entry_name(t: _Table, key: str, table: str, index: int) -> str:
    """A name: the entry's own (default <table><k>, k its number in the table from 1), or the
    name of another entry it refers to (a [[friction]]'s guide)."""
    if not t.has(key):
        return f"{table}{index + 1}"
    value = t.raw(key)
    if not isinstance(value, str) or not _NAME.fullmatch(value):
        raise t.error(key, f"must be a name of letters, digits, '_' and '-', got {_show(value)}")
    return value


def _bounded_number(t: _Table, p: ParamSpec, value: Any) -> float:
    x = (t.number(p.key, value, allow_inf=math.isinf(p.max)) if p.kind == "number"
         else float(t.integer(p.key, value, positive=False)))
    low_ok = x > p.min if p.min_open else x >= p.min
    if not (low_ok and x <= p.max):
        lo = f"{'>' if p.min_open else '>='} {p.min:g}" if math.isfinite(p.min) else ""
        hi = f"<= {p.max:g}" if math.isfinite(p.max) else ""
        raise t.error(p.key, f"must be {' and '.join(b for b in (lo, hi) if b)}"
                             f"{f' {p.unit}' if p.unit else ''}, got {_show(value)}")
    return x


def _check_position(t: _Table, key: str, beam: Beam, s: float) -> None:
    """A stated position must be the beam's reference point there (a check the user asked for)."""
    position = t.vec3(key)
    reference = beam.geometry.point_at(s)
    gap = float(np.linalg.norm(np.subtract(position, reference)))
    if gap > 1e-9 * beam.geometry.length + 1e-12:
        raise t.error(key, f"must sit on its beam: {position} is {gap:.3g} away from the reference point "
                           f"{reference} at s = {s}")


def _parse_motion(t: _Table, size: int, base_dir: str, num: dict[str, float], vec: dict[str, list[float]],
                  text: dict[str, str]) -> None:
    """motion = {displacement = [m], rotation = [rad] (size 6), time_function = {...}}, which
    must start from the drawn state (f(0) = 0)."""
    turns = size == 6
    t.check_keys(_MOTION_KEYS if turns else tuple(k for k in _MOTION_KEYS if k != "rotation"))
    if not (t.has("displacement") or t.has("rotation")):
        raise t.error("displacement", "a motion needs a displacement (m)" + (" or a rotation (rad)" if turns else ""))
    tf = _parse_time_function(t.sub("time_function", f"{t.label}.time_function"), base_dir)
    if abs(tf.value(0.0)) > 0.0:
        raise t.error("time_function", f"a motion must start from the drawn state: its time function is "
                                       f"{tf.value(0.0):g} at t = 0, not 0 (use a ramp, a hat or a step that starts "
                                       f"after 0)")
    zero = [0.0, 0.0, 0.0]
    vec["motion_displacement"] = list(t.vec3("displacement", zero))
    if turns:
        vec["motion_rotation"] = list(t.vec3("rotation", zero))
    tf_num, tf_vec, tf_text = tf.params()
    num.update(tf_num)
    vec.update(tf_vec)
    text.update(tf_text)


_BODY_TABLES = ("support", "load")  # registry tables whose `beam` may name a [[body]] (beside [[joint]])


def _named_body(t: _Table, p: ParamSpec, spec: EffectSpec, bodies: tuple[Body, ...]) -> Body | None:
    """The body a `beam` parameter names in the tables that take bodies, or a `body` parameter
    (a [[contact]] sphere's)."""
    if p.kind != "beam" or (spec.table not in _BODY_TABLES and p.key != "body") or not t.has(p.key):
        return None
    return _body_named(bodies, t.raw(p.key))


def _body_named(bodies: tuple[Body, ...], name: Any) -> Body | None:
    return next((b for b in bodies if b.name == name), None)


def _part(beams: tuple[Beam, ...], bodies: tuple[Body, ...], index: int) -> Beam | Body:
    """A beam or a body by its index in the core."""
    return beams[index] if index < len(beams) else bodies[index - len(beams)]


def _parse_beam_pair(t: _Table, p: ParamSpec, beams: tuple[Beam, ...], spec: EffectSpec,
                     bodies: tuple[Body, ...] = ()) -> list[int]:
    """Two beams' (or, for a [[joint]], bodies') names -> their indices in the core."""
    names = t.raw(p.key)
    if not (isinstance(names, list) and len(names) == p.size and all(isinstance(n, str) for n in names)):
        raise t.error(p.key, f"must be {p.size} beam names, e.g. [\"leg1\", \"leg2\"], got {_show(names)}")
    out = []
    for name in names:
        body = _body_named(bodies, name)
        if body is not None:  # a body has a frame: any joint takes it
            if spec.table != "joint":
                raise t.error(p.key, f"'{name}' is a [[body]]: it has no ends; join it with a [[joint]] at a point "
                                     f"of the body")
            out.append(body.index)
            continue
        out.append(_named_beam(t, p.key, beams, name))
        _check_formulation(t, p.key, beams[out[-1]], p, spec)
    if len(set(out)) < len(out):
        raise t.error(p.key, f"needs {p.size} different beams, got {_show(names)}")
    return out


def _parse_points(t: _Table, key: str, value: Any, parts: list[Beam | Body]) -> list[float | Vec3]:
    """One point per part: on a beam an arc length ('start', 'end' or a number), on a body where the
    point is drawn (3 numbers)."""
    if not (isinstance(value, list) and len(value) == len(parts)):
        raise t.error(key, f"must be {len(parts)} points, one per beam ('start', 'end' or an arc length; on a "
                           f"body, where the point is drawn), got {_show(value)}")
    return [t.vec3_value(key, v) if isinstance(p, Body) else _parse_at(t, p.geometry.length, key, v)
            for v, p in zip(value, parts)]


def _parse_ends(t: _Table, key: str, value: Any, beams: list[Beam]) -> list[float]:
    if not (isinstance(value, list) and len(value) == len(beams) and all(e in ("start", "end") for e in value)):
        raise t.error(key, f"must be {len(beams)} of 'start'/'end' (one per beam), got {_show(value)}")
    return [0.0 if e == "start" else b.geometry.length for e, b in zip(value, beams)]
