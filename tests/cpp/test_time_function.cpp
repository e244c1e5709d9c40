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
