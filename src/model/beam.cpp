// SPDX-License-Identifier: MIT
#include "model/beam.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace slidebeam {

namespace {
/// A span's Barlow points: the two-point Gauss points, in the span's parameter t in [0, 1].
constexpr double kBarlow[2] = {0.5 - 0.28867513459481287, 0.5 + 0.28867513459481287};

/// Basis of span e at parameter xi as a quadrature point of weight w. corrected: with the data of
/// the director-interpolation correction (kernels::point_table).
kernels::GaussPoint basis_point(int n_spans, double L, int e, double xi, double w, bool corrected) {
  const auto b = bspline::basis_on_span(n_spans, e, xi);
  kernels::GaussPoint gp{};
  for (int a = 0; a < 3; ++a) {
    gp.N[a] = b.N[a];
    gp.dN[a] = b.dN[a] / L;  // d/ds = (1/L) d/dxi
    gp.ddN[a] = b.ddN[a] / (L * L);
  }
  gp.w = w;
  gp.t = xi * n_spans - e;
  gp.corrected = corrected;
  if (corrected) gp.correction_weight = L * L * bspline::director_correction_weight(n_spans, e, xi);
  return gp;
}

std::vector<kernels::GaussPoint> gauss_points(int n_spans, double L, kernels::Quadrature q, bool corrected) {
  std::array<double, 3> x{}, w{};
  const int ng = kernels::gauss_rule(q, x, w);
  std::vector<kernels::GaussPoint> gps;
  gps.reserve(static_cast<size_t>(n_spans * ng));
  const double h = 1.0 / n_spans;
  for (int e = 0; e < n_spans; ++e) {
    for (int g = 0; g < ng; ++g) gps.push_back(basis_point(n_spans, L, e, (e + x[g]) * h, w[g] * h * L, corrected));
  }
  return gps;
}
}  // namespace

Beam::Beam(const BeamSpec& spec, int id, int first_cp) : spec_(spec), id_(id), first_cp_(first_cp) {
  if (is_rigid()) {
    if (spec.n_spans != 0 || spec.q_ref.size() != 12)
      throw std::invalid_argument("body '" + spec.name + "': a rigid body is one control point of 12 coordinates");
    if (!(spec.mass > 0)) throw std::invalid_argument("body '" + spec.name + "': mass must be > 0");
    return;
  }
  if (spec.n_spans < 1) throw std::invalid_argument("beam '" + spec.name + "': spans must be >= 1");
  if (!(spec.length > 0)) throw std::invalid_argument("beam '" + spec.name + "': length must be > 0");
  if (spec.q_ref.size() != static_cast<size_t>(coordinates_per_cp() * n_cp()))
    throw std::invalid_argument("beam '" + spec.name + "': q_ref must hold " + std::to_string(coordinates_per_cp()) +
                                " values per control point");
  if (is_ancf()) {
    // Equal elements of the reference arc length; each element's stress-free state is its slice
    // of q_ref (x = arc length, so r0' should be a unit vector).
    const double Le = spec.length / spec.n_spans;
    if (spec.unstretched_length > 0.0) {
      // A rope of unit stretch has r' = r0' / r, no curvature; both strains are quadratic in the
      // derivatives: EA and EI per unit of x are r^3 times the rope's, rhoA 1/r times (see below).
      stretch_ = spec.length / spec.unstretched_length;
      Section& s = spec_.section;
      for (double* stiff : {&s.EA, &s.EI2, &s.EI3}) *stiff *= stretch_ * stretch_ * stretch_;
      s.rhoA /= stretch_;
    }
    for (int e = 0; e < spec.n_spans; ++e) {
      kernels::ancf::AncfElement el = kernels::ancf::make_element(
          Le, Eigen::Map<const kernels::ancf::ElVec>(spec.q_ref.data() + kernels::ancf::kNodeDofs * e));
      if (spec.unstretched_length > 0.0) {  // the rope of unit stretch: |r0'| = 1/r, straight
        for (auto& p : el.axial) p.half_s0s0 = 0.5 / (stretch_ * stretch_);
        for (auto& p : el.bend) p.ddr0.setZero();
      }
      ancf_elements_.push_back(el);
    }
    return;
  }
  if (spec.unstretched_length > 0.0) {
    if (spec.strain != kernels::StrainMeasure::SimoReissner)
      throw std::invalid_argument("beam '" + spec.name + "': an unstretched length needs the Simo-Reissner strains");
    // A piece ds of the drawn parameter is ds / r of rope (r = stretch): the rope's strains are r
    // times the parameter's, but the centre line's axial strain 1/2 (phi'.phi' - 1) of assumed
    // strains, which is r^2 times; the energy per unit of s is 1/r of the rope's. So the
    // stiffnesses are r (r^3 on that axial strain) times the rope's, the inertias 1/r times.
    stretch_ = spec.length / spec.unstretched_length;
    Section& s = spec_.section;
    for (double* stiff : {&s.kGA2, &s.kGA3, &s.GJ, &s.EI2, &s.EI3}) *stiff *= stretch_;
    s.EA *= centre_line_axial() ? stretch_ * stretch_ * stretch_ : stretch_;
    for (double* inertia : {&s.rhoA, &s.rhoI2, &s.rhoI3}) *inertia /= stretch_;
  }
  const auto& s = spec_.section;
  stiffness_ << s.EA, s.kGA2, s.kGA3, s.GJ, s.EI2, s.EI3;
  gps_ = gauss_points(spec.n_spans, spec.length, spec.quadrature, corrected());
  gps_full_ = gauss_points(spec.n_spans, spec.length, kernels::Quadrature::Full, false);
  n_gp_ = static_cast<int>(gps_.size()) / spec.n_spans;
  knot_mass_.assign(static_cast<size_t>(spec.n_spans + 1), 0.0);
  for (int e = 0; e < spec.n_spans; ++e)
    for (int g = 0; g < n_gp_; ++g) {
      knot_mass_[static_cast<size_t>(e)] += gp(e, g).w * (1.0 - gp(e, g).t);
      knot_mass_[static_cast<size_t>(e + 1)] += gp(e, g).w * gp(e, g).t;
    }
  // Reference strains at the stiffness quadrature points: the reference configuration is stress free.
  eps0_.resize(gps_.size());
  for (int e = 0; e < spec.n_spans; ++e) {
    const kernels::VecEl q = Eigen::Map<const kernels::VecEl>(spec.q_ref.data() + 12 * e);
    for (int g = 0; g < n_gp_; ++g)
      eps0_[e * n_gp_ + g] =
          stress_free(kernels::point_strains(strain_table(), gp(e, g), kernels::field_map(gp(e, g)) * q));
  }
}

kernels::Vec6 Beam::stress_free(const kernels::Vec6& eps_drawn) const {
  if (spec_.unstretched_length <= 0.0) return eps_drawn;
  // Straight and untwisted: no shear, no curvature, and the axial strain form's value at a rope
  // of unit stretch, |phi'| = 1/r per unit of s: d1 . phi' = 1/r, 1/2 phi' . phi' = 1/(2 r^2).
  // Not the drawing's own value over r: the spline rounds a polyline's corners, and the rope
  // would be shorter by what the corners cut (5 cm in 220 m of a mooring chain drawn with one).
  kernels::Vec6 eps = kernels::Vec6::Zero();
  eps(0) = centre_line_axial() ? 0.5 / (stretch_ * stretch_) : 1.0 / stretch_;
  return eps;
}

kernels::Vec6 Beam::rope_strains(const kernels::Vec6& eps) const {
  kernels::Vec6 out = stretch_ * eps;
  if (centre_line_axial()) out(0) *= stretch_;
  return out;
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

BeamSamples Beam::sample(const std::vector<double>& q, const std::vector<double>& q_dot, int samples_per_span) const {
  BeamSamples out;
  sample_into(q, q_dot, samples_per_span, out);
  return out;
}

void Beam::sample_into(const std::vector<double>& q, const std::vector<double>& q_dot, int samples_per_span,
                       BeamSamples& out) const {
  if (samples_per_span < 1) throw std::invalid_argument("samples_per_span must be >= 1");
  if (q.size() != spec_.q_ref.size() || (!q_dot.empty() && q_dot.size() != q.size()))
    throw std::invalid_argument("beam '" + name() + "': sample needs " + std::to_string(coordinates_per_cp()) +
                                " coordinates per control point");
  if (is_ancf()) {
    out = sample_ancf(q, q_dot, samples_per_span);
    return;
  }
  if (is_rigid()) {  // the centre of mass and the body frame; no strain, no resultants
    out = BeamSamples{};
    out.s = {0.0};
    out.position.assign(q.begin(), q.begin() + 3);
    out.velocity = q_dot.empty() ? std::vector<double>(3, 0.0) : std::vector<double>(q_dot.begin(), q_dot.begin() + 3);
    out.d1.assign(q.begin() + 3, q.begin() + 6);
    out.d2.assign(q.begin() + 6, q.begin() + 9);
    out.d3.assign(q.begin() + 9, q.begin() + 12);
    out.strain.assign(6, 0.0);
    out.force.assign(3, 0.0);
    out.moment.assign(3, 0.0);
    out.tension.assign(1, 0.0);
    return;
  }
  const auto& points = sample_points(samples_per_span);
  const int n = static_cast<int>(points.size());
  out.s.resize(static_cast<size_t>(n));
  for (auto* v : {&out.position, &out.velocity, &out.d1, &out.d2, &out.d3, &out.force, &out.moment})
    v->assign(static_cast<size_t>(3 * n), 0.0);
  out.strain.assign(static_cast<size_t>(6 * n), 0.0);
  out.tension.assign(static_cast<size_t>(n), 0.0);
  const std::vector<Eigen::Vector3d> knots = gamma_at_knots() ? knot_gamma(q) : std::vector<Eigen::Vector3d>{};
  const std::vector<std::array<Eigen::Vector3d, 2>> barlow =
      gamma_at_knots() ? std::vector<std::array<Eigen::Vector3d, 2>>{} : barlow_gamma(q);
  for (int i = 0; i < n; ++i) {
    const SamplePoint& p = points[static_cast<size_t>(i)];
    const PointBasis& b = p.basis;
    const kernels::StrainTable& T = p.table;
    const kernels::VecEl qe = Eigen::Map<const kernels::VecEl>(q.data() + 12 * b.span);
    const kernels::VecZ z = kernels::field_values(p.gp, qe);
    kernels::Vec6 eps = kernels::point_strains(strain_table(), p.gp, z) - p.eps_ref;
    if (gamma_at_knots()) {  // the element's own membrane and shear strains: the knots' values interpolated
      const double t = p.gp.t;
      eps.head<3>() = (1.0 - t) * knots[static_cast<size_t>(b.span)] + t * knots[static_cast<size_t>(b.span + 1)];
    } else {
      // The membrane and shear strains of a displacement-based span are right to second order only
      // at its Barlow points (the two-point Gauss points); in between, the shear strain, the small
      // difference of phi' and the directors, swings parabolically (a stocky boom's shear force
      // 6x too large at the knots). So they are taken as the line through the Barlow points' values.
      const auto& g = barlow[static_cast<size_t>(b.span)];
      const double u = (p.gp.t - kBarlow[0]) / (kBarlow[1] - kBarlow[0]);
      eps.head<3>() = (1.0 - u) * g[0] + u * g[1];
    }
    const kernels::Vec6 sigma = stiffness_.cwiseProduct(eps);
    out.s[static_cast<size_t>(i)] = p.s;
    Eigen::Vector3d f[4] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                            Eigen::Vector3d::Zero()};  // phi, d1, d2, d3
    Eigen::Vector3d vel = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a) {
      for (int blk = 0; blk < 4; ++blk) f[blk] += b.N[a] * qe.segment<3>(12 * a + 3 * blk);
      if (!q_dot.empty()) vel += b.N[a] * Eigen::Map<const Eigen::Vector3d>(q_dot.data() + 12 * (b.span + a));
    }
    // n = dW/dphi' = sum_k sigma_k d eps_k / dphi' (sigma_0 d1 + sigma_1 d2 + sigma_2 d3 for the
    // Simo-Reissner strains; sigma_0 phi' + ... where the axial strain is the centre line's)
    Eigen::Vector3d n_sp = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      for (int t = 0; t < T[k].n_terms; ++t) {
        const auto& term = T[k].terms[static_cast<size_t>(t)];
        if (term.a == kernels::kPhiS) n_sp += sigma(k) * term.c * z.segment<3>(3 * term.b);
        if (term.b == kernels::kPhiS) n_sp += sigma(k) * term.c * z.segment<3>(3 * term.a);
      }
    // the axial force: the resultant's component along the axial strain's direction (d1, or the
    // centre line's tangent)
    const double axial_force = p.centre_line_axial ? sigma(0) * z.segment<3>(3 * kernels::kPhiS).norm() : sigma(0);
    const Eigen::Vector3d m_sp = sigma(3) * f[1] + sigma(4) * f[2] + sigma(5) * f[3];
    auto put = [i](std::vector<double>& v, const Eigen::Vector3d& x) {
      for (int k = 0; k < 3; ++k) v[static_cast<size_t>(3 * i + k)] = x(k);
    };
    put(out.position, f[0]);
    put(out.d1, f[1]);
    put(out.d2, f[2]);
    put(out.d3, f[3]);
    put(out.velocity, vel);
    put(out.force, n_sp);
    put(out.moment, m_sp);
    out.tension[static_cast<size_t>(i)] = axial_force;
    const kernels::Vec6 rope = rope_strains(eps);
    for (int k = 0; k < 6; ++k) out.strain[static_cast<size_t>(6 * i + k)] = rope(k);
  }
}

const std::vector<Beam::SamplePoint>& Beam::sample_points(int samples_per_span) const {
  if (sampled_per_span_ == samples_per_span) return sample_points_;
  const int n = n_spans() * samples_per_span + 1;
  std::vector<SamplePoint> points(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    SamplePoint& p = points[static_cast<size_t>(i)];
    p.s = length() * i / (n - 1);
    p.basis = basis_at(p.s);
    p.gp = basis_point(n_spans(), length(), p.basis.span, p.s / length(), 0.0, corrected());
    p.table = kernels::point_table(strain_table(), p.gp);
    const kernels::VecEl q0 = Eigen::Map<const kernels::VecEl>(spec_.q_ref.data() + 12 * p.basis.span);
    p.eps_ref = stress_free(kernels::point_strains(strain_table(), p.gp, kernels::field_map(p.gp) * q0));
    const auto& axial = p.table[0];
    p.centre_line_axial = axial.n_terms == 1 && axial.terms[0].a == kernels::kPhiS && axial.terms[0].b == kernels::kPhiS;
  }
  sample_points_ = std::move(points);
  sampled_per_span_ = samples_per_span;
  return sample_points_;
}

std::vector<std::array<Eigen::Vector3d, 2>> Beam::barlow_gamma(const std::vector<double>& q) const {
  if (barlow_points_.empty()) {
    barlow_points_.resize(static_cast<size_t>(2 * n_spans()));
    for (int e = 0; e < n_spans(); ++e)
      for (int g = 0; g < 2; ++g) {
        SamplePoint& p = barlow_points_[static_cast<size_t>(2 * e + g)];
        p.s = length() * (e + kBarlow[g]) / n_spans();
        p.gp = basis_point(n_spans(), length(), e, (e + kBarlow[g]) / n_spans(), 0.0, corrected());
        const kernels::VecEl q0 = Eigen::Map<const kernels::VecEl>(spec_.q_ref.data() + 12 * e);
        p.eps_ref = stress_free(kernels::point_strains(strain_table(), p.gp, kernels::field_map(p.gp) * q0));
      }
  }
  std::vector<std::array<Eigen::Vector3d, 2>> out(static_cast<size_t>(n_spans()));
  for (int e = 0; e < n_spans(); ++e) {
    const kernels::VecEl qe = Eigen::Map<const kernels::VecEl>(q.data() + 12 * e);
    for (int g = 0; g < 2; ++g) {
      const SamplePoint& p = barlow_points_[static_cast<size_t>(2 * e + g)];
      const kernels::Vec6 eps = kernels::point_strains(strain_table(), p.gp, kernels::field_values(p.gp, qe)) - p.eps_ref;
      out[static_cast<size_t>(e)][static_cast<size_t>(g)] = eps.head<3>();
    }
  }
  return out;
}

std::vector<Eigen::Vector3d> Beam::knot_gamma(const std::vector<double>& q) const {
  std::vector<int> all(static_cast<size_t>(n_spans()));
  for (int e = 0; e < n_spans(); ++e) all[static_cast<size_t>(e)] = e;
  return knot_gamma(all, [&q](int e) { return kernels::VecEl(Eigen::Map<const kernels::VecEl>(q.data() + 12 * e)); });
}

int Beam::ancf_element_at(double s, double& x) const {
  const double Le = length() / n_spans();
  const int e = std::clamp(static_cast<int>(std::floor(s / Le)), 0, n_spans() - 1);
  x = s - e * Le;
  return e;
}

PositionStencil Beam::body_point(const std::array<double, 3>& X) const {
  PositionStencil p;
  p.n = 4;
  p.cp = {0, 0, 0, 0};
  p.comp = {0, 3, 6, 9};
  p.w = {1.0, X[0], X[1], X[2]};
  return p;
}

PositionStencil Beam::body_point_drawn(const std::array<double, 3>& drawn) const {
  const double* q = spec_.q_ref.data();  // phi, d1, d2, d3
  std::array<double, 3> X{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) X[static_cast<size_t>(i)] += q[3 + 3 * i + k] * (drawn[static_cast<size_t>(k)] - q[k]);
  return body_point(X);
}

PositionStencil Beam::position_at(double s) const {
  PositionStencil p;
  if (is_rigid()) return body_point({0.0, 0.0, 0.0});
  if (is_ancf()) {
    double x = 0.0;
    const int e = ancf_element_at(s, x);
    p.n = 4;
    p.span = e;
    p.cp = {e, e, e + 1, e + 1};
    p.comp = {0, 3, 0, 3};  // r_1, r'_1, r_2, r'_2: the order of the Hermite basis
    p.w = kernels::ancf::hermite(x, length() / n_spans()).S;
    return p;
  }
  const PointBasis b = basis_at(s);
  p.n = 3;
  p.span = b.span;
  for (int a = 0; a < 3; ++a) {
    p.cp[a] = b.span + a;
    p.w[a] = b.N[a];
  }
  return p;
}

BeamSamples Beam::sample_ancf(const std::vector<double>& q, const std::vector<double>& q_dot,
                              int samples_per_span) const {
  namespace ancf = kernels::ancf;
  const int n = n_spans() * samples_per_span + 1;
  const double Le = length() / n_spans();
  BeamSamples out;
  out.s.resize(static_cast<size_t>(n));
  for (auto* v : {&out.position, &out.velocity, &out.d1, &out.d2, &out.d3, &out.force, &out.moment})
    v->assign(static_cast<size_t>(3 * n), 0.0);
  out.strain.assign(static_cast<size_t>(6 * n), 0.0);
  out.tension.assign(static_cast<size_t>(n), 0.0);
  const auto sec = ancf_section();
  for (int i = 0; i < n; ++i) {
    const double s = length() * i / (n - 1);
    double x = 0.0;
    const int e = ancf_element_at(s, x);
    const auto slice = [e](const std::vector<double>& v) {
      return ancf::ElVec(Eigen::Map<const ancf::ElVec>(v.data() + ancf::kNodeDofs * e));
    };
    const ancf::CablePoint c = ancf::evaluate(Le, x, slice(q));
    ancf::CablePoint c0 = ancf::evaluate(Le, x, slice(spec_.q_ref));
    if (spec_.unstretched_length > 0.0) {  // the stress-free rope: straight, |r0'| = 1/r
      c0.dr = c0.dr.normalized() / stretch_;
      c0.ddr.setZero();
    }
    const double eps = 0.5 * (c.dr.squaredNorm() - c0.dr.squaredNorm());
    const double stretch = c.dr.norm();
    const Eigen::Vector3d t = c.dr / stretch;
    const Eigen::Vector3d kappa = c.dr.cross(c.ddr) / (stretch * stretch * stretch);
    auto put = [i](std::vector<double>& v, const Eigen::Vector3d& y) {
      for (int k = 0; k < 3; ++k) v[static_cast<size_t>(3 * i + k)] = y(k);
    };
    out.s[static_cast<size_t>(i)] = s;
    put(out.position, c.r);
    if (!q_dot.empty()) put(out.velocity, ancf::interpolate(c.basis.S, slice(q_dot)));
    put(out.d1, t);
    put(out.force, sec.EA * eps * c.dr);  // dW/dr' of W = EA/2 eps^2
    out.tension[static_cast<size_t>(i)] = sec.EA * eps * stretch;
    put(out.moment, sec.EI * c.dr.cross(c.ddr - c0.ddr));
    out.strain[static_cast<size_t>(6 * i)] = stretch_ * stretch_ * eps;  // per unit of rope (x = r sigma)
    for (int k = 0; k < 3; ++k) out.strain[static_cast<size_t>(6 * i + 3 + k)] = kappa(k);  // geometric: any parameter
  }
  return out;
}

PointBasis Beam::basis_at(double s) const {
  return basis_on_span(bspline::find_span(n_spans(), s / length()), s);
}

}  // namespace slidebeam
