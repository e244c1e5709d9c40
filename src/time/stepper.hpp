// SPDX-License-Identifier: MIT
#pragma once
/// @file Step control of a dynamic run, in the core: the step size, cuts after a failed Newton
/// solve, and events located on the step size. The scheme (energy-momentum, midpoint, Newmark,
/// HHT) is the TimeIntegrator's; the Stepper decides which steps it takes.
///
/// One call to advance() ends in one of four ways:
///   accepted  a step was taken (the step size then grows back towards dt, doubling);
///   cut       Newton failed: the step size is halved for the next call (the state is at t_n);
///   failed    Newton failed at a step that cannot be halved above dt_min (the state is at t_n);
///   event     an indicator of an EventSource effect fell below zero during the step: the step
///             was taken again from t_n, shortened by Illinois regula falsi on its size until the
///             indicator lies within [0, 1e-9] of its scale, and that shortened step is the
///             run's last (or, if no shortened step stays inside, the state is left at t_n).
/// With error control (set_error_control, `[analysis] adapt`) an accepted Newton solve whose
/// local error estimate exceeds the tolerance is a rejection: the state goes back to t_n and
/// the call ends as `cut` with a smaller step; accepted steps set the next size from the
/// estimate (time/error_control.hpp), and `failed` also means the error stayed above the
/// tolerance at dt_min.
/// The caller records, checkpoints and answers signals between calls (one call per step: the
/// record cadence and the run's end are the caller's).

#include "model/model.hpp"
#include "time/advance_status.hpp"
#include "time/error_control.hpp"
#include "time/event_set.hpp"
#include "solvers/time_integrator.hpp"

#include <memory>
#include <vector>

namespace slidebeam {

struct StepAdvance {
  using Status = AdvanceStatus;
  Status status = Status::Accepted;
  SolveResult result;            ///< the accepted (or shortened) step's solve, else the failed attempt's
  double h = 0.0;                ///< its size
  int rejected_attempts = 0;     ///< attempts whose Newton solve failed (a cut, the event's shortened tries)
  int newton_iterations = 0;     ///< over every attempt of this call
  double wall_time = 0.0;        ///< seconds in the step's first attempt (the event's tries not counted)
  int event = -1;                ///< Event: index into Stepper::events()
  double event_value = 0.0;      ///< Event: the indicator at the state the call ends in
  bool event_step_taken = false; ///< Event: a shortened step was taken (else the state is at t_n)
  double local_error = -1.0;     ///< error control: err of the step (<= 1 accepted; -1: none)
};

class Stepper {
 public:
  /// dt: the nominal step (the step grows back to it after cuts); dt_min: no step below it.
  Stepper(Model& model, TimeIntegrator& integrator, double dt, double dt_min);
  ~Stepper();
  Stepper(const Stepper&) = delete;
  Stepper& operator=(const Stepper&) = delete;

  /// Take the next step towards t_end (see the file comment). Collective.
  StepAdvance advance(double t_end);
  /// The step size the next call tries (below dt after cuts; a restart sets it back).
  double dt() const { return dt_; }
  void set_dt(double dt) { dt_ = dt; }
  const std::vector<EventIndicator>& events() const { return events_.indicators(); }
  /// Choose the steps by their local error from now on (the estimate starts at the current state).
  void set_error_control(const ErrorControlParams& params);
  /// Begin the estimate afresh at the current state (a checkpoint: the run then goes on as a
  /// restart from it would).
  void restart_error_estimate() {
    if (control_) control_->start(integ_.x());
  }

 private:
  /// The integrator's state at t_n, to take a step again with another size.
  struct Snapshot {
    Vec x = nullptr, v = nullptr, a = nullptr, v_prev = nullptr, sdot = nullptr;
    double t = 0.0, h_prev = 0.0, segment_start = 0.0;
    long segment_steps = 0;
    bool pivoting = false;
    std::vector<double> flows;
    std::vector<double> history;  ///< the effects' (Model::effect_history)
  };
  void allocate_snapshot();
  /// snap_'s vectors exist (there are events or error control).
  bool snapshots() const { return snap_.x != nullptr; }
  /// After a rejected attempt of size h: try next, but not below dt_min; fail if h was dt_min.
  void cut(double h, double next, StepAdvance& adv);
  void take();
  void restore();
  /// Take the step from t_n again, shortened so that event k's indicator lands on its boundary;
  /// g_in >= 0 at t_n, g_out < 0 at the end of the step of size h.
  void arrive(int k, double h, double g_in, double g_out, StepAdvance& adv);
  /// The step of size h failed (its Newton, or an indicator that jumped): cut it, or fail at dt_min.
  void reject(double h, StepAdvance& adv);
  void locate(int k, double h, double g_in, double g_out, StepAdvance& adv);

  Model& model_;
  TimeIntegrator& integ_;
  double dt_nominal_, dt_min_, dt_;
  EventSet events_;
  Snapshot snap_;
  std::unique_ptr<ErrorControl> control_;
  bool monitor_ = false;  // -sb_adapt_monitor: each estimate and what set it, on the console
  void report_error(double h, double err) const;
};

}  // namespace slidebeam
