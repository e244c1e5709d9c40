// SPDX-License-Identifier: MIT
#pragma once
/// @file A clean stop on SIGINT / SIGTERM. While the handlers are installed, the first signal
/// only records itself (the run loops poll stop_signal() and end the run with its results
/// written); its handler is then reset to the system default, so that a second one ends the
/// process at once, even in the middle of a long solve.

#include <mpi.h>

namespace slidebeam {

/// Install the handlers for SIGINT and SIGTERM and forget any earlier signal.
void install_stop_handlers();
/// The signal received since install_stop_handlers(), 0 if none (this process only).
int stop_signal();
/// The same, agreed over comm (the largest of the ranks'; collective).
int stop_signal(MPI_Comm comm);

}  // namespace slidebeam
