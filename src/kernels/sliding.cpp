// SPDX-License-Identifier: MIT
#include "kernels/sliding.hpp"

#include "kernels/ancf_sliding.hpp"
#include "kernels/bspline.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slidebeam::sliding {

int span_of(int n_spans, double L, double s) { return bspline::find_span(n_spans, s / L); }

void add_basis(int n_spans, double L, int span, double s, int k, double f, Weights& w) {
  const auto b = bspline::basis_on_span(n_spans, span, s / L);
  const double scale = k == 0 ? 1.0 : (k == 1 ? 1.0 / L : 1.0 / (L * L));  // d/ds = (1/L) d/dxi
  for (int a = 0; a < 3; ++a) {
    const double v = k == 0 ? b.N[a] : (k == 1 ? b.dN[a] : b.ddN[a]);
    w.w[static_cast<size_t>(span + a - w.lo)] += f * scale * v;
  }
}

std::array<int, 2> touched_cps(int n_spans, double L, double s0, double s1) {
  // spans of both ends, not of min/max: a non-finite s (a diverging iterate) compares false
  const int a = span_of(n_spans, L, s0), b = span_of(n_spans, L, s1);
  return {std::min(a, b), std::max(a, b) + 2};
}

void difference_quotient(int n_spans, double L, double s0, double s1, Weights& D, Weights& dD) {
  const auto r = touched_cps(n_spans, L, s0, s1);
  D.reset(r[0], r[1] - r[0] + 1);
  dD.reset(r[0], r[1] - r[0] + 1);
  const double lo = std::min(s0, s1), hi = std::max(s0, s1), ds = hi - lo;
  if (ds == 0.0) {
    const int e = span_of(n_spans, L, s0);
    add_basis(n_spans, L, e, s0, 1, 1.0, D);
    add_basis(n_spans, L, e, s0, 2, 0.5, dD);
    return;
  }
  // pieces [a, b] between consecutive interior knots inside (lo, hi)
  double a = lo;
  while (a < hi) {
    int e = span_of(n_spans, L, a);
    // right end of span e (interior knots only; the last span extends to +inf); a knot that
    // rounding left at or below a belongs to the piece before
    double b = e + 1 < n_spans ? L * (e + 1) / n_spans : hi;
    while (b <= a && e + 1 < n_spans) b = ++e + 1 < n_spans ? L * (e + 1) / n_spans : hi;
    b = std::min(b, hi);
    if (b <= a) break;
    const int span = span_of(n_spans, L, 0.5 * (a + b));
    const double len = (b - a) / ds, mid = 0.5 * (a + b);
    add_basis(n_spans, L, span, mid, 1, len, D);
    add_basis(n_spans, L, span, mid, 2, len * std::abs(mid - s0) / ds, dD);
    a = b;
  }
}

std::array<double, 2> project_on_span(int n_spans, double L, const double* x, int stride, int e, const double p[3]) {
  auto eval = [&](double s, double c[3], double dc[3], double ddc[3]) {
    const auto b = bspline::basis_on_span(n_spans, e, s / L);
    for (int k = 0; k < 3; ++k) c[k] = dc[k] = ddc[k] = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double* xa = x + static_cast<size_t>(stride) * static_cast<size_t>(e + a);
      for (int k = 0; k < 3; ++k) {
        c[k] += b.N[a] * xa[k];
        dc[k] += b.dN[a] / L * xa[k];
        ddc[k] += b.ddN[a] / (L * L) * xa[k];
      }
    }
  };
  const double sa = L * e / n_spans, sb = L * (e + 1) / n_spans;
  return closest_on_piece(sa, sb, L, p, eval);
}

std::array<double, 2> project(int n_spans, double L, const double* x, int stride, const double p[3]) {
  double best_s = 0.0, best_d = std::numeric_limits<double>::infinity();
  for (int e = 0; e < n_spans; ++e) {
    const auto r = project_on_span(n_spans, L, x, stride, e, p);
    if (r[1] < best_d) best_d = r[1], best_s = r[0];
  }
  return {best_s, best_d};
}

int Curve::span_of(double s) const {
  return kind == Kind::Hermite ? hermite::element_of(n_spans, L, s) : sliding::span_of(n_spans, L, s);
}

void Curve::add_basis(int span, double s, int k, double f, Weights& w) const {
  if (kind == Kind::Hermite) hermite::add_basis(n_spans, L, span, s, k, f, w);
  else sliding::add_basis(n_spans, L, span, s, k, f, w);
}

std::array<int, 2> Curve::touched_blocks(double s0, double s1) const {
  return kind == Kind::Hermite ? hermite::touched_blocks(n_spans, L, s0, s1) : sliding::touched_cps(n_spans, L, s0, s1);
}

void Curve::difference_quotient(double s0, double s1, Weights& D, Weights& dD) const {
  if (kind == Kind::Hermite) hermite::difference_quotient(n_spans, L, s0, s1, D, dD);
  else sliding::difference_quotient(n_spans, L, s0, s1, D, dD);
}

std::array<double, 2> Curve::project_on_span(const double* x, int stride, int e, const double p[3]) const {
  return kind == Kind::Hermite ? hermite::project_on_element(n_spans, L, x, stride, e, p)
                               : sliding::project_on_span(n_spans, L, x, stride, e, p);
}

std::array<double, 2> Curve::project(const double* x, int stride, const double p[3]) const {
  double best_s = 0.0, best_d = std::numeric_limits<double>::infinity();
  for (int e = 0; e < n_spans; ++e) {
    const auto r = project_on_span(x, stride, e, p);
    if (r[1] < best_d) best_d = r[1], best_s = r[0];
  }
  return {best_s, best_d};
}

}  // namespace slidebeam::sliding
