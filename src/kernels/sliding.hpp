// SPDX-License-Identifier: MIT
#pragma once
/// @file The carrier curve of a sliding joint: basis weights of its control points at a sliding
/// coordinate, the exact discrete derivative in s across knots, and the closest-point projection.
/// Pure functions of the carrier's knot vector (n_spans, length L; xi = s / L); no PETSc.

#include <array>
#include <cstddef>
#include <vector>

namespace slidebeam::sliding {

/// Weights of carrier control points lo .. lo + size - 1 (all other control points: 0).
struct Weights {
  int lo = 0;
  std::vector<double> w;
  void reset(int lo_cp, int n) {
    lo = lo_cp;
    w.assign(static_cast<std::size_t>(n), 0.0);
  }
  double at(int cp) const { return (cp < lo || cp >= lo + static_cast<int>(w.size())) ? 0.0 : w[static_cast<std::size_t>(cp - lo)]; }
};

/// Span of s (clamped to the first/last span; beyond the ends the end span's polynomial extends).
int span_of(int n_spans, double L, double s);

/// w += f * d^k N_A / ds^k (s), A over the 3 control points of span `span` (k = 0, 1, 2).
void add_basis(int n_spans, double L, int span, double s, int k, double f, Weights& w);

/// Exact discrete derivative of the basis between s0 and s1 (formulation.md section 6):
///   D_A = (N_A(s1) - N_A(s0)) / (s1 - s0)   and   dD_A / ds1,
/// evaluated without dividing by s1 - s0: [s0, s1] is split at knots, D is the length-weighted
/// mean of N'_A at the pieces' midpoints, and dD/ds1 = (1/ds^2) int N''(t) |t - s0| dt is summed
/// piecewise (N'' is constant on a span). Within one span D = N'((s0+s1)/2), dD/ds1 = N''/2.
/// D and dD are reset to the control points the interval touches.
void difference_quotient(int n_spans, double L, double s0, double s1, Weights& D, Weights& dD);

/// First and last carrier control point touched by [min(s0,s1), max(s0,s1)] (span range + 2).
std::array<int, 2> touched_cps(int n_spans, double L, double s0, double s1);

/// Closest point of span e of the curve sum_A N_A(s) x_A to p (samples, then Newton on
/// (c(s) - p) . c'(s) = 0 inside the span). Returns {s, distance}.
std::array<double, 2> project_on_span(int n_spans, double L, const double* x, int stride, int e, const double p[3]);

/// Closest point of the curve sum_A N_A(s) x_A (x_A: control point positions, 3 values each
/// with the given stride) to the point p: search every span (samples, then Newton on
/// (c(s) - p) . c'(s) = 0 inside the span). Returns {s, distance}.
std::array<double, 2> project(int n_spans, double L, const double* x, int stride, const double p[3]);

}  // namespace slidebeam::sliding
