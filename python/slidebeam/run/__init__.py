# SPDX-License-Identifier: MIT
"""Running a scene: the model built from it (model.py, geometry.py), the Simulation facade over
the C++ core (simulation.py), the dynamic run loop's records, checkpoints and signals around the
core's stepper (dynamics.py, interrupts.py), and what a run needs around them: its PETSc options
(options_check.py), ranks (parallel.py), memory (resources.py) and costs (costs.py)."""
