// SPDX-License-Identifier: MIT
#pragma once
/// @file Step control of a static run (load stepping), in the core beside the dynamic Stepper:
/// the load time t runs from 0 to t_end in `steps` equal increments; each load step starts from
/// the secant predictor (the last two converged states extrapolated, the director triads turned
/// on by their last rotation), then Newton on the director manifold; where Newton fails, the
/// pseudo-transient continuation from the same state (a failed first attempt is mostly a
/// mechanism's: a hanger free to turn, a rope slack under a small load, where Newton on the
/// whole system wanders between equilibria and the continuation descends to a stable one); where
/// that fails too, Newton's fall-backs on the whole system. A step that fails is tried again
/// from the last converged state with half the increment, down to 1/2^max_cuts of it; after a
/// success the increment doubles back towards the nominal one. The load time is the StepClock's:
/// within a run of equal increments t_0 + n dt, landing exactly on t_end.
///
/// One call to advance() ends in one of four ways (as Stepper::advance):
///   accepted  the load step was solved (the state is at the new t);
///   cut       it failed: the next call tries half the increment (the state is at the last t);
///   failed    it failed at the smallest increment (the state is at the last t);
///   event     an EventSource indicator fell below zero (a slider beyond its carrier's end):
///             the state goes back to the last load step, which ends the run.
/// The caller records and answers signals between calls.

#include "model/model.hpp"
#include "solvers/equilibrium_solver.hpp"
#include "solvers/static_solver.hpp"
#include "time/advance_status.hpp"
#include "time/event_set.hpp"
#include "util/step_clock.hpp"

#include <memory>
#include <vector>

namespace slidebeam {

struct LoadAdvance {
  using Status = AdvanceStatus;
  Status status = Status::Accepted;
  SolveResult result;      ///< the step's solve: iterations over every attempt, the last attempt's reason and ||F||
  double t = 0.0;          ///< the load time attempted
  bool continued = false;  ///< the continuation was tried (result.reason its, or the fall-backs')
  bool by_continuation = false;  ///< the continuation solved it
  int event = -1;          ///< Event: the effect (model index) whose indicator crossed
  int event_index = 0;     ///< ... that effect's indicator
  double event_value = 0.0;  ///< ... its value at the solved (rejected) state
};

class LoadStepper {
 public:
  /// The continuation's first pseudo-step (s); switched evolution relaxation grows it.
  static constexpr double kPseudoStep = 0.01;

  LoadStepper(Model& model, StaticSolver& solver, double t_end, int steps, int max_cuts);
  ~LoadStepper();
  LoadStepper(const LoadStepper&) = delete;
  LoadStepper& operator=(const LoadStepper&) = delete;

  /// Take the next load step (see the file comment). Collective.
  LoadAdvance advance();
  /// The load time of the last converged step.
  double time() const { return clock_.time(); }
  bool done() const { return clock_.time() >= t_end_ * (1 - 1e-12); }
  /// Start each load step from the secant predictor (default true).
  void set_predictor(bool on) { predictor_ = on; }
  /// Unknowns the continuation keeps within [lo, hi] (free sliders' s within their carriers).
  void set_continuation_bounds(std::vector<PetscInt> rows, std::vector<double> lo, std::vector<double> hi);
  int cuts() const { return cuts_; }
  int continuations() const { return continuations_; }

 private:
  /// Newton, then the continuation, then the fall-backs, from the current (predicted) x.
  void solve(double t, LoadAdvance& adv);
  EquilibriumSolver& continuation();
  /// The first EventSource indicator at x below zero: adv's event, event_index and event_value
  /// (event -1: none). Collective.
  void find_crossing(LoadAdvance& adv) const;

  Model& model_;
  StaticSolver& solver_;
  double t_end_, dt_nominal_, dt_;
  int max_cuts_;
  bool predictor_ = true;
  StepClock clock_;
  EventSet events_;
  double dt_last_ = 0.0;  // the last converged increment (0: none yet, no predictor)
  Vec x_last_ = nullptr, x_prev_ = nullptr, start_ = nullptr;
  std::unique_ptr<EquilibriumSolver> continuation_;
  std::vector<PetscInt> bound_rows_;
  std::vector<double> bound_lo_, bound_hi_;
  int cuts_ = 0, continuations_ = 0;
};

}  // namespace slidebeam
