// SPDX-License-Identifier: MIT
#pragma once
/// @file How Model::finalize spreads the unknowns over the ranks. The options -sb_serial_below
/// and -sb_serial_above_cut set it (solvers/solver_options.hpp reads them); the model only
/// applies it.

#include <petscsys.h>

namespace slidebeam {

struct PartitionPolicy {
  /// a model with fewer unknowns is owned and solved by rank 0 alone (0: always distribute).
  /// Measured on 2 ranks (scripts/bench_ranks.py, docs/performance.md): the distributed run
  /// costs 1.9x the serial one at 166 unknowns, 1.8x on the 64-span pendulum (1188); sliding
  /// scenes gain from about 800 unknowns, every scene measured from 1832 on.
  PetscInt serial_below = 1500;
  /// a split that leaves a rank more control points next to another rank's than this is owned
  /// by rank 0 alone (0: no limit). Measured: nets cut across 10 ropes (20 points a side) ran
  /// 0.9-1.0x the serial time on 2 ranks, across 20 ropes 2x (docs/performance.md, "Coupled ranks")
  PetscInt serial_above_cut = 30;
};

}  // namespace slidebeam
