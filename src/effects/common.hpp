// SPDX-License-Identifier: MIT
#pragma once
/// @file Helpers shared by effects: which items a rank owns, gathering a span's coordinates,
/// and the global indices of its unknowns.

#include "kernels/beam_kernels.hpp"
#include "model/model.hpp"

#include <array>
#include <string>
#include <vector>

namespace slidebeam::effects {

/// Beam index from parameters, checked against the model.
int beam_param(const Model& model, const EffectParams& p);

/// Rank that evaluates span e of a beam: the owner of its middle control point, so that every
/// span has exactly one owner and neighbouring spans mostly stay on one rank.
inline bool owns_span(const Model& m, const Beam& b, int e) { return m.dof_map().owns_cp(b.first_cp() + e + 1); }

/// Index (within the beam) of the end control point at arc length s (0 or L), or -1 if s is
/// inside the beam. Open knot vectors make end control points interpolate.
int end_cp(const Beam& b, double s);

/// Add all unknowns (coordinates and multipliers) of control points cp0 .. cp0+n-1 to a dof list.
void add_cp_blocks(const DofMap& map, PetscInt cp0, int n, std::vector<PetscInt>& dofs);

/// The 36 coordinates of span e (control points e, e+1, e+2) in the state x.
kernels::VecEl gather_span(const LocalValues& x, const DofMap& map, const Beam& b, int e);

/// Global indices of the 36 coordinates of span e.
std::array<PetscInt, kernels::kNqEl> span_q_dofs(const DofMap& map, const Beam& b, int e);

/// r(span coordinates) += v.
void scatter_span(const DofMap& map, const LocalValues& r, const Beam& b, int e, const kernels::VecEl& v);

}  // namespace slidebeam::effects
