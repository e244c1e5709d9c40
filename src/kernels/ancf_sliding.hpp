// SPDX-License-Identifier: MIT
#pragma once
/// @file The centre line of an ANCF cable as the carrier of a sliding joint: cubic Hermite
/// elements (kernels/ancf_kernels.hpp), n_spans equal elements of length Le = L / n_spans.
///
/// The curve is c(s) = sum_j N_j(s) y_j over coordinate 3-blocks ("curve blocks"): block 2a is
/// r of node a, block 2a + 1 is r' of node a, so element e touches blocks 2e .. 2e + 3 with the
/// Hermite weights (S_1, S_2, S_3, S_4)(s - e Le). The curve is C1 across nodes (the slope
/// blocks are shared); N'' jumps at nodes and is linear, not constant, inside an element.
///
/// The exact discrete derivative D_j = (N_j(s1) - N_j(s0)) / (s1 - s0) and its derivative
/// dD_j/ds1 = (1/ds^2) int_[s0,s1] N_j''(t) |t - s0| dt are integrated piecewise over the
/// elements the interval touches, with 2-point Gauss rules on each piece: N' is quadratic and
/// N'' |t - s0| is quadratic on a piece, so both are exact, and nothing divides by s1 - s0 except
/// piece lengths and distances that are at most s1 - s0.
///
/// Pure functions; no PETSc.

#include "kernels/sliding.hpp"

#include <array>

namespace slidebeam::sliding::hermite {

/// Element of s: floor(s / Le), clamped to the first/last element (the cubic extends beyond).
int element_of(int n_elements, double L, double s);

/// w += f * d^k N_j / ds^k (s) over the 4 blocks of element e (k = 0, 1, 2).
void add_basis(int n_elements, double L, int e, double s, int k, double f, Weights& w);

/// First and last curve block touched by [min(s0,s1), max(s0,s1)]: 2 e0 .. 2 e1 + 3.
std::array<int, 2> touched_blocks(int n_elements, double L, double s0, double s1);

/// D and dD/ds1 of the interval s0 -> s1 (see the file comment); reset to the touched blocks.
/// s0 == s1: D = N'(s0), dD = N''(s0) / 2.
void difference_quotient(int n_elements, double L, double s0, double s1, Weights& D, Weights& dD);

/// The Bezier control points b0 = r1, b1 = r1 + Le r1'/3, b2 = r2 - Le r2'/3, b3 = r2 of
/// element e (nodes with the given stride, r at offset 0 and r' at offset 3): the element lies
/// in their convex hull, so their bounding box bounds it.
std::array<std::array<double, 3>, 4> bezier_points(int n_elements, double L, const double* x, int stride, int e);

/// Closest point of element e to p (samples, then Newton on (c - p) . c' = 0 inside the element).
/// Returns {s, distance}.
std::array<double, 2> project_on_element(int n_elements, double L, const double* x, int stride, int e, const double p[3]);

}  // namespace slidebeam::sliding::hermite
