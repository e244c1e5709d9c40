// SPDX-License-Identifier: MIT
#include "time/load_stepper.hpp"

#include "util/petsc_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace slidebeam {

LoadStepper::LoadStepper(Model& model, StaticSolver& solver, double t_end, int steps, int max_cuts)
    : model_(model), solver_(solver), t_end_(t_end), dt_nominal_(t_end / steps), dt_(t_end / steps),
      max_cuts_(max_cuts), events_(model) {
  if (!(t_end > 0) || steps < 1) throw std::invalid_argument("load stepping needs t_end > 0 and steps >= 1");
  clock_.start(0.0);
  for (Vec* v : {&x_last_, &x_prev_, &start_}) SB_CHECK(VecDuplicate(model_.x(), v));
  SB_CHECK(VecCopy(model_.x(), x_last_));
}

LoadStepper::~LoadStepper() {
  for (Vec* v : {&x_last_, &x_prev_, &start_}) VecDestroy(v);
}

void LoadStepper::set_continuation_bounds(std::vector<PetscInt> rows, std::vector<double> lo, std::vector<double> hi) {
  bound_rows_ = std::move(rows);
  bound_lo_ = std::move(lo);
  bound_hi_ = std::move(hi);
  if (continuation_) continuation_->set_bounds(bound_rows_, bound_lo_, bound_hi_);
}

EquilibriumSolver& LoadStepper::continuation() {
  if (!continuation_) {  // built at the first use: most load stepping never needs it
    continuation_ = std::make_unique<EquilibriumSolver>(model_);
    continuation_->set_bounds(bound_rows_, bound_lo_, bound_hi_);
  }
  return *continuation_;
}

void LoadStepper::solve(double t, LoadAdvance& adv) {
  Vec x = model_.x();
  SB_CHECK(VecCopy(x, start_));
  const SolveResult first = solver_.solve(t, ManifoldNewton::Attempts::first);
  adv.result = first;
  if (first.converged() && std::isfinite(first.residual_norm)) return;
  SB_CHECK(VecCopy(start_, x));
  const EquilibriumResult continued = continuation().solve(t, kPseudoStep);
  ++continuations_;
  adv.continued = true;
  solver_.set_time(t);
  adv.result.iterations = first.iterations + continued.newton_iterations;
  if (continued.converged) {
    adv.by_continuation = true;
    adv.result.reason = 1;  // converged (by the continuation)
    adv.result.residual_norm = continued.residual;
    return;
  }
  SB_CHECK(VecCopy(start_, x));
  const SolveResult last = solver_.solve(t, ManifoldNewton::Attempts::fallbacks);
  adv.result.reason = last.reason;
  adv.result.residual_norm = last.residual_norm;
  adv.result.iterations += last.iterations;
  adv.result.linear_iterations += last.linear_iterations;
}

void LoadStepper::find_crossing(LoadAdvance& adv) const {
  if (events_.empty()) return;
  const std::vector<double> g = events_.values(model_.x());
  const int k = events_.first_crossed(g);
  if (k < 0) return;
  const EventIndicator& crossed = events_.indicators()[static_cast<size_t>(k)];
  adv.event = crossed.effect;
  adv.event_index = crossed.index;
  adv.event_value = g[static_cast<size_t>(k)];
}

LoadAdvance LoadStepper::advance() {
  LoadAdvance adv;
  const double t_last = clock_.time();
  double t_new = clock_.next(dt_);
  if (t_new > t_end_ - 1e-9 * dt_nominal_) t_new = t_end_;  // land exactly on t_end despite rounding
  adv.t = t_new;
  Vec x = model_.x();
  if (dt_last_ > 0 && predictor_) model_.extrapolate(x, x_last_, x_prev_, (t_new - t_last) / dt_last_);
  solve(t_new, adv);
  if (adv.result.converged() && std::isfinite(adv.result.residual_norm)) {
    find_crossing(adv);
    if (adv.event >= 0) {  // back to the last load step, every slider on its carrier
      SB_CHECK(VecCopy(x_last_, x));
      solver_.set_time(t_last);
      adv.status = LoadAdvance::Status::Event;
      return adv;
    }
    SB_CHECK(VecCopy(x_last_, x_prev_));
    SB_CHECK(VecCopy(x, x_last_));
    clock_.advance(dt_, t_new);
    dt_last_ = t_new - t_last;
    dt_ = std::min(2 * dt_, dt_nominal_);  // recover the nominal increment after cuts
    return adv;
  }
  SB_CHECK(VecCopy(x_last_, x));  // back to the last converged state
  if (dt_ < dt_nominal_ / std::ldexp(1.0, max_cuts_)) {
    adv.status = LoadAdvance::Status::Failed;
    return adv;
  }
  dt_ /= 2;
  ++cuts_;
  adv.status = LoadAdvance::Status::Cut;
  return adv;
}

}  // namespace slidebeam
