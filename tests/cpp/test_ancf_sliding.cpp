// SPDX-License-Identifier: MIT
/// The Hermite (ANCF cable) carrier curve of the sliding joint: basis over curve blocks, the
/// exact discrete derivative across nodes and its derivative, the Bezier hull and projection.
#include "kernels/ancf_kernels.hpp"
#include "kernels/ancf_sliding.hpp"
#include "kernels/sliding.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace slidebeam::sliding;

namespace {
constexpr int kElements = 4;
constexpr double kL = 2.0;  // nodes at 0.5, 1.0, 1.5
const Curve kCurve{Curve::Kind::Hermite, kElements, kL};

/// Global basis N_j(s) (or a derivative) of every curve block, on the element that contains s.
std::vector<double> global_basis(double s, int k) {
  Weights w;
  w.reset(0, kCurve.n_blocks());
  kCurve.add_basis(kCurve.span_of(s), s, k, 1.0, w);
  return w.w;
}

/// Nodes (r, r') of a wound, stretched curve: stride 6.
std::vector<double> wound_nodes(int n, double L) {
  std::vector<double> x;
  for (int a = 0; a <= n; ++a) {
    const double s = L * a / n;
    const double v[6] = {std::cos(3 * s), std::sin(3 * s), 0.7 * s, -3 * std::sin(3 * s), 3 * std::cos(3 * s), 0.7};
    x.insert(x.end(), v, v + 6);
  }
  return x;
}
}  // namespace

TEST(HermiteCurve, BlocksAndBasisMatchTheCableElement) {
  EXPECT_EQ(kCurve.n_blocks(), 10);
  EXPECT_EQ(kCurve.n_cp(), 5);
  EXPECT_EQ(kCurve.cp_of_block(7), 3);
  EXPECT_EQ(kCurve.offset_of_block(7), 3);
  EXPECT_EQ(kCurve.offset_of_block(6), 0);
  const auto x = wound_nodes(kElements, kL);
  for (double s : {0.0, 0.3, 0.5, 0.77, 1.49, 2.0}) {
    const int e = kCurve.span_of(s);
    const auto N = global_basis(s, 0), dN = global_basis(s, 1);
    slidebeam::kernels::ancf::ElVec q = Eigen::Map<const slidebeam::kernels::ancf::ElVec>(x.data() + 6 * e);
    const auto c = slidebeam::kernels::ancf::evaluate(kL / kElements, s - e * kL / kElements, q);
    for (int k = 0; k < 3; ++k) {
      double r = 0, dr = 0;
      for (int j = 0; j < kCurve.n_blocks(); ++j) {
        const double y = x[static_cast<size_t>(6 * kCurve.cp_of_block(j) + kCurve.offset_of_block(j) + k)];
        r += N[static_cast<size_t>(j)] * y;
        dr += dN[static_cast<size_t>(j)] * y;
      }
      EXPECT_NEAR(r, c.r(k), 1e-14);
      EXPECT_NEAR(dr, c.dr(k), 1e-13);
    }
  }
  // C1 across a node: N and N' agree from both elements
  for (int k : {0, 1}) {
    Weights a, b;
    a.reset(0, kCurve.n_blocks());
    b.reset(0, kCurve.n_blocks());
    kCurve.add_basis(1, 1.0, k, 1.0, a);
    kCurve.add_basis(2, 1.0, k, 1.0, b);
    for (int j = 0; j < kCurve.n_blocks(); ++j) EXPECT_NEAR(a.at(j), b.at(j), 1e-14) << "block " << j << ", k " << k;
  }
}

struct Interval {
  double s0, s1;
};
class HermiteDifferenceQuotient : public ::testing::TestWithParam<Interval> {};

/// D_j = (N_j(s1) - N_j(s0)) / (s1 - s0) exactly, inside an element, across one or several nodes,
/// either direction, beyond the ends.
TEST_P(HermiteDifferenceQuotient, EqualsTheSecantOfTheGlobalBasis) {
  const auto [s0, s1] = GetParam();
  Weights D, dD;
  kCurve.difference_quotient(s0, s1, D, dD);
  const auto N0 = global_basis(s0, 0), N1 = global_basis(s1, 0);
  double sum_r = 0.0;
  for (int j = 0; j < kCurve.n_blocks(); ++j) {
    EXPECT_NEAR(D.at(j), (N1[j] - N0[j]) / (s1 - s0), 1e-12) << "block " << j;
    if (j % 2 == 0) sum_r += D.at(j);
  }
  EXPECT_NEAR(sum_r, 0.0, 1e-12);  // the position weights sum to 1 everywhere
}

/// dD/ds1 against central differences of D in s1.
TEST_P(HermiteDifferenceQuotient, DerivativeMatchesFiniteDifferences) {
  const auto [s0, s1] = GetParam();
  Weights D, dD, Dp, dDp, Dm, dDm;
  kCurve.difference_quotient(s0, s1, D, dD);
  const double h = std::min(1e-6, 1e-4 * std::abs(s1 - s0));
  kCurve.difference_quotient(s0, s1 + h, Dp, dDp);
  kCurve.difference_quotient(s0, s1 - h, Dm, dDm);
  for (int j = 0; j < kCurve.n_blocks(); ++j)
    EXPECT_NEAR(dD.at(j), (Dp.at(j) - Dm.at(j)) / (2 * h), 1e-6) << "block " << j;
}

INSTANTIATE_TEST_SUITE_P(Intervals, HermiteDifferenceQuotient,
                         ::testing::Values(Interval{0.1, 0.3}, Interval{0.45, 0.62}, Interval{0.62, 0.45},
                                           Interval{0.3, 1.7}, Interval{1.9, 0.2}, Interval{0.4999, 0.5003},
                                           Interval{1.2, 2.1}, Interval{-0.05, 0.3}));

/// Within an element, as s1 -> s0: D -> N'(s0), dD -> N''(s0)/2, with no blow-up.
TEST(HermiteCurve, DifferenceQuotientOfATinyStep) {
  Weights D, dD, D0, dD0;
  kCurve.difference_quotient(0.7, 0.7 + 1e-13, D, dD);
  kCurve.difference_quotient(0.7, 0.7, D0, dD0);
  for (int j = D0.lo; j < D0.lo + static_cast<int>(D0.w.size()); ++j) {
    EXPECT_NEAR(D.at(j), D0.at(j), 1e-11);
    EXPECT_NEAR(dD.at(j), dD0.at(j), 1e-9);
  }
}

TEST(HermiteCurve, BezierHullBoundsTheElementAndProjectionFindsPoints) {
  const auto x = wound_nodes(kElements, kL);
  for (int e = 0; e < kElements; ++e) {
    const auto b = hermite::bezier_points(kElements, kL, x.data(), 6, e);
    for (int i = 0; i <= 20; ++i) {
      const double s = kL / kElements * (e + i / 20.0);
      const auto N = global_basis(s, 0);
      for (int k = 0; k < 3; ++k) {
        double r = 0;
        for (int j = 0; j < kCurve.n_blocks(); ++j)
          r += N[static_cast<size_t>(j)] * x[static_cast<size_t>(6 * kCurve.cp_of_block(j) + kCurve.offset_of_block(j) + k)];
        const double lo = std::min({b[0][k], b[1][k], b[2][k], b[3][k]}), hi = std::max({b[0][k], b[1][k], b[2][k], b[3][k]});
        EXPECT_GE(r, lo - 1e-14);
        EXPECT_LE(r, hi + 1e-14);
      }
      if (i == 7) {  // a point on the curve projects onto itself
        double p[3];
        for (int k = 0; k < 3; ++k) {
          p[k] = 0;
          for (int j = 0; j < kCurve.n_blocks(); ++j)
            p[k] += N[static_cast<size_t>(j)] * x[static_cast<size_t>(6 * kCurve.cp_of_block(j) + kCurve.offset_of_block(j) + k)];
        }
        const auto r = kCurve.project(x.data(), 6, p);
        EXPECT_NEAR(r[0], s, 1e-9);
        EXPECT_LT(r[1], 1e-12);
      }
    }
  }
}
