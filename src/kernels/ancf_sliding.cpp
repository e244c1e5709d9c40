// SPDX-License-Identifier: MIT
#include "kernels/ancf_sliding.hpp"

#include "kernels/ancf_kernels.hpp"
#include "kernels/sliding.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slidebeam::sliding::hermite {

int element_of(int n_elements, double L, double s) {
  const double Le = L / n_elements;
  if (!(s > 0.0)) return 0;  // also NaN
  return std::clamp(static_cast<int>(std::floor(s / Le)), 0, n_elements - 1);
}

void add_basis(int n_elements, double L, int e, double s, int k, double f, Weights& w) {
  const double Le = L / n_elements;
  const auto b = kernels::ancf::hermite(s - e * Le, Le);
  const auto& v = k == 0 ? b.S : (k == 1 ? b.dS : b.ddS);
  for (int a = 0; a < 4; ++a) w.w[static_cast<size_t>(2 * e + a - w.lo)] += f * v[static_cast<size_t>(a)];
}

std::array<int, 2> touched_blocks(int n_elements, double L, double s0, double s1) {
  // elements of both ends, not of min/max: a non-finite s (a diverging iterate) compares false
  const int a = element_of(n_elements, L, s0), b = element_of(n_elements, L, s1);
  return {2 * std::min(a, b), 2 * std::max(a, b) + 3};
}

void difference_quotient(int n_elements, double L, double s0, double s1, Weights& D, Weights& dD) {
  const auto r = touched_blocks(n_elements, L, s0, s1);
  D.reset(r[0], r[1] - r[0] + 1);
  dD.reset(r[0], r[1] - r[0] + 1);
  const double lo = std::min(s0, s1), hi = std::max(s0, s1), ds = hi - lo;
  if (ds == 0.0) {
    const int e = element_of(n_elements, L, s0);
    hermite::add_basis(n_elements, L, e, s0, 1, 1.0, D);
    hermite::add_basis(n_elements, L, e, s0, 2, 0.5, dD);
    return;
  }
  const double Le = L / n_elements;
  const double g = 0.5 / std::sqrt(3.0);  // 2-point Gauss on [-1/2, 1/2], weights 1/2
  double a = lo;
  while (a < hi) {
    // pieces end at interior nodes (the last element extends to +inf, the first to -inf)
    int e = element_of(n_elements, L, a);
    double b = e + 1 < n_elements ? Le * (e + 1) : hi;
    while (b <= a && e + 1 < n_elements) b = ++e + 1 < n_elements ? Le * (e + 1) : hi;  // rounding at a node
    b = std::min(b, hi);
    if (b <= a) break;
    // Gauss points as offsets u from lo (a - lo, b - a and hi - lo are exact differences of
    // nearby numbers), so |t - s0| / ds keeps its relative accuracy for tiny steps
    const double mid = 0.5 * (a + b), len = (b - a) / ds, a_off = a - lo;
    const int el = element_of(n_elements, L, mid);
    for (const double f : {0.5 - g, 0.5 + g}) {
      const double u = a_off + f * (b - a), t = lo + u;
      const double dist = s0 == lo ? u : ds - u;  // |t - s0|
      hermite::add_basis(n_elements, L, el, t, 1, 0.5 * len, D);
      hermite::add_basis(n_elements, L, el, t, 2, 0.5 * len * dist / ds, dD);
    }
    a = b;
  }
}

std::array<std::array<double, 3>, 4> bezier_points(int n_elements, double L, const double* x, int stride, int e) {
  const double Le = L / n_elements;
  const double* n1 = x + static_cast<size_t>(stride) * static_cast<size_t>(e);
  const double* n2 = n1 + stride;
  std::array<std::array<double, 3>, 4> b{};
  for (int k = 0; k < 3; ++k) {
    b[0][k] = n1[k];
    b[1][k] = n1[k] + Le * n1[3 + k] / 3.0;
    b[2][k] = n2[k] - Le * n2[3 + k] / 3.0;
    b[3][k] = n2[k];
  }
  return b;
}

std::array<double, 2> project_on_element(int n_elements, double L, const double* x, int stride, int e, const double p[3]) {
  const double Le = L / n_elements;
  const double* n1 = x + static_cast<size_t>(stride) * static_cast<size_t>(e);
  const double* n2 = n1 + stride;
  auto eval = [&](double s, double c[3], double dc[3], double ddc[3]) {
    const auto h = kernels::ancf::hermite(s - e * Le, Le);
    for (int k = 0; k < 3; ++k) {
      const double y[4] = {n1[k], n1[3 + k], n2[k], n2[3 + k]};
      c[k] = dc[k] = ddc[k] = 0.0;
      for (int a = 0; a < 4; ++a) {
        c[k] += h.S[static_cast<size_t>(a)] * y[a];
        dc[k] += h.dS[static_cast<size_t>(a)] * y[a];
        ddc[k] += h.ddS[static_cast<size_t>(a)] * y[a];
      }
    }
  };
  const double sa = Le * e, sb = e + 1 == n_elements ? L : Le * (e + 1);
  return closest_on_piece(sa, sb, L, p, eval);
}

}  // namespace slidebeam::sliding::hermite
