// SPDX-License-Identifier: MIT
#pragma once
/// @file Quadratic B-splines on open uniform knot vectors (Piegl & Tiller A2.1/A2.3,
/// specialised to degree 2). Pure functions: no PETSc, no allocation.

#include <array>

namespace slidebeam::bspline {

/// Values and first/second derivatives (d/dxi) of the 3 basis functions that are
/// non-zero on one knot span. Span e couples control points e, e+1, e+2.
struct SpanBasis {
  int span = 0;
  std::array<double, 3> N{};
  std::array<double, 3> dN{};
  std::array<double, 3> ddN{};
};

/// Knot span of parameter xi in [0,1] for n_spans uniform spans. xi == 1 belongs to the last span
/// (the closed right end), so the basis interpolates the last control point there.
int find_span(int n_spans, double xi);

/// Basis on a given span, evaluated at xi (xi may lie outside the span: the span's polynomial is
/// extended, which the sliding joint's difference quotients rely on).
SpanBasis basis_on_span(int n_spans, int span, double xi);

/// Basis at xi on the span that contains it.
inline SpanBasis basis(int n_spans, double xi) { return basis_on_span(n_spans, find_span(n_spans, xi), xi); }

/// Greville abscissa of control point a (0 <= a <= n_spans+1): mean of its two interior knots.
double greville(int n_spans, int a);

/// Weight c of the director-interpolation correction (docs/theory.md, "Directors between control
/// points") at xi on span `span`, in units of the parameter squared (times L^2 for arc length):
///   c = (v + m3' / 6) / (1 + v'' / 2),   v = sum_a N_a (g_a - xi)^2,  m3 = sum_a N_a (g_a - xi)^3,
/// with g_a the Greville abscissae. v is the interpolated directors' stretch per squared
/// curvature, m3 / 6 the twist lag of their angle; dividing by 1 + v''/2 undoes the stretch's
/// share in the correction's own form, which counts in the end spans, where v varies.
double director_correction_weight(int n_spans, int span, double xi);

/// Knot value u_i of the open uniform knot vector {0,0,0,1/n,...,(n-1)/n,1,1,1}.
double knot(int n_spans, int i);

}  // namespace slidebeam::bspline
