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

namespace {
/// Three carriers joined end to end: a B-spline beam of 3 spans (drawn forwards), an ANCF cable of
/// 2 elements drawn from the far side (reversed) and a B-spline beam of 4 spans (forwards).
Track three_piece_track() {
  Track t;
  t.append({Curve::Kind::BSpline, 3, 1.5}, false);
  t.append({Curve::Kind::Hermite, 2, 1.0}, true);
  t.append({Curve::Kind::BSpline, 4, 2.0}, false);
  return t;
}

/// Track blocks y_A whose junction blocks meet (the first piece's last block, the cable's r at
/// its end node, which the reversed piece meets first; its r at node 0 and the last piece's
/// first block): random otherwise.
std::vector<double> joined_blocks(const Track& t) {
  std::vector<double> y(static_cast<size_t>(t.n_blocks()));
  for (size_t i = 0; i < y.size(); ++i) y[i] = std::sin(1.7 * static_cast<double>(i) + 0.3) + 0.1 * static_cast<double>(i);
  // piece 0: blocks 0..4; piece 1 (reversed): track blocks 5..10 = local 5..0 (r'2, r2, r'1, r1, r'0, r0);
  // piece 2: blocks 11..16
  y[6] = y[4];    // the cable's end node r2 meets the first beam's end
  y[11] = y[10];  // the last beam's start meets the cable's r0
  return y;
}

double curve_at(const Track& t, const std::vector<double>& y, double s, int k) {
  Weights w;
  w.reset(0, t.n_blocks());
  t.add_basis(t.span_of(s), s, k, 1.0, w);
  double c = 0.0;
  for (int A = 0; A < t.n_blocks(); ++A) c += w.at(A) * y[static_cast<size_t>(A)];
  return c;
}
}  // namespace

/// A track of one forward piece is its curve.
TEST(Track, OnePieceIsItsCurve) {
  Track t;
  const Curve c{Curve::Kind::BSpline, kSpans, kL};
  t.append(c, false);
  Weights D, dD, Dc, dDc;
  t.difference_quotient(0.3, 1.7, D, dD);
  c.difference_quotient(0.3, 1.7, Dc, dDc);
  EXPECT_EQ(D.lo, Dc.lo);
  EXPECT_EQ(D.w, Dc.w);
  EXPECT_EQ(dD.w, dDc.w);
}

/// The pieces meet: the curve is continuous across the junctions, its slope runs the way of s on
/// the reversed piece, and the basis is a partition of unity everywhere.
TEST(Track, IsContinuousAcrossJunctionsAndReversesTheReversedPiece) {
  const Track t = three_piece_track();
  EXPECT_DOUBLE_EQ(t.length(), 4.5);
  const std::vector<double> y = joined_blocks(t);
  for (double s : {1.5, 2.5}) EXPECT_NEAR(curve_at(t, y, s - 1e-12, 0), curve_at(t, y, s + 1e-12, 0), 1e-10);
  const double h = 1e-6;
  for (double s : {0.4, 1.8, 2.2, 3.9})
    EXPECT_NEAR(curve_at(t, y, s, 1), (curve_at(t, y, s + h, 0) - curve_at(t, y, s - h, 0)) / (2 * h), 1e-7) << s;
  std::vector<double> ones(static_cast<size_t>(t.n_blocks()), 0.0);
  for (int A = 0; A < t.n_blocks(); ++A)
    if (t.offset_of_block(A) == 0) ones[static_cast<size_t>(A)] = 1.0;  // positions 1, slopes 0
  for (double s : {0.2, 1.5, 1.9, 2.5, 4.4}) EXPECT_NEAR(curve_at(t, ones, s, 0), 1.0, 1e-14) << s;
  EXPECT_EQ(t.cp_of_block(5), 2);      // the reversed cable's last node comes first along s
  EXPECT_EQ(t.offset_of_block(5), 3);  // its slope block r'2, then r2
  EXPECT_EQ(t.offset_of_block(6), 0);
  EXPECT_EQ(t.local_cp(t.touched_cps(1.6, 1.6)[0]), 2);
}

/// sum_A D_A y_A (s1 - s0) = c(s1) - c(s0) across one and two junctions, either way, and dD/ds1
/// against central differences of D.
TEST(Track, DifferenceQuotientIsTheSecantAcrossJunctions) {
  const Track t = three_piece_track();
  const std::vector<double> y = joined_blocks(t);
  for (const Interval iv : {Interval{1.2, 1.9}, Interval{1.9, 1.2}, Interval{0.7, 3.3}, Interval{4.1, 1.4},
                            Interval{1.4999, 1.5002}, Interval{2.3, 2.45}}) {
    Weights D, dD, Dp, dDp, Dm, dDm;
    t.difference_quotient(iv.s0, iv.s1, D, dD);
    double secant = 0.0, sum = 0.0;
    for (int A = D.lo; A < D.lo + static_cast<int>(D.w.size()); ++A) {
      secant += D.at(A) * y[static_cast<size_t>(A)];
      if (t.offset_of_block(A) == 0) sum += D.at(A);
    }
    EXPECT_NEAR(secant * (iv.s1 - iv.s0), curve_at(t, y, iv.s1, 0) - curve_at(t, y, iv.s0, 0), 1e-12) << iv.s0 << " " << iv.s1;
    EXPECT_NEAR(sum, 0.0, 1e-11);
    const double h = std::min(1e-6, 1e-4 * std::abs(iv.s1 - iv.s0));
    t.difference_quotient(iv.s0, iv.s1 + h, Dp, dDp);
    t.difference_quotient(iv.s0, iv.s1 - h, Dm, dDm);
    for (int A = 0; A < t.n_blocks(); ++A)
      EXPECT_NEAR(dD.at(A), (Dp.at(A) - Dm.at(A)) / (2 * h), 2e-5 * std::max(1.0, std::abs(dD.at(A))))
          << iv.s0 << " " << iv.s1 << " block " << A;
  }
}
