#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Scripting slidebeam from Python (petsc4py).

Builds a cantilever scene in Python (the same layout as a TOML scene), solves it by driving
the load steps from the script, reaches the state, residual, Jacobian and SNES as petsc4py
objects (the very objects the C++ core uses, no copies), and writes the results as
`slidebeam run` does. docs/api.md is the reference.

    PYTHONPATH=python /usr/bin/python3 runs/scripting_example.py [output folder]
    mpirun -n 2 env PYTHONPATH=python /usr/bin/python3 runs/scripting_example.py -sb_static_snes_monitor
"""
import sys

import petsc4py

petsc4py.init(sys.argv)  # PETSc options from the command line, e.g. -snes_monitor or -sb_static_snes_monitor
from mpi4py import MPI  # noqa: E402
from petsc4py import PETSc  # noqa: E402

import slidebeam  # noqa: E402

scene = slidebeam.scene_from_dict({
    "scene": {"name": "cantilever"},
    "analysis": {"type": "static", "steps": 4},
    "beam": [{
        "name": "rod", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 8,
        "section": {"shape": "circle", "r": 0.01, "E": 2.1e11, "nu": 0.3, "rho": 7800},
    }],
    "support": [{"type": "clamp", "beam": "rod", "at": "start"}],
    "load": [{"type": "force", "beam": "rod", "at": "end", "value": [0, 0, -300.0]}],
})
sim = slidebeam.Simulation(scene)
rank = MPI.COMM_WORLD.Get_rank()
if rank == 0:
    print("active effects:", [e.label for e in sim.active_effects])

# The script drives the load steps itself, keeping a history record of each.
records = [sim.record(0, None)]
for k in range(1, 5):
    result = sim.solve_step(t=k / 4)
    tip = sim.point("rod", 2.0).phi  # BeamPoint(phi, d1, d2, d3)
    if rank == 0:
        print(f"load step {k}: {result.iterations} Newton iterations, tip = {tip.round(6).tolist()}")
    assert result.converged
    records.append(sim.record(k, result))

# The core's PETSc objects, shared with petsc4py.
x: PETSc.Vec = sim.x
F: PETSc.Vec = sim.static_residual()
J: PETSc.Mat = sim.assemble_jacobian()
snes: PETSc.SNES = sim.snes
assert snes.getFunction()[0].handle == F.handle  # the SNES evaluates into the same vector
fnorm, size = F.norm(), x.getSize()
if rank == 0:
    print(f"{size} unknowns, |F| = {fnorm:.2e}, J: {J.getSize()}, SNES type {snes.getType()}, "
          f"KSP {snes.getKSP().getType()}/{snes.getKSP().getPC().getFactorSolverType()}")

# Energies and the deflected shape; the static tip deflection of a linear cantilever, P L^3/(3 EI),
# is a sanity check for this small load.
e = sim.energies()
EI = 2.1e11 * 3.141592653589793 * 0.01**4 / 4
if rank == 0:
    print(f"strain energy {e['strain']:.6f} J; linear theory tip deflection {300 * 8 / (3 * EI):.6f} m")

# history.csv, final_configuration.csv and summary.json, as `slidebeam run` writes them
folder = next((a for a in sys.argv[1:] if not a.startswith("-")), None)
if folder:
    summary = slidebeam.write_results(sim, records, folder)
    if rank == 0:
        print(f"results in {folder}/: complete = {summary['complete']}")
