// SPDX-License-Identifier: MIT
#pragma once
/// @file The event log behind a run's cost table (summary.json "cost"). The table reads the
/// slidebeam events (effects, ghost exchange, time steps, output) and the linear solves
/// (KSPSolve, PCSetUp). PETSc's default log handler costs about 0.3 us per event (two clock reads
/// through MPI_Wtime and the bookkeeping of flops, messages and reductions), and PETSc logs every
/// vector, matrix and star-forest operation: dozens per Newton iteration, a third of a small
/// cable's time step. So unless an option asks for PETSc's own log (-log_view, -log_all, ...),
/// only the events the table reads are logged, by a handler that sums wall time and calls.

#include <petscsys.h>

#include <string>
#include <utility>

namespace slidebeam {

/// Turn the event log on: the cost table's events with a light handler, or PETSc's whole log
/// when a -log_* option asks for it. Call once, after PETSc is initialised.
PetscErrorCode start_cost_log();

/// Wall time (s) and calls of the event `name` on this rank so far; (0, 0) for an event never
/// registered or not logged.
std::pair<double, long> event_stats(const std::string& name);

}  // namespace slidebeam
