# SPDX-License-Identifier: MIT
"""slidebeam: director-based geometrically exact beams with sliding joints on PETSc.

The package's rooms, their dependencies running one way (app -> plots, output -> run -> scene):
``scene`` (scene files, importable without PETSc), ``run`` (the model and the Simulation facade
over the C++ core ``_core``), ``output`` (history, run folders, checkpoints, XDMF, run folders
read back), ``plots`` (figures and pictures of run folders), ``app`` (the command line, studies).

Scene handling is importable without PETSc. ``Simulation`` (and everything that touches the
C++ core) imports petsc4py on first use, so a program can call ``petsc4py.init(args)``
itself first (the command-line tool does, to pass PETSc options such as -log_view).
"""
from __future__ import annotations

from typing import Any

from .scene import Scene, SceneError, load_scene, scene_from_dict

__all__ = ["Scene", "SceneError", "load_scene", "scene_from_dict", "Simulation", "BeamPoint", "StepRecord",
           "DynamicRecord", "RunOutcome", "JointState", "Reaction", "ConstraintWarning", "EquilibriumFailure",
           "ResultWriter", "write_results"]

# name -> the module that defines it (imported on first use: they need petsc4py)
_LAZY = {"Simulation": "run.simulation", "BeamPoint": "run.simulation", "StepRecord": "run.simulation",
         "ConstraintWarning": "run.simulation", "EquilibriumFailure": "run.simulation",
         "DynamicRecord": "run.dynamics", "RunOutcome": "run.dynamics", "JointState": "run.dynamics",
         "Reaction": "run.dynamics", "ResultWriter": "output.results", "write_results": "output.results"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'slidebeam' has no attribute {name!r}")
