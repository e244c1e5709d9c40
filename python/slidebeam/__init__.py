# SPDX-License-Identifier: MIT
"""slidebeam: director-based geometrically exact beams with sliding joints on PETSc.

Scene handling is importable without PETSc. ``Simulation`` (and everything that touches the
C++ core) imports petsc4py on first use, so a program can call ``petsc4py.init(args)``
itself first (the command-line tool does, to pass PETSc options such as -log_view).
"""
from __future__ import annotations

from typing import Any

from .scene import Scene, SceneError, load_scene, scene_from_dict

__all__ = ["Scene", "SceneError", "load_scene", "scene_from_dict", "Simulation", "Reaction", "ConstraintWarning"]


def __getattr__(name: str) -> Any:
    if name == "Simulation":
        from .simulation import Simulation

        return Simulation
    if name == "ConstraintWarning":
        from .simulation import ConstraintWarning

        return ConstraintWarning
    if name == "Reaction":
        from .dynamics import Reaction

        return Reaction
    raise AttributeError(f"module 'slidebeam' has no attribute {name!r}")
