// SPDX-License-Identifier: MIT
#pragma once
/// @file Error-controlled step sizes (`[analysis] adapt`): an estimate of each step's local
/// truncation error from the last four solutions, and the choice of the next step from it.
///
/// Every scheme here is second order with a leading error in the phase: on a mode of frequency w
/// a step of size h advances the phase by w h (1 - C (w h)^2), so the position error of a step is
/// C h^3 |x'''|, with C = 1/12 for energy-momentum and midpoint and |beta - 1/12| / 2 for Newmark
/// and HHT (1/12 for the trapezoidal beta = 1/4). x''' comes from the third divided difference of
/// x_{n+1}, x_n, x_{n-1}, x_{n-2} on their (unequal) times: backward differences of the solutions,
/// as PETSc's TSEvaluateWLTE does, which needs no acceleration (energy-momentum has none).
///
/// The tolerance is on the error at t_end: a step of size h may contribute its share h / T of it
/// (T the run's span), so that phase errors, which add up step after step, sum to about the
/// tolerance at the end (error per unit step). Per entry the tolerance is atol on points and
/// sliding coordinates (metres) and rtol on directions (directors, ANCF slopes: dimensionless);
/// multipliers carry none. The step's error is
///
///   err = max_i |C h^3 x'''_i| / tol_i * T / h,     accepted when err <= 1.
///
/// An oscillation's phase error stops adding up once its phase is lost: it is then at most twice
/// its amplitude, |x''|^3 / |x'''|^2 for one mode (the same from resolved and unresolved
/// samples), and that bound replaces the estimate where it is smaller. A stiff mode barely
/// excited (the axial vibration of a steel beam) or Newton's noise then asks for no small steps
/// unless its amplitude exceeds the tolerance.
///
/// The next step is h * 0.9 err^(-1/2), at most 2x larger and 4x smaller. It grows only when the
/// envelope of err since the step size last changed (each step's err forgotten by 3 % a step)
/// allows 1.25x or more, after at least kSettle steps of that size: each change costs a fresh step Jacobian, and an oscillation's error comes
/// and goes twice a period, so the step follows its envelope, not every swing.

#include "model/model.hpp"

#include <petscvec.h>

#include <utility>
#include <vector>

namespace slidebeam {

struct ErrorControlParams {
  double rtol = 1e-4;    ///< on directions
  double atol = 1e-4;    ///< on points and sliding coordinates [m]
  double dt_max = 0.0;   ///< no step above it (0: none)
  double span = 1.0;     ///< T: the run's duration the tolerance is for
  double constant = 1.0 / 12.0;  ///< C of the scheme (see the file comment)
};

class ErrorControl {
 public:
  /// The first two steps have no estimate: they are taken at this fraction of the first step
  /// asked for, and the steps grow from there as the estimate allows (every step, up to 10x,
  /// until the estimate first limits the growth or a step is rejected).
  static constexpr double kStartFraction = 0.01;

  ErrorControl(const Model& model, Vec like, const ErrorControlParams& params);
  ~ErrorControl();
  ErrorControl(const ErrorControl&) = delete;
  ErrorControl& operator=(const ErrorControl&) = delete;

  /// Begin (or begin again: a restart, a checkpoint) the estimate at the state x_n.
  void start(Vec x_n);
  /// err of the step of size h from x_n (the last solution given) to x1 (collective); a negative
  /// value when fewer than three earlier solutions are known (the first two steps after start).
  double error(Vec x1, double h) const;
  /// The step of size h to x1 was accepted with the given err (negative: none): remember x1,
  /// return the next step's size.
  double accepted(Vec x1, double h, double err);
  /// The step of size h was rejected (err > 1; a failed Newton solve: 0): the size to try instead.
  double rejected(double h, double err);

  /// What set the last error(): the unknown whose term was largest, where it sits, and its two
  /// bounds in units of the tolerance (the phase estimate, twice the oscillation's amplitude).
  struct Limit {
    PetscInt unknown = -1;  ///< global index (-1: none)
    PetscInt control_point = -1;
    int coordinate = -1;    ///< at the control point (0-2 the point, then directions; -1: a sliding coordinate)
    double phase = 0.0, oscillation = 0.0;
    double err = 0.0;       ///< this rank's largest term (the step's err where it is largest)
  };
  /// The limit on this rank; the rank holding the largest term has the unknown.
  const Limit& limit() const { return limit_; }

 private:
  static constexpr int kSettle = 3;
  double bounded(double h) const { return params_.dt_max > 0 ? std::min(h, params_.dt_max) : h; }
  ErrorControlParams params_;
  Vec tol_inv_ = nullptr;    // 1 / tol_i (0 on multipliers)
  Vec past_[3] = {nullptr, nullptr, nullptr};  // x_n, x_{n-1}, x_{n-2}
  double past_h_[2] = {0.0, 0.0};     // t_n - t_{n-1}, t_{n-1} - t_{n-2}
  int known_ = 0;           // past solutions held (0..3)
  double worst_ = 0.0;      // the envelope of err since the step size last changed (decaying)
  int settled_ = 0;         // accepted steps at the current size
  bool starting_ = true;    // since start(): growing by the estimate every step, up to 10x
  std::vector<std::pair<PetscInt, int>> where_;  // per local entry: control point, coordinate
  mutable Limit limit_;
};

}  // namespace slidebeam
