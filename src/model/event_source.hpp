// SPDX-License-Identifier: MIT
#pragma once
/// @file An effect's opt-in part: events. An event is where an indicator function g(x) of the
/// state falls below zero (g >= 0 inside): a slider passing its carrier's end. The stepper
/// (src/time/stepper.hpp) evaluates the indicators after each step and, where one has crossed,
/// takes the step again, shortened until the state lies on the boundary. An effect takes part
/// by deriving from EventSource as well as Effect; nothing else in the model needs to know it.

#include <petscsys.h>

namespace slidebeam {

class Model;

class EventSource {
 public:
  virtual ~EventSource() = default;
  /// Number of indicator functions.
  virtual int n_events() const = 0;
  /// g_i(x) for i < n_events() from this rank's owned rows of x (the array holds rows
  /// [owned_lo, owned_hi)); 0 for what this rank does not own: the caller sums over the ranks.
  virtual void event_values(const Model& model, const PetscScalar* x, PetscInt owned_lo, PetscInt owned_hi,
                            double* g) const = 0;
  /// The length that scales g_i: an indicator below -1e-12 of it has crossed, and a shortened
  /// step ends on the boundary once g_i is within [0, 1e-9] of it.
  virtual double event_scale(const Model& model, int i) const = 0;
};

}  // namespace slidebeam
