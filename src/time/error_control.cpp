// SPDX-License-Identifier: MIT
#include "time/error_control.hpp"

#include "util/petsc_check.hpp"

#include <algorithm>
#include <cmath>

namespace slidebeam {

namespace {
constexpr double kSafety = 0.9;
constexpr double kGrowMax = 2.0, kShrinkMax = 0.25, kGrowMin = 1.25;
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
  for (PetscInt cp = 0; cp < map.n_cp(); ++cp) {
    if (!map.owns_cp(cp)) continue;
    for (int c = 0; c < map.n_coordinates(cp); ++c) {
      const PetscInt i = map.q(cp, c);
      if (i >= lo && i < hi) w[i - lo] = 1.0 / (c < 3 ? params_.atol : params_.rtol);
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
  // x''' = 6 x[t_n+1, t_n, t_n-1, t_n-2]; the error C h^3 x''' in units of tol * h / T
  const double scale = params_.constant * 6.0 * h * h * params_.span;
  double worst = 0.0;
  for (PetscInt i = 0; i < n; ++i) {
    if (w[i] == 0.0) continue;
    const double d32 = (p3[i] - p2[i]) / h, d21 = (p2[i] - p1[i]) / h2, d10 = (p1[i] - p0[i]) / h1;
    const double dd = ((d32 - d21) / (h + h2) - (d21 - d10) / (h2 + h1)) / (h + h2 + h1);
    worst = std::max(worst, std::abs(dd) * w[i]);
  }
  SB_CHECK(VecRestoreArrayRead(x1, &p3));
  SB_CHECK(VecRestoreArrayRead(past_[0], &p2));
  SB_CHECK(VecRestoreArrayRead(past_[1], &p1));
  SB_CHECK(VecRestoreArrayRead(past_[2], &p0));
  SB_CHECK(VecRestoreArrayRead(tol_inv_, &w));
  double global = 0.0;
  const double local = worst * scale;
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
  worst_ = std::max(worst_, err);
  if (settled_ < kSettle) return bounded(h);
  const double grow = worst_ > 0 ? kSafety / std::sqrt(worst_) : kGrowMax;
  if (grow < kGrowMin) return bounded(h);
  const double next = bounded(h * std::min(grow, kGrowMax));
  if (next != h) worst_ = 0.0, settled_ = 0;
  return next;
}

double ErrorControl::rejected(double h, double err) {
  worst_ = 0.0;
  settled_ = 0;
  if (err <= 0) return 0.5 * h;
  return h * std::max(kShrinkMax, std::min(kSafety, kSafety / std::sqrt(err)));
}

}  // namespace slidebeam
