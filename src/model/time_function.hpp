// SPDX-License-Identifier: MIT
#pragma once
/// @file Load amplitude over time: constant, ramp, hat, step (scene `time_function`).

#include "model/effect.hpp"

#include <limits>
#include <string>

namespace slidebeam {

struct TimeFunction {
  enum class Kind { Constant, Ramp, Hat, Step } kind = Kind::Constant;
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity(), t2 = std::numeric_limits<double>::infinity();

  double operator()(double t) const {
    switch (kind) {
      case Kind::Constant: return 1.0;
      case Kind::Ramp: return t <= t0 ? 0.0 : (t >= t1 ? 1.0 : (t - t0) / (t1 - t0));
      case Kind::Hat:
        if (t <= t0 || t >= t2) return 0.0;
        return t <= t1 ? (t - t0) / (t1 - t0) : (t2 - t) / (t2 - t1);
      case Kind::Step: return (t >= t0 && t < t1) ? 1.0 : 0.0;
    }
    return 0.0;
  }

  /// From effect parameters tf_type, tf_t0, tf_t1, tf_t2 (default: constant).
  static TimeFunction from(const EffectParams& p);
};

}  // namespace slidebeam
