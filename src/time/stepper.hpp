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
/// The caller records, checkpoints and answers signals between calls (one call per step: the
/// record cadence and the run's end are the caller's).

#include "model/effect_parts.hpp"
#include "model/model.hpp"
#include "solvers/time_integrator.hpp"

#include <vector>

namespace slidebeam {

struct StepAdvance {
  enum class Status { Accepted, Cut, Failed, Event };
  Status status = Status::Accepted;
  SolveResult result;            ///< the accepted (or shortened) step's solve, else the failed attempt's
  double h = 0.0;                ///< its size
  int rejected_attempts = 0;     ///< attempts whose Newton solve failed (a cut, the event's shortened tries)
  int newton_iterations = 0;     ///< over every attempt of this call
  double wall_time = 0.0;        ///< seconds in the step's first attempt (the event's tries not counted)
  int event = -1;                ///< Event: index into Stepper::events()
  bool event_step_taken = false; ///< Event: a shortened step was taken (else the state is at t_n)
};

class Stepper {
 public:
  /// An indicator: the effect (model index) and its indicator's index there.
  struct Event {
    int effect = -1;
    int index = 0;
    double scale = 1.0;
  };

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
  const std::vector<Event>& events() const { return events_; }

 private:
  /// The integrator's state at t_n, to take a step again with another size.
  struct Snapshot {
    Vec x = nullptr, v = nullptr, a = nullptr, v_prev = nullptr, sdot = nullptr;
    double t = 0.0, h_prev = 0.0, segment_start = 0.0;
    long segment_steps = 0;
    bool pivoting = false;
    std::vector<double> flows;
  };
  void take();
  void restore();
  /// Every indicator at the integrator's x (collective).
  std::vector<double> indicators() const;
  /// Take the step from t_n again, shortened so that event k's indicator lands on its boundary;
  /// g_in >= 0 at t_n, g_out < 0 at the end of the step of size h.
  void arrive(int k, double h, double g_in, double g_out, StepAdvance& adv);

  Model& model_;
  TimeIntegrator& integ_;
  double dt_nominal_, dt_min_, dt_;
  std::vector<Event> events_;
  std::vector<const EventSource*> sources_;  // per event
  Snapshot snap_;
};

}  // namespace slidebeam
