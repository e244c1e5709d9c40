// SPDX-License-Identifier: MIT
#pragma once
/// @file The clock of a run of steps, dynamic or static: within a run of equal steps h the time
/// is t_0 + n h from the run's start, not a sum of steps, so that t_end and the output times
/// carry no accumulated roundoff, and a run stopped and restarted takes the same times.

namespace slidebeam {

class StepClock {
 public:
  /// Start at t (no step taken yet).
  void start(double t) {
    t_ = t0_ = t;
    n_ = 0;
  }
  double time() const { return t_; }
  /// The time after a step of size h from now.
  double next(double h) const { return h == h_ && n_ > 0 ? t0_ + double(n_ + 1) * h : t_ + h; }
  /// A step of size h was taken, to t_next (next(h), or a time it was clamped to).
  void advance(double h, double t_next) {
    if (h == h_ && n_ > 0) {
      ++n_;
    } else {
      t0_ = t_;
      n_ = 1;
    }
    h_ = h;
    t_ = t_next;
  }
  /// Resume at t; steps > 0 continues a run of `steps` equal steps h that started at start.
  void restore(double t, double h, double start, long steps) {
    t_ = t;
    h_ = h;
    t0_ = steps > 0 ? start : t;
    n_ = steps > 0 ? steps : 0;
  }
  /// The current run of equal steps: its start and the number of steps taken in it.
  double run_start() const { return t0_; }
  long run_steps() const { return n_; }

 private:
  double t_ = 0.0, t0_ = 0.0, h_ = 0.0;
  long n_ = 0;
};

}  // namespace slidebeam
