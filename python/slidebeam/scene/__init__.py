# SPDX-License-Identifier: MIT
"""Scenes: the TOML (or dict) description of a structure, parsed and validated (parse.py), the
scene tables' schema for the reference (schema.py), the effect tables from the core's registry
(effect_tables.py), and the closed-form cables a scene may be given by (catenary.py). Importable
without PETSc."""
from .parse import (Analysis, Beam, Body, Geometry, Output, Scene, SceneError, Section, SlidingJoint, Support,
                    TimeFunction, TrackPoint, Vec3, apply_override, auto_quadrature, circle_properties,
                    default_every, load_scene, rectangle_properties, sagging_arc, scene_from_dict, span_slenderness,
                    stretch_at_tension)

__all__ = ["Analysis", "Beam", "Body", "Geometry", "Output", "Scene", "SceneError", "Section", "SlidingJoint",
           "Support", "TimeFunction", "TrackPoint", "Vec3", "apply_override", "auto_quadrature", "circle_properties",
           "default_every", "load_scene", "rectangle_properties", "sagging_arc", "scene_from_dict",
           "span_slenderness", "stretch_at_tension"]
