// SPDX-License-Identifier: MIT
#include "kernels/bspline.hpp"

#include <gtest/gtest.h>

using namespace slidebeam::bspline;

class BSplineSpans : public ::testing::TestWithParam<int> {};

TEST_P(BSplineSpans, PartitionOfUnityAndLinearReproduction) {
  const int n = GetParam();
  for (int i = 0; i <= 200; ++i) {
    const double xi = i / 200.0;
    const auto b = basis(n, xi);
    double sum = 0, dsum = 0, ddsum = 0, lin = 0, dlin = 0;
    for (int a = 0; a < 3; ++a) {
      sum += b.N[a];
      dsum += b.dN[a];
      ddsum += b.ddN[a];
      lin += b.N[a] * greville(n, b.span + a);  // Greville abscissae reproduce xi
      dlin += b.dN[a] * greville(n, b.span + a);
      EXPECT_GE(b.N[a], -1e-15);
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_NEAR(dsum, 0.0, 1e-12);
    EXPECT_NEAR(ddsum, 0.0, 1e-10);
    EXPECT_NEAR(lin, xi, 1e-14);
    EXPECT_NEAR(dlin, 1.0, 1e-12);
  }
}

TEST_P(BSplineSpans, DerivativesMatchFiniteDifferences) {
  const int n = GetParam();
  const double h = 1e-6;
  for (int i = 1; i < 97; ++i) {
    const double xi = i / 97.0;
    const int e = find_span(n, xi);
    const auto b = basis_on_span(n, e, xi);
    const auto bp = basis_on_span(n, e, xi + h), bm = basis_on_span(n, e, xi - h);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(b.dN[a], (bp.N[a] - bm.N[a]) / (2 * h), 1e-7 * n);
      EXPECT_NEAR(b.ddN[a], (bp.dN[a] - bm.dN[a]) / (2 * h), 1e-6 * n * n);
    }
  }
}

TEST_P(BSplineSpans, C1AcrossKnots) {
  const int n = GetParam();
  for (int e = 1; e < n; ++e) {
    const double xi = static_cast<double>(e) / n;
    const auto L = basis_on_span(n, e - 1, xi), R = basis_on_span(n, e, xi);
    // global functions: left span's a -> cp e-1+a, right span's a -> cp e+a
    for (int cp = e - 1; cp <= e + 2; ++cp) {
      const double NL = (cp - (e - 1) >= 0 && cp - (e - 1) < 3) ? L.N[cp - (e - 1)] : 0.0;
      const double NR = (cp - e >= 0 && cp - e < 3) ? R.N[cp - e] : 0.0;
      const double dL = (cp - (e - 1) >= 0 && cp - (e - 1) < 3) ? L.dN[cp - (e - 1)] : 0.0;
      const double dR = (cp - e >= 0 && cp - e < 3) ? R.dN[cp - e] : 0.0;
      EXPECT_NEAR(NL, NR, 1e-14);
      EXPECT_NEAR(dL, dR, 1e-12);
    }
  }
}

TEST(BSpline, EndInterpolationAndBernsteinCase) {
  auto b0 = basis(4, 0.0), b1 = basis(4, 1.0);
  EXPECT_EQ(b1.span, 3);
  EXPECT_DOUBLE_EQ(b0.N[0], 1.0);
  EXPECT_DOUBLE_EQ(b1.N[2], 1.0);
  const auto b = basis(1, 0.3);  // one span: Bernstein polynomials
  EXPECT_NEAR(b.N[0], 0.49, 1e-15);
  EXPECT_NEAR(b.N[1], 0.42, 1e-15);
  EXPECT_NEAR(b.N[2], 0.09, 1e-15);
  EXPECT_DOUBLE_EQ(greville(4, 1), 0.125);
}

INSTANTIATE_TEST_SUITE_P(Spans, BSplineSpans, ::testing::Values(1, 2, 4, 7));
