# SPDX-License-Identifier: MIT
"""Translate a validated scene into the C++ model: one beam per [[beam]], one effect per
physical term the scene names (and nothing else)."""
from __future__ import annotations

import re
from dataclasses import dataclass

from .. import _core
from ..scene.effect_tables import effect_specs
from .geometry import reference_coordinates
from .parallel import run_comm
from .resources import check_memory
from ..scene.parse import Scene, SceneError


@dataclass(frozen=True)
class EffectInfo:
    """What the scene asked for, in the order of the model's effects."""

    type: str
    label: str


def build_model(scene: Scene, comm: object | None = None) -> tuple[_core.Model, list[EffectInfo]]:
    """Create and finalize the C++ model of a scene (collective over comm). A scene that cannot
    fit in memory is refused first (SceneError, see resources.check_memory). comm: an mpi4py
    communicator (default: the run's, parallel.run_comm)."""
    comm = run_comm() if comm is None else comm
    check_memory(scene, comm)
    model = _core.Model(comm)
    effects: list[EffectInfo] = []

    seen: dict[str, int] = {}

    def add(kind: str, label: str, num: dict | None = None, vec: dict | None = None, text: dict | None = None) -> None:
        model.add_effect(kind, num or {}, vec or {}, text or {})
        # a label names history columns: a second entry of a table on the same beam is "#2"
        seen[label] = seen.get(label, 0) + 1
        effects.append(EffectInfo(kind, label if seen[label] == 1 else f"{label}#{seen[label]}"))

    for b in scene.beams:
        sec = b.section
        try:
            reference = reference_coordinates(b)
        except ValueError as exc:  # a centre line the section frame cannot follow
            raise SceneError(str(exc), scene.file, f"[[beam]] #{b.index + 1} ('{b.name}')", b.geometry.kind) from exc
        model.add_beam(
            b.name, b.spans, b.geometry.length,
            {k: getattr(sec, k) for k in ("EA", "kGA2", "kGA3", "GJ", "EI2", "EI3", "rhoA", "rhoI2", "rhoI3")},
            "simo-reissner" if b.formulation == "ancf" else b.strain, b.quadrature, reference,
            b.formulation, b.unstretched_length,
        )
    dynamic = scene.analysis.type == "dynamic"
    for body in scene.bodies:  # one control point: its frame keeps the beams' orthonormality constraints
        model.add_body(body.name, body.mass, body.euler, body.q_ref())
        add("director_constraints", f"director_constraints[{body.name}]", {"beam": body.index})
        if dynamic:
            add("body_inertia", f"body_inertia[{body.name}]", {"beam": body.index})
    for b in scene.beams:
        if b.formulation == "ancf":  # a cable has no constraints of its own
            add("ancf_elastic", f"ancf_elastic[{b.name}]", {"beam": b.index})
            if dynamic:
                add("ancf_inertia", f"ancf_inertia[{b.name}]", {"beam": b.index})
            continue
        add("beam_elastic", f"beam_elastic[{b.name}]", {"beam": b.index})
        add("director_constraints", f"director_constraints[{b.name}]", {"beam": b.index})
        if dynamic:
            add("beam_inertia", f"beam_inertia[{b.name}]", {"beam": b.index})
    # The scene's effect tables, from the core's registry, in file order but constraints
    # (supports, joints) first: an effect that acts on a joint (friction, a drive) finds it made.
    specs = effect_specs()
    for entry in sorted(scene.effects, key=lambda e: specs[e.type].role != "constraint"):
        try:
            add(entry.type, entry.label, entry.num, entry.vec, entry.text)
            if specs[entry.type].table == "contact" and dynamic:
                # its friction and its damping: effects of their own beside it, on the same shape
                for keys, kind in ((("mu", "mu_axial", "mu_transverse"), "friction"), (("damping",), "damping")):
                    if any(entry.num.get(key, 0.0) > 0.0 for key in keys):
                        label = entry.label.replace("_contact", f"_{kind}", 1)
                        add(f"contact_{kind}", label, entry.num, entry.vec,
                            {**entry.text, "shape": specs[entry.type].variant, "label": label})
            if entry.type == "fluid_drag" and dynamic and any(
                    entry.num.get(key, 0.0) > 0.0 for key in ("ca_normal", "ca_tangential")):
                # the water it carries: kinetic energy of its own, beside the drag
                add("added_mass", entry.label.replace("fluid_drag", "added_mass", 1), entry.num, entry.vec, entry.text)
        except _core.ParamError as exc:  # refused by the effect: name the entry and the key
            key, message = exc.args
            raise SceneError(message, scene.file, entry.place, key) from exc
    try:
        model.finalize()
    except ValueError as exc:
        raise _placement_error(scene, str(exc)) from exc
    return model, effects


def _placement_error(scene: Scene, message: str) -> Exception:
    """The core's parallel closest-point search found a slider off its carrier: name the
    [[sliding_joint]] (the message names the slider and carrier beams)."""
    guide = re.match(r"guide: guide '(.*?)' ", message)
    if guide:
        for e in scene.effects:
            if e.type == "guide" and e.text.get("name") == guide.group(1):
                return SceneError(message.removeprefix("guide: "), scene.file, e.place, "point")
    match = re.match(r"sliding_joint: the slider point of beam '(.*?)' .* from carrier '(.*?)'", message)
    if not match:
        return ValueError(message)
    for i, sj in enumerate(scene.sliding_joints):
        slider, carrier = match.groups()
        if scene.beams[sj.slider].name == slider and carrier in (scene.beams[c].name for c in sj.carriers):
            return SceneError(message.removeprefix("sliding_joint: "), scene.file, f"[[sliding_joint]] #{i + 1}")
    return ValueError(message)
