# SPDX-License-Identifier: MIT
"""Translate a validated scene into the C++ model: one beam per [[beam]], one effect per
physical term the scene names (and nothing else)."""
from __future__ import annotations

import re
from dataclasses import dataclass

from . import _core
from .geometry import reference_coordinates
from .resources import check_memory
from .scene import Scene, SceneError, TimeFunction


@dataclass(frozen=True)
class EffectInfo:
    """What the scene asked for, in the order of the model's effects."""

    type: str
    label: str


def _tf(tf: TimeFunction) -> tuple[dict[str, float], dict[str, list[float]], dict[str, str]]:
    return tf.params()


def _where(scene: Scene, beam: int, s: float) -> str:
    b = scene.beams[beam]
    if s == 0.0:
        return f"{b.name}@start"
    if s == b.geometry.length:
        return f"{b.name}@end"
    return f"{b.name}@s={s:g}"


def _reference_point(beam, q, s: float) -> list[float]:
    """The point at arc length s of a beam's discretised reference centre line (control points q)."""
    if beam.formulation == "ancf":
        le = beam.geometry.length / beam.spans
        e = min(max(int(s // le), 0), beam.spans - 1)
        S, _, _ = _core.hermite_basis(min(max(s - e * le, 0.0), le), le)
        blocks = [q[e][:3], q[e][3:6], q[e + 1][:3], q[e + 1][3:6]]
        return [float(sum(w * y[k] for w, y in zip(S, blocks))) for k in range(3)]
    span, N, _, _ = _core.bspline_basis(beam.spans, min(max(s / beam.geometry.length, 0.0), 1.0))
    return [float(sum(N[a] * q[span + a][k] for a in range(3))) for k in range(3)]


def build_model(scene: Scene, comm: object | None = None) -> tuple[_core.Model, list[EffectInfo]]:
    """Create and finalize the C++ model of a scene (collective over comm). A scene that cannot
    fit in memory is refused first (SceneError, see resources.check_memory)."""
    check_memory(scene, comm)
    model = _core.Model(comm)
    effects: list[EffectInfo] = []

    def add(kind: str, label: str, num: dict | None = None, vec: dict | None = None, text: dict | None = None) -> None:
        model.add_effect(kind, num or {}, vec or {}, text or {})
        effects.append(EffectInfo(kind, label))

    references = []
    for b in scene.beams:
        sec = b.section
        try:
            reference = reference_coordinates(b)
            references.append(reference)
        except ValueError as exc:  # a centre line the section frame cannot follow
            raise SceneError(str(exc), scene.file, f"[[beam]] #{b.index + 1} ('{b.name}')", b.geometry.kind) from exc
        model.add_beam(
            b.name, b.spans, b.geometry.length,
            {k: getattr(sec, k) for k in ("EA", "kGA2", "kGA3", "GJ", "EI2", "EI3", "rhoA", "rhoI2", "rhoI3")},
            "simo-reissner" if b.formulation == "ancf" else b.strain, b.quadrature, reference,
            b.formulation,
        )
    dynamic = scene.analysis.type == "dynamic"
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
    for sup in scene.supports:
        name = scene.beams[sup.beam].name
        num: dict = {"beam": sup.beam}
        vec: dict = {}
        text: dict = {}
        if sup.motion is not None:
            tf_num, vec, text = _tf(sup.motion.time_function)
            num.update(tf_num)
            vec = {**vec, "motion_displacement": list(sup.motion.displacement),
                   "motion_rotation": list(sup.motion.rotation)}
        if sup.type == "fixed":
            add("fixed", f"fixed[{name}]", num)
        elif sup.type == "clamp":
            add("clamp", f"clamp[{_where(scene, sup.beam, sup.at)}]", {**num, "s": sup.at}, vec, text)
        else:
            # the discretised reference centre line's point (a spline through a polyline's corner
            # or along an arc passes beside the drawn one): the reference state meets the support
            position = _reference_point(scene.beams[sup.beam], references[sup.beam], sup.at)
            add("spherical", f"spherical[{_where(scene, sup.beam, sup.at)}]", {**num, "s": sup.at},
                {**vec, "position": list(position)}, text)
    for load in scene.loads:
        num, vec, text = _tf(load.time_function)
        text["frame"] = load.frame
        add(load.type, f"{load.type}[{_where(scene, load.beam, load.at)}]",
            {"beam": load.beam, "s": load.at, **num}, {"value": list(load.value), **vec}, text)
    for j in scene.rigid_joints:
        add("rigid_joint", f"rigid_joint[{_where(scene, j.beam_a, j.at_a)}-{_where(scene, j.beam_b, j.at_b)}]",
            {"beam_a": j.beam_a, "s_a": j.at_a, "beam_b": j.beam_b, "s_b": j.at_b})
    for sj in scene.sliding_joints:
        num = {"slider": sj.slider, "slider_s": sj.at, "carrier": sj.carrier}
        if sj.tolerance is not None:
            num["tolerance"] = sj.tolerance
        add("sliding_joint", f"sliding_joint[{_where(scene, sj.slider, sj.at)} on {scene.beams[sj.carrier].name}]",
            num, None, {"discrete_gradient": sj.discrete_gradient, "form": sj.form})
    for pm in scene.point_masses:
        add("point_mass", f"point_mass[{_where(scene, pm.beam, pm.at)}, {pm.mass:g} kg]",
            {"beam": pm.beam, "s": pm.at, "mass": pm.mass})
    for entry in scene.effects:  # tables of the core's registry
        add(entry.type, entry.label, entry.num, entry.vec, entry.text)
    if scene.gravity is not None:
        # By default gravity grows with the load steps in statics like every other load, and is
        # constant in dynamics; [gravity] time_function replaces that.
        tf = scene.gravity_time_function
        if tf is None:
            tf = (TimeFunction("ramp", 0.0, scene.analysis.t_end, float("inf")) if scene.analysis.type == "static"
                  else TimeFunction("constant", 0.0, float("inf"), float("inf")))
        num, vec, text = _tf(tf)
        add("gravity", "gravity", num, {"g": list(scene.gravity), **vec}, text)
    try:
        model.finalize()
    except ValueError as exc:
        raise _placement_error(scene, str(exc)) from exc
    return model, effects


def _placement_error(scene: Scene, message: str) -> Exception:
    """The core's parallel closest-point search found a slider off its carrier: name the
    [[sliding_joint]] (the message names the slider and carrier beams)."""
    match = re.match(r"sliding_joint: the slider point of beam '(.*?)' .* from carrier '(.*?)'", message)
    if not match:
        return ValueError(message)
    for i, sj in enumerate(scene.sliding_joints):
        if (scene.beams[sj.slider].name, scene.beams[sj.carrier].name) == match.groups():
            return SceneError(message.removeprefix("sliding_joint: "), scene.file, f"[[sliding_joint]] #{i + 1}")
    return ValueError(message)
