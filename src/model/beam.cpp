// SPDX-License-Identifier: MIT
#include "model/beam.hpp"

#include <stdexcept>

namespace slidebeam {

namespace {
std::vector<kernels::GaussPoint> gauss_points(int n_spans, double L, kernels::Quadrature q) {
  std::array<double, 3> x{}, w{};
  const int ng = kernels::gauss_rule(q, x, w);
  std::vector<kernels::GaussPoint> gps;
  gps.reserve(static_cast<size_t>(n_spans * ng));
  const double h = 1.0 / n_spans;
  for (int e = 0; e < n_spans; ++e) {
    for (int g = 0; g < ng; ++g) {
      const double xi = (e + x[g]) * h;
      const auto b = bspline::basis_on_span(n_spans, e, xi);
      kernels::GaussPoint gp{};
      for (int a = 0; a < 3; ++a) {
        gp.N[a] = b.N[a];
        gp.dN[a] = b.dN[a] / L;  // d/ds = (1/L) d/dxi
      }
      gp.w = w[g] * h * L;  // ds = L dxi
      gps.push_back(gp);
    }
  }
  return gps;
}
}  // namespace

Beam::Beam(const BeamSpec& spec, int id, int first_cp) : spec_(spec), id_(id), first_cp_(first_cp) {
  if (spec.n_spans < 1) throw std::invalid_argument("beam '" + spec.name + "': spans must be >= 1");
  if (!(spec.length > 0)) throw std::invalid_argument("beam '" + spec.name + "': length must be > 0");
  if (spec.q_ref.size() != static_cast<size_t>(12 * n_cp()))
    throw std::invalid_argument("beam '" + spec.name + "': q_ref must hold 12 values per control point");
  const auto& s = spec.section;
  stiffness_ << s.EA, s.kGA2, s.kGA3, s.GJ, s.EI2, s.EI3;
  gps_ = gauss_points(spec.n_spans, spec.length, spec.quadrature);
  gps_full_ = gauss_points(spec.n_spans, spec.length, kernels::Quadrature::Full);
  n_gp_ = static_cast<int>(gps_.size()) / spec.n_spans;
  // Reference strains at the stiffness quadrature points: the reference configuration is stress free.
  eps0_.resize(gps_.size());
  for (int e = 0; e < spec.n_spans; ++e) {
    const kernels::VecEl q = Eigen::Map<const kernels::VecEl>(spec.q_ref.data() + 12 * e);
    for (int g = 0; g < n_gp_; ++g)
      eps0_[e * n_gp_ + g] = kernels::strains(strain_table(), kernels::field_map(gp(e, g)) * q);
  }
}

PointBasis Beam::basis_on_span(int span, double s) const {
  const auto b = bspline::basis_on_span(n_spans(), span, s / length());
  PointBasis p;
  p.span = span;
  for (int a = 0; a < 3; ++a) {
    p.N[a] = b.N[a];
    p.dN[a] = b.dN[a] / length();
  }
  return p;
}

PointBasis Beam::basis_at(double s) const {
  return basis_on_span(bspline::find_span(n_spans(), s / length()), s);
}

}  // namespace slidebeam
