// SPDX-License-Identifier: MIT
#include "kernels/bspline.hpp"

#include <algorithm>
#include <cmath>

namespace slidebeam::bspline {

double knot(int n_spans, int i) {
  // indices 0,1,2 -> 0 ; 3..n+1 -> (i-2)/n ; n+2.. -> 1
  if (i <= 2) return 0.0;
  if (i >= n_spans + 2) return 1.0;
  return static_cast<double>(i - 2) / n_spans;
}

int find_span(int n_spans, double xi) {
  // clamp before converting: a huge or non-finite xi (a diverging Newton iterate) must not
  // overflow the integer; its basis then carries the NaN/Inf into the residual
  const double f = std::floor(xi * n_spans);
  if (!(f > 0.0)) return 0;  // also NaN
  if (f >= n_spans - 1) return n_spans - 1;
  return static_cast<int>(f);
}

double greville(int n_spans, int a) { return 0.5 * (knot(n_spans, a + 1) + knot(n_spans, a + 2)); }

double director_correction_weight(int n_spans, int span, double xi) {
  // With sum_a N_a = 1 and sum_a N_a g_a = xi: m3' = sum_a N_a' d^3 - 3 v and
  // 1 + v''/2 = 1/2 sum_a N_a'' d^2, for d = g_a - xi.
  const SpanBasis b = basis_on_span(n_spans, span, xi);
  double v = 0.0, dm3 = 0.0, ddm2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double d = greville(n_spans, span + a) - xi;
    v += b.N[a] * d * d;
    dm3 += b.dN[a] * d * d * d;
    ddm2 += b.ddN[a] * d * d;
  }
  return (0.5 * v + dm3 / 6.0) / (0.5 * ddm2);
}

SpanBasis basis_on_span(int n_spans, int e, double xi) {
  // Cox-de Boor for p = 2 on span [u_{e+2}, u_{e+3}) of the full knot vector.
  const int i = e + 2;
  const double u[6] = {knot(n_spans, i - 2), knot(n_spans, i - 1), knot(n_spans, i),
                       knot(n_spans, i + 1), knot(n_spans, i + 2), knot(n_spans, i + 3)};
  // u[2] = left end of span, u[3] = right end.
  auto div = [](double a, double b) { return b == 0.0 ? 0.0 : a / b; };
  // degree 1 functions on this span: N_{i-1,1}, N_{i,1}
  const double h = u[3] - u[2];
  const double B1_0 = (u[3] - xi) / h;  // N_{i-1,1}
  const double B1_1 = (xi - u[2]) / h;  // N_{i,1}
  // degree 2: N_{i-2,2}, N_{i-1,2}, N_{i,2}
  SpanBasis b;
  b.span = e;
  const double a0 = div(u[3] - xi, u[3] - u[1]);
  const double a1 = div(xi - u[1], u[3] - u[1]);
  const double a2 = div(u[4] - xi, u[4] - u[2]);
  const double a3 = div(xi - u[2], u[4] - u[2]);
  b.N = {a0 * B1_0, a1 * B1_0 + a2 * B1_1, a3 * B1_1};
  // derivatives: N'_{j,2} = 2/(u_{j+2}-u_j) N_{j,1} - 2/(u_{j+3}-u_{j+1}) N_{j+1,1}
  const double c0 = div(2.0, u[3] - u[1]);  // for N_{i-1,1}
  const double c1 = div(2.0, u[4] - u[2]);  // for N_{i,1}
  b.dN = {-c0 * B1_0, c0 * B1_0 - c1 * B1_1, c1 * B1_1};
  // second derivatives are constant on the span: N'_{j,1} = +-1/h
  b.ddN = {c0 / h, -c0 / h - c1 / h, c1 / h};
  return b;
}

}  // namespace slidebeam::bspline
