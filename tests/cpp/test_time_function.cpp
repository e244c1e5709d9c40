// SPDX-License-Identifier: MIT
// Time functions (scene `time_function`): the values of every kind and the parameter checks of
// TimeFunction::from (the scene parser checks first; these guard the core's own API).
#include "model/time_function.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace slidebeam;

namespace {
EffectParams sine(double amplitude, double frequency, double phase, double offset) {
  EffectParams p;
  p.str["tf_type"] = "sine";
  p.num = {{"tf_amplitude", amplitude}, {"tf_frequency", frequency}, {"tf_phase", phase}, {"tf_offset", offset}};
  return p;
}
EffectParams table(std::vector<double> t, std::vector<double> v) {
  EffectParams p;
  p.str["tf_type"] = "table";
  p.vec = {{"tf_times", std::move(t)}, {"tf_values", std::move(v)}};
  return p;
}
}  // namespace

TEST(TimeFunction, Sine) {
  const TimeFunction f = TimeFunction::from(sine(2.0, 0.5, 0.3, -1.0));
  for (double t : {0.0, 0.1, 0.77, 3.2, -1.5})
    EXPECT_NEAR(f(t), -1.0 + 2.0 * std::sin(2.0 * M_PI * 0.5 * t + 0.3), 1e-14) << t;
  EXPECT_NEAR(f(0.5), -1.0 + 2.0 * std::sin(M_PI / 2 + 0.3), 1e-14);  // a quarter period
  EffectParams defaults;  // amplitude 1, phase 0, offset 0
  defaults.str["tf_type"] = "sine";
  defaults.num["tf_frequency"] = 2.0;
  EXPECT_NEAR(TimeFunction::from(defaults)(0.125), 1.0, 1e-15);
}

TEST(TimeFunction, TableIsPiecewiseLinearAndConstantBeyondTheEnds) {
  const TimeFunction f = TimeFunction::from(table({0.0, 1.0, 3.0}, {2.0, 4.0, -2.0}));
  EXPECT_DOUBLE_EQ(f(-5.0), 2.0);
  EXPECT_DOUBLE_EQ(f(0.0), 2.0);
  EXPECT_DOUBLE_EQ(f(0.25), 2.5);
  EXPECT_DOUBLE_EQ(f(1.0), 4.0);
  EXPECT_DOUBLE_EQ(f(2.0), 1.0);
  EXPECT_DOUBLE_EQ(f(3.0), -2.0);
  EXPECT_DOUBLE_EQ(f(10.0), -2.0);
  EXPECT_DOUBLE_EQ(TimeFunction::from(table({1.0}, {7.0}))(0.0), 7.0);  // one point: a constant
}

TEST(TimeFunction, SplineGoesThroughItsPointsWithContinuousRateAndAccelerationAndStartsAtRest) {
  EffectParams p = table({0.0, 0.1, 0.25, 0.3, 0.7}, {0.0, 2.0, -1.0, 0.5, 0.5});
  p.str["tf_type"] = "spline";
  const TimeFunction f = TimeFunction::from(p);
  const std::vector<double> t = {0.0, 0.1, 0.25, 0.3, 0.7}, v = {0.0, 2.0, -1.0, 0.5, 0.5};
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(f(t[i]), v[i], 1e-14);
  EXPECT_DOUBLE_EQ(f(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(f(5.0), 0.5);
  const double d = 1e-5;
  for (double e : {t.front(), t.back()}) {  // zero slope at the ends: the quotients fall with d
    const double side = e == t.front() ? 1.0 : -1.0;
    EXPECT_LT(std::abs(f(e + side * d) - f(e)), 0.11 * std::abs(f(e + side * 10 * d) - f(e)));
  }
  for (size_t i = 1; i + 1 < t.size(); ++i) {
    const double acc_left = (f(t[i]) - 2 * f(t[i] - d) + f(t[i] - 2 * d)) / (d * d);
    const double acc_right = (f(t[i] + 2 * d) - 2 * f(t[i] + d) + f(t[i])) / (d * d);
    EXPECT_NEAR(acc_left, acc_right, 1e-2 * (1.0 + std::abs(acc_left)));  // C2
    // C1: the one-sided quotients differ by the acceleration times d, not by a jump
    const double left = (f(t[i]) - f(t[i] - d)) / d, right = (f(t[i] + d) - f(t[i])) / d;
    EXPECT_NEAR(left, right, 2.0 * d * (1.0 + std::abs(acc_left)));
  }
  EffectParams two = table({1.0, 3.0}, {0.0, 2.0});  // two points: the smooth step 3u^2 - 2u^3
  two.str["tf_type"] = "spline";
  const TimeFunction g = TimeFunction::from(two);
  for (double u : {0.0, 0.25, 0.5, 0.9, 1.0}) EXPECT_NEAR(g(1.0 + 2.0 * u), 2.0 * (3 * u * u - 2 * u * u * u), 1e-14);
}

TEST(TimeFunction, InvalidParametersAreRefused) {
  EXPECT_THROW(TimeFunction::from(sine(1.0, 0.0, 0.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(TimeFunction::from(sine(1.0, -2.0, 0.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(TimeFunction::from(table({0.0, 1.0}, {1.0})), std::invalid_argument);
  EXPECT_THROW(TimeFunction::from(table({0.0, 0.0}, {1.0, 2.0})), std::invalid_argument);
  EXPECT_THROW(TimeFunction::from(table({1.0, 0.5}, {1.0, 2.0})), std::invalid_argument);
  EXPECT_THROW(TimeFunction::from(table({}, {})), std::invalid_argument);
  EffectParams unknown;
  unknown.str["tf_type"] = "square";
  EXPECT_THROW(TimeFunction::from(unknown), std::invalid_argument);
}
