// SPDX-License-Identifier: MIT
#pragma once
/// @file Load amplitude over time: constant, ramp, smooth_ramp, hat, step, sine, table, spline
/// (scene `time_function`).

#include "model/effect.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace slidebeam {

struct TimeFunction {
  enum class Kind { Constant, Ramp, SmoothRamp, Hat, Step, Sine, Table, Spline } kind = Kind::Constant;
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity(), t2 = std::numeric_limits<double>::infinity();
  /// Sine: offset + amplitude r(t) sin(2 pi frequency t + phase) (frequency in Hz, phase in rad),
  /// r the smooth ramp from 0 at t = 0 to 1 at t1 (1 throughout if t1 is infinite): a motion
  /// that starts from rest.
  double amplitude = 1.0, frequency = 0.0, phase = 0.0, offset = 0.0;
  /// Table: piecewise linear through (times[i], values[i]), times strictly increasing; constant
  /// (the first or last value) beyond the ends. Spline: the cubic spline through them with zero
  /// slope at both ends (curvatures: the second derivatives at the times), so that its rate and
  /// acceleration are continuous inside and its rate at the ends, where it goes on constant.
  std::vector<double> times, values, curvatures;

  double operator()(double t) const {
    const auto smooth = [](double u) { return u * u * u * (10.0 + u * (-15.0 + 6.0 * u)); };
    switch (kind) {
      case Kind::Constant: return 1.0;
      case Kind::Ramp: return t <= t0 ? 0.0 : (t >= t1 ? 1.0 : (t - t0) / (t1 - t0));
      case Kind::SmoothRamp: {  // 10u^3 - 15u^4 + 6u^5: rate and its rate continuous at both ends
        if (t <= t0) return 0.0;
        if (t >= t1) return 1.0;
        return smooth((t - t0) / (t1 - t0));
      }
      case Kind::Hat:
        if (t <= t0 || t >= t2) return 0.0;
        return t <= t1 ? (t - t0) / (t1 - t0) : (t2 - t) / (t2 - t1);
      case Kind::Step: return (t >= t0 && t < t1) ? 1.0 : 0.0;
      case Kind::Sine: {
        const double fade = std::isinf(t1) || t >= t1 ? 1.0 : t <= 0.0 ? 0.0 : smooth(t / t1);
        return offset + amplitude * fade * std::sin(6.283185307179586 * frequency * t + phase);
      }
      case Kind::Table:
      case Kind::Spline: {
        if (t <= times.front()) return values.front();
        if (t >= times.back()) return values.back();
        const size_t i = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
        const double h = times[i] - times[i - 1], b = (t - times[i - 1]) / h, a = 1.0 - b;
        const double linear = a * values[i - 1] + b * values[i];
        if (kind == Kind::Table) return linear;
        return linear + ((a * a * a - a) * curvatures[i - 1] + (b * b * b - b) * curvatures[i]) * h * h / 6.0;
      }
    }
    return 0.0;
  }

  /// From effect parameters tf_type, tf_t0, tf_t1, tf_t2; sine: tf_amplitude, tf_frequency,
  /// tf_phase, tf_offset; table and spline: the vectors tf_times and tf_values (default: constant).
  /// Throws std::invalid_argument for an unknown type or invalid parameters.
  static TimeFunction from(const EffectParams& p);
  /// The spline's second derivatives at the times, zero slope at both ends (a tridiagonal solve).
  static std::vector<double> spline_curvatures(const std::vector<double>& times, const std::vector<double>& values);
};

}  // namespace slidebeam
