// SPDX-License-Identifier: MIT
#include "time/stepper.hpp"

#include "solvers/solver_options.hpp"
#include "util/petsc_check.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <tuple>

namespace slidebeam {

namespace {
// A shortened step ends on the boundary once its indicator is within [0, this] of its scale.
constexpr double kArrival = 1e-9;
// Regula falsi rounds on the step size before the closest inside try is taken.
constexpr int kArrivalRounds = 16;
/// An indicator found crossed while the best state inside the step is still this share of its
/// scale away (a slider more than 5 % of its carrier's length from the end) did not arrive: it
/// jumped, Newton having found a state beyond the end (the end span's polynomial extends there).
constexpr double kJump = 0.05;
}  // namespace

Stepper::Stepper(Model& model, TimeIntegrator& integrator, double dt, double dt_min)
    : model_(model), integ_(integrator), dt_nominal_(dt), dt_min_(dt_min), dt_(dt), events_(model) {
  if (!events_.empty()) allocate_snapshot();
}

void Stepper::allocate_snapshot() {
  if (snapshots()) return;
  for (Vec* v : {&snap_.x, &snap_.v, &snap_.a, &snap_.v_prev, &snap_.sdot}) SB_CHECK(VecDuplicate(integ_.x(), v));
}

void Stepper::set_error_control(const ErrorControlParams& params) {
  allocate_snapshot();
  control_ = std::make_unique<ErrorControl>(model_, integ_.x(), params);
  control_->start(integ_.x());
  dt_ = std::max(dt_min_, ErrorControl::kStartFraction * dt_);
  monitor_ = core_options(model_.comm()).adapt_monitor;
}

void Stepper::report_error(double h, double err) const {
  const ErrorControl::Limit& l = control_->limit();
  if (l.unknown < 0 || l.err != err) return;  // the rank holding the largest term reports it
  const std::string at = l.coordinate < 0 ? "a sliding coordinate"
                         : "control point " + std::to_string(l.control_point) + ", " +
                               (l.coordinate < 3 ? "position " : "direction ") + std::to_string(l.coordinate);
  SB_CHECK(PetscPrintf(PETSC_COMM_SELF,
                       "adapt: t = %.9g h = %.4g err = %.3g %s; largest at unknown %" PetscInt_FMT
                       " (%s): phase %.3g, oscillation bound %.3g\n",
                       integ_.time(), h, err, err > 1.0 ? "rejected" : "accepted", l.unknown, at.c_str(), l.phase,
                       l.oscillation));
}

Stepper::~Stepper() {
  for (Vec* v : {&snap_.x, &snap_.v, &snap_.a, &snap_.v_prev, &snap_.sdot}) VecDestroy(v);
}

void Stepper::take() {
  SB_CHECK(VecCopy(integ_.x(), snap_.x));
  SB_CHECK(VecCopy(integ_.v(), snap_.v));
  SB_CHECK(VecCopy(integ_.a(), snap_.a));
  SB_CHECK(VecCopy(integ_.v_prev(), snap_.v_prev));
  SB_CHECK(VecCopy(integ_.sliding_rate(), snap_.sdot));
  snap_.t = integ_.time();
  snap_.h_prev = integ_.h_prev();
  snap_.pivoting = integ_.pivoting_lu();
  std::tie(snap_.segment_start, snap_.segment_steps) = integ_.time_segment();
  snap_.flows.clear();
  for (const auto& f : integ_.energy_flows()) snap_.flows.push_back(f.work);
  if (model_.has_effect_history()) snap_.history = model_.effect_history();
}

void Stepper::restore() {
  SB_CHECK(VecCopy(snap_.x, integ_.x()));
  SB_CHECK(VecCopy(snap_.v, integ_.v()));
  SB_CHECK(VecCopy(snap_.a, integ_.a()));
  SB_CHECK(VecCopy(snap_.v_prev, integ_.v_prev()));
  SB_CHECK(VecCopy(snap_.sdot, integ_.sliding_rate()));
  integ_.restore(snap_.t, snap_.h_prev, snap_.pivoting, snap_.segment_start, snap_.segment_steps);
  if (model_.has_effect_history()) model_.set_effect_history(snap_.history);
  integ_.set_energy_flows(snap_.flows);
}

StepAdvance Stepper::advance(double t_end) {
  StepAdvance adv;
  // The step is dt unless less remains; a remainder within roundoff of dt is taken as dt, so
  // that a run stopped at t_end and restarted takes exactly the steps of one that went on.
  const double remaining = t_end - integ_.time();
  double h = remaining >= dt_ * (1 - 1e-9) ? dt_ : remaining;
  // error control: no sliver of a step at the end, two equal ones instead
  if (control_ && remaining > dt_ * (1 + 1e-9) && remaining < 1.5 * dt_) h = remaining / 2;
  std::vector<double> g_in;
  if (snapshots()) take();
  if (!events_.empty()) g_in = events_.values(integ_.x());
  const auto started = std::chrono::steady_clock::now();
  adv.result = integ_.step(h);
  adv.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  adv.h = h;
  adv.newton_iterations = adv.result.iterations;
  if (adv.result.converged()) {  // the integrator already counts NaN/Inf in F or x as a failure
    if (control_) {
      adv.local_error = control_->error(integ_.x(), h);
      if (monitor_) report_error(h, adv.local_error);
      if (adv.local_error > 1.0) {
        restore();
        cut(h, control_->rejected(h, adv.local_error), adv);
        return adv;
      }
    }
    if (!events_.empty()) {
      const std::vector<double> g = events_.values(integ_.x());
      const int k = events_.first_crossed(g);
      if (k >= 0) {
        arrive(k, h, g_in[static_cast<size_t>(k)], g[static_cast<size_t>(k)], adv);
        return adv;
      }
    }
    if (control_)
      dt_ = control_->accepted(integ_.x(), h, adv.local_error);
    else
      dt_ = std::min(2 * dt_, dt_nominal_);
    return adv;
  }
  reject(h, adv);
  return adv;
}

void Stepper::reject(double h, StepAdvance& adv) {
  if (control_) {
    cut(h, control_->rejected(h, 0.0), adv);
    return;
  }
  adv.rejected_attempts += 1;
  if (h / 2 < dt_min_ * (1 - 1e-12)) {
    adv.status = StepAdvance::Status::Failed;
    return;
  }
  adv.status = StepAdvance::Status::Cut;
  dt_ = h / 2;
}

void Stepper::cut(double h, double next, StepAdvance& adv) {
  adv.rejected_attempts += 1;
  adv.status = h <= dt_min_ * (1 + 1e-12) ? StepAdvance::Status::Failed : StepAdvance::Status::Cut;
  dt_ = std::max(next, dt_min_);
}

void Stepper::arrive(int k, double h, double g_in, double g_out, StepAdvance& adv) {
  locate(k, h, g_in, g_out, adv);
  adv.event_value = events_.values(integ_.x())[static_cast<size_t>(k)];
  if (adv.event_value <= kJump * events_.indicators()[static_cast<size_t>(k)].scale) return;
  // not an arrival: the step failed, and is cut like a step whose Newton failed
  restore();
  adv.event = -1;
  adv.event_step_taken = false;
  adv.event_value = 0.0;
  adv.result.reason = SNES_DIVERGED_FUNCTION_DOMAIN;  // its state left the carrier
  reject(h, adv);
}

void Stepper::locate(int k, double h, double g_in, double g_out, StepAdvance& adv) {
  adv.status = StepAdvance::Status::Event;
  adv.event = k;
  const double tolerance = kArrival * events_.indicators()[static_cast<size_t>(k)].scale;
  double h_in = 0.0, h_out = h;
  double best = -1.0;
  int side = 0;
  for (int round = 0; round < kArrivalRounds; ++round) {
    restore();
    double h_try = h_in + (h_out - h_in) * g_in / (g_in - g_out);
    h_try = std::min(std::max(h_try, h_in + 1e-4 * (h_out - h_in)), h_out - 1e-4 * (h_out - h_in));
    const SolveResult r = integ_.step(h_try);
    adv.newton_iterations += r.iterations;
    adv.rejected_attempts += r.converged() ? 0 : 1;
    const double g = r.converged() ? events_.values(integ_.x())[static_cast<size_t>(k)] : -1.0;
    if (g >= 0) {
      best = h_try;
      if (g <= tolerance) {
        adv.result = r;
        adv.h = h_try;
        adv.event_step_taken = true;
        return;
      }
      h_in = h_try;
      g_in = g;
      g_out *= side == 1 ? 0.5 : 1.0;  // Illinois: the same side twice halves the other end's value
      side = 1;
    } else {
      h_out = h_try;
      g_out = r.converged() ? g : 0.5 * g_out;
      g_in *= side == -1 ? 0.5 : 1.0;
      side = -1;
    }
  }
  restore();
  if (best < 0) return;  // no shortened step stayed inside: the event is at t_n
  adv.result = integ_.step(best);
  adv.newton_iterations += adv.result.iterations;
  adv.h = best;
  adv.event_step_taken = true;
}

}  // namespace slidebeam
