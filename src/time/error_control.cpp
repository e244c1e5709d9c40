// SPDX-License-Identifier: MIT
#include "time/error_control.hpp"

#include "util/petsc_check.hpp"

#include <algorithm>
#include <cmath>

namespace slidebeam {

namespace {
constexpr double kSafety = 0.9;
constexpr double kGrowMax = 2.0, kShrinkMax = 0.25, kGrowMin = 1.25;
// growth per step while the run starts (until the estimate first limits it)
constexpr double kStartGrowMax = 10.0;
// the envelope forgets a step's err by this factor a step: a spike (a snap, a slider crossing a
// knot) holds the step for some tens of steps, not for the rest of the run
constexpr double kForget = 0.97;
}  // namespace

ErrorControl::ErrorControl(const Model& model, Vec like, const ErrorControlParams& params) : params_(params) {
  SB_CHECK(VecDuplicate(like, &tol_inv_));
  for (Vec& v : past_) SB_CHECK(VecDuplicate(like, &v));
  SB_CHECK(VecCopy(model.sliding_mask(), tol_inv_));
  SB_CHECK(VecScale(tol_inv_, 1.0 / params_.atol));
  const DofMap& map = model.dof_map();
  PetscInt lo = 0, hi = 0;
  SB_CHECK(VecGetOwnershipRange(tol_inv_, &lo, &hi));
  PetscScalar* w = nullptr;
  SB_CHECK(VecGetArray(tol_inv_, &w));
  where_.assign(static_cast<size_t>(hi - lo), {-1, -1});
  for (PetscInt cp = 0; cp < map.n_cp(); ++cp) {
    if (!map.owns_cp(cp)) continue;
    for (int c = 0; c < map.n_coordinates(cp); ++c) {
      const PetscInt i = map.q(cp, c);
      if (i < lo || i >= hi) continue;
      w[i - lo] = 1.0 / (c < 3 ? params_.atol : params_.rtol);
      where_[static_cast<size_t>(i - lo)] = {cp, c};
    }
  }
  SB_CHECK(VecRestoreArray(tol_inv_, &w));
}

ErrorControl::~ErrorControl() {
  VecDestroy(&tol_inv_);
  for (Vec& v : past_) VecDestroy(&v);
}

void ErrorControl::start(Vec x_n) {
  SB_CHECK(VecCopy(x_n, past_[0]));
  known_ = 1;
  worst_ = 0.0;
  settled_ = 0;
  starting_ = true;
}

double ErrorControl::error(Vec x1, double h) const {
  if (known_ < 3) return -1.0;
  const double h2 = past_h_[0], h1 = past_h_[1];
  const PetscScalar *p3 = nullptr, *p2 = nullptr, *p1 = nullptr, *p0 = nullptr, *w = nullptr;
  PetscInt n = 0;
  SB_CHECK(VecGetLocalSize(x1, &n));
  SB_CHECK(VecGetArrayRead(x1, &p3));
  SB_CHECK(VecGetArrayRead(past_[0], &p2));
  SB_CHECK(VecGetArrayRead(past_[1], &p1));
  SB_CHECK(VecGetArrayRead(past_[2], &p0));
  SB_CHECK(VecGetArrayRead(tol_inv_, &w));
  // x'' = 2 x[t_n+1, t_n, t_n-1] (or the earlier triple's), x''' = 6 x[t_n+1, t_n, t_n-1, t_n-2];
  // the phase error carried to t_end, C h^3 |x'''| T / h, saturates at twice the amplitude
  // |x''|^3 / |x'''|^2 of the oscillation that makes it
  const double phase = params_.constant * h * h * params_.span;  // times |x'''|: C h^2 T |x'''|
  double worst = 0.0;
  limit_ = Limit{};
  PetscInt lo = 0;
  SB_CHECK(VecGetOwnershipRange(x1, &lo, nullptr));
  for (PetscInt i = 0; i < n; ++i) {
    if (w[i] == 0.0) continue;
    const double d32 = (p3[i] - p2[i]) / h, d21 = (p2[i] - p1[i]) / h2, d10 = (p1[i] - p0[i]) / h1;
    const double s1 = (d32 - d21) / (h + h2), s0 = (d21 - d10) / (h2 + h1);
    const double third = 6.0 * std::abs((s1 - s0) / (h + h2 + h1));
    if (third == 0.0) continue;
    const double second = 2.0 * std::max(std::abs(s1), std::abs(s0));
    const double amplitude = second * second * second / (third * third);
    const double carried = phase * third * w[i], oscillation = 2.0 * amplitude * w[i];
    const double bound = std::min(carried, oscillation);
    if (bound > worst) {
      worst = bound;
      const auto [cp, c] = where_[static_cast<size_t>(i)];
      limit_ = {lo + i, cp, c, carried, oscillation, bound};
    }
  }
  SB_CHECK(VecRestoreArrayRead(x1, &p3));
  SB_CHECK(VecRestoreArrayRead(past_[0], &p2));
  SB_CHECK(VecRestoreArrayRead(past_[1], &p1));
  SB_CHECK(VecRestoreArrayRead(past_[2], &p0));
  SB_CHECK(VecRestoreArrayRead(tol_inv_, &w));
  double global = 0.0;
  const double local = worst;
  MPI_Allreduce(&local, &global, 1, MPI_DOUBLE, MPI_MAX, PetscObjectComm(reinterpret_cast<PetscObject>(x1)));
  return global;
}

double ErrorControl::accepted(Vec x1, double h, double err) {
  std::swap(past_[2], past_[1]);  // the oldest vector takes x1
  std::swap(past_[1], past_[0]);
  SB_CHECK(VecCopy(x1, past_[0]));
  past_h_[1] = past_h_[0];
  past_h_[0] = h;
  known_ = std::min(known_ + 1, 3);
  ++settled_;
  if (err < 0) return bounded(h);
  worst_ = std::max(worst_ * kForget, err);
  if (starting_) {  // from the small first steps up to the size the estimate asks for, a step at a time
    const double grow = err > 0 ? kSafety / std::sqrt(err) : kStartGrowMax;
    if (grow < kStartGrowMax) starting_ = false;
    if (grow >= kGrowMin) {
      worst_ = 0.0, settled_ = 0;
      return bounded(h * std::min(grow, kStartGrowMax));
    }
    return bounded(h);
  }
  if (settled_ < kSettle) return bounded(h);
  const double grow = worst_ > 0 ? kSafety / std::sqrt(worst_) : kGrowMax;
  if (grow < kGrowMin) return bounded(h);
  const double next = bounded(h * std::min(grow, kGrowMax));
  if (next != h) worst_ = 0.0, settled_ = 0;
  return next;
}

double ErrorControl::rejected(double h, double err) {
  starting_ = false;
  worst_ = 0.0;
  settled_ = 0;
  if (err <= 0) return 0.5 * h;
  return h * std::max(kShrinkMax, std::min(kSafety, kSafety / std::sqrt(err)));
}

}  // namespace slidebeam
