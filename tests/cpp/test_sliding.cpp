// SPDX-License-Identifier: MIT
/// The carrier-curve kernels of the sliding joint: the exact discrete derivative across knots
/// and its derivative, and the closest-point projection.
#include "kernels/ancf_sliding.hpp"
#include "kernels/sliding.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace slidebeam::sliding;

namespace {
constexpr int kSpans = 4;
constexpr double kL = 2.0;  // knots at 0.5, 1.0, 1.5

/// Global basis N_A(s) (or a derivative) of every control point, on the span that contains s.
std::vector<double> global_basis(double s, int k) {
  Weights w;
  w.reset(0, kSpans + 2);
  add_basis(kSpans, kL, span_of(kSpans, kL, s), s, k, 1.0, w);
  return w.w;
}
}  // namespace

struct Interval {
  double s0, s1;
};
class DifferenceQuotient : public ::testing::TestWithParam<Interval> {};

/// D_A = (N_A(s1) - N_A(s0)) / (s1 - s0) exactly, for intervals inside a span, across one or
/// several knots, in either direction.
TEST_P(DifferenceQuotient, EqualsTheSecantOfTheGlobalBasis) {
  const auto [s0, s1] = GetParam();
  Weights D, dD;
  difference_quotient(kSpans, kL, s0, s1, D, dD);
  const auto N0 = global_basis(s0, 0), N1 = global_basis(s1, 0);
  double sum = 0.0;
  for (int A = 0; A < kSpans + 2; ++A) {
    EXPECT_NEAR(D.at(A), (N1[A] - N0[A]) / (s1 - s0), 1e-12) << "control point " << A;
    sum += D.at(A);
  }
  EXPECT_NEAR(sum, 0.0, 1e-12);  // partition of unity
}

/// dD/ds1 against central differences of D in s1 (away from knots, where N'' jumps).
TEST_P(DifferenceQuotient, DerivativeMatchesFiniteDifferences) {
  const auto [s0, s1] = GetParam();
  Weights D, dD, Dp, dDp, Dm, dDm;
  difference_quotient(kSpans, kL, s0, s1, D, dD);
  const double h = std::min(1e-6, 1e-4 * std::abs(s1 - s0));  // D varies on the scale of s1 - s0
  difference_quotient(kSpans, kL, s0, s1 + h, Dp, dDp);
  difference_quotient(kSpans, kL, s0, s1 - h, Dm, dDm);
  for (int A = 0; A < kSpans + 2; ++A) EXPECT_NEAR(dD.at(A), (Dp.at(A) - Dm.at(A)) / (2 * h), 1e-6) << "control point " << A;
}

INSTANTIATE_TEST_SUITE_P(Intervals, DifferenceQuotient,
                         ::testing::Values(Interval{0.1, 0.3}, Interval{0.45, 0.62}, Interval{0.62, 0.45},
                                           Interval{0.3, 1.7}, Interval{1.9, 0.2}, Interval{0.4999, 0.5003},
                                           Interval{1.2, 2.1}, Interval{-0.05, 0.3}));

/// A tiny step across a knot: the quotient is the (continuous) N' there, no cancellation.
TEST(DifferenceQuotientLimit, TinyStepAcrossAKnotIsStable) {
  Weights D, dD;
  difference_quotient(kSpans, kL, 0.5 - 1e-14, 0.5 + 1e-14, D, dD);
  const auto dN = global_basis(0.5, 1);
  for (int A = 0; A < kSpans + 2; ++A) EXPECT_NEAR(D.at(A), dN[A], 1e-12);
  difference_quotient(kSpans, kL, 0.7, 0.7, D, dD);  // s1 == s0: N'(s0)
  const auto dN7 = global_basis(0.7, 1);
  for (int A = 0; A < kSpans + 2; ++A) EXPECT_NEAR(D.at(A), dN7[A], 1e-14);
}

TEST(Projection, FindsTheClosestPointOfACurvedCarrier) {
  // a parabola-like control polygon; the point lies off the curve along its normal
  const std::vector<double> x = {0, 0, 0, 0.25, 0.2, 0, 0.75, 0.4, 0, 1.25, 0.4, 0, 1.75, 0.2, 0, 2.0, 0, 0};
  const double s_true = 1.3;
  Weights N, dN;
  N.reset(0, 6);
  dN.reset(0, 6);
  add_basis(kSpans, kL, span_of(kSpans, kL, s_true), s_true, 0, 1.0, N);
  add_basis(kSpans, kL, span_of(kSpans, kL, s_true), s_true, 1, 1.0, dN);
  double c[3] = {0, 0, 0}, t[3] = {0, 0, 0};
  for (int A = 0; A < 6; ++A)
    for (int k = 0; k < 3; ++k) c[k] += N.at(A) * x[3 * A + k], t[k] += dN.at(A) * x[3 * A + k];
  const double p[3] = {c[0] - 0.01 * t[1], c[1] + 0.01 * t[0], c[2] + 0.0};  // 0.01 |t| off, along the normal
  const auto r = project(kSpans, kL, x.data(), 3, p);
  EXPECT_NEAR(r[0], s_true, 1e-10);
  EXPECT_NEAR(r[1], 0.01 * std::hypot(t[0], t[1]), 1e-10);
}

// A diverging Newton iterate can make s non-finite: the blocks a step touches still cover the
// spans of both ends (min/max of a NaN picked one end only, and the basis of the other was
// written outside the weights).
TEST(TouchedBlocks, CoverBothEndsWhenSIsNotFinite) {
  const double nan = std::nan("");
  const double inf = std::numeric_limits<double>::infinity();
  for (const double s1 : {nan, inf, -inf}) {
    const auto r = touched_cps(8, 2.0, 1.3, s1);  // s0 in span 5
    EXPECT_LE(r[0], std::min(5, span_of(8, 2.0, s1)));
    EXPECT_GE(r[1], std::max(5, span_of(8, 2.0, s1)) + 2);
    const auto a = hermite::touched_blocks(8, 2.0, 1.3, s1);  // element 5: blocks 10 .. 13
    EXPECT_LE(a[0], 2 * std::min(5, hermite::element_of(8, 2.0, s1)));
    EXPECT_GE(a[1], 2 * std::max(5, hermite::element_of(8, 2.0, s1)) + 3);
  }
}
