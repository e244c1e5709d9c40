// SPDX-License-Identifier: MIT
#include "kernels/ancf_kernels.hpp"

#include <cmath>

namespace slidebeam::kernels::ancf {

namespace {
// Gauss-Legendre rules on [0,1].
struct Rule5 {
  std::array<double, 5> x, w;
  Rule5() {
    const double a = std::sqrt(5.0 - 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
    const double b = std::sqrt(5.0 + 2.0 * std::sqrt(10.0 / 7.0)) / 3.0;
    const double wa = (322.0 + 13.0 * std::sqrt(70.0)) / 900.0;
    const double wb = (322.0 - 13.0 * std::sqrt(70.0)) / 900.0;
    x = {0.5 * (1 - b), 0.5 * (1 - a), 0.5, 0.5 * (1 + a), 0.5 * (1 + b)};
    w = {0.5 * wb, 0.5 * wa, 0.5 * 128.0 / 225.0, 0.5 * wa, 0.5 * wb};
  }
};
struct Rule3 {
  std::array<double, 3> x, w;
  Rule3() {
    const double a = std::sqrt(0.6);
    x = {0.5 * (1 - a), 0.5, 0.5 * (1 + a)};
    w = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
  }
};

// sum_a w_a q_a for 4 basis weights
inline Eigen::Vector3d interp(const std::array<double, 4>& w, const ElVec& q) {
  return w[0] * q.segment<3>(0) + w[1] * q.segment<3>(3) + w[2] * q.segment<3>(6) + w[3] * q.segment<3>(9);
}
// f_a += c w_a v
inline void add_weighted(const std::array<double, 4>& w, double c, const Eigen::Vector3d& v, ElVec& f) {
  for (int a = 0; a < 4; ++a) f.segment<3>(3 * a) += (c * w[a]) * v;
}
// K_ab += c w_a w_b I3
inline void add_scalar_block(const std::array<double, 4>& w, double c, ElMat& K) {
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const double s = c * w[a] * w[b];
      for (int k = 0; k < 3; ++k) K(3 * a + k, 3 * b + k) += s;
    }
}
// K_ab += c w_a w_b u v^T
inline void add_dyad_block(const std::array<double, 4>& w, double c, const Eigen::Vector3d& u,
                           const Eigen::Vector3d& v, ElMat& K) {
  const Eigen::Matrix3d uv = c * u * v.transpose();
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) K.block<3, 3>(3 * a, 3 * b) += (w[a] * w[b]) * uv;
}
}  // namespace

HermiteBasis hermite(double x, double Le) {
  const double t = x / Le, t2 = t * t, t3 = t2 * t;
  HermiteBasis b;
  b.S = {1.0 - 3.0 * t2 + 2.0 * t3, Le * (t - 2.0 * t2 + t3), 3.0 * t2 - 2.0 * t3, Le * (t3 - t2)};
  b.dS = {6.0 * (t2 - t) / Le, 1.0 - 4.0 * t + 3.0 * t2, 6.0 * (t - t2) / Le, 3.0 * t2 - 2.0 * t};
  b.ddS = {(12.0 * t - 6.0) / (Le * Le), (6.0 * t - 4.0) / Le, (6.0 - 12.0 * t) / (Le * Le), (6.0 * t - 2.0) / Le};
  return b;
}

Mat3x12 shape_matrix(const std::array<double, 4>& w) {
  Mat3x12 P = Mat3x12::Zero();
  for (int a = 0; a < 4; ++a) P.block<3, 3>(0, 3 * a).diagonal().setConstant(w[a]);
  return P;
}

Eigen::Vector3d interpolate(const std::array<double, 4>& w, const ElVec& q) { return interp(w, q); }

AncfElement make_element(double Le, const ElVec& q_ref) {
  static const Rule5 r5;
  static const Rule3 r3;
  AncfElement el;
  el.Le = Le;
  for (int g = 0; g < kAxialPoints; ++g) {
    const HermiteBasis b = hermite(r5.x[g] * Le, Le);
    AxialPoint& p = el.axial[g];
    p.S = b.S;
    p.dS = b.dS;
    p.w = r5.w[g] * Le;
    p.half_s0s0 = 0.5 * interp(b.dS, q_ref).squaredNorm();
  }
  for (int g = 0; g < kBendPoints; ++g) {
    const HermiteBasis b = hermite(r3.x[g] * Le, Le);
    BendPoint& p = el.bend[g];
    p.ddS = b.ddS;
    p.w = r3.w[g] * Le;
    p.ddr0 = interp(b.ddS, q_ref);
  }
  return el;
}

ElVec straight_reference(const Eigen::Vector3d& X1, const Eigen::Vector3d& X2) {
  const Eigen::Vector3d t = (X2 - X1).normalized();
  ElVec q;
  q << X1, t, X2, t;
  return q;
}

double axial_strain(const AncfElement& el, int g, const ElVec& q) {
  const AxialPoint& p = el.axial[g];
  return 0.5 * interp(p.dS, q).squaredNorm() - p.half_s0s0;
}

double energy(const AncfSection& sec, const AncfElement& el, const ElVec& q) {
  double U = 0.0;
  for (int g = 0; g < kAxialPoints; ++g) {
    const double e = axial_strain(el, g, q);
    U += 0.5 * el.axial[g].w * sec.EA * e * e;
  }
  for (const BendPoint& p : el.bend) U += 0.5 * p.w * sec.EI * (interp(p.ddS, q) - p.ddr0).squaredNorm();
  return U;
}

void internal_force(const AncfSection& sec, const AncfElement& el, const ElVec& q, ElVec& f, ElMat* K) {
  f.setZero();
  if (K) K->setZero();
  // axial: d eps / d q_a = S'_a r',  d2 eps / d q_a d q_b = S'_a S'_b I
  for (const AxialPoint& p : el.axial) {
    const Eigen::Vector3d s = interp(p.dS, q);
    const double N = sec.EA * (0.5 * s.squaredNorm() - p.half_s0s0);  // axial force
    add_weighted(p.dS, p.w * N, s, f);
    if (K) {
      add_dyad_block(p.dS, p.w * sec.EA, s, s, *K);
      add_scalar_block(p.dS, p.w * N, *K);
    }
  }
  // bending: r'' is linear in q
  for (const BendPoint& p : el.bend) {
    add_weighted(p.ddS, p.w * sec.EI, interp(p.ddS, q) - p.ddr0, f);
    if (K) add_scalar_block(p.ddS, p.w * sec.EI, *K);
  }
}

void internal_force_em(const AncfSection& sec, const AncfElement& el, const ElVec& q0, const ElVec& q1,
                       ElVec& f, ElMat* K, double xi) {
  f.setZero();
  if (K) K->setZero();
  const double c0 = 0.5 * (1.0 - xi), c1 = 0.5 * (1.0 + xi);
  for (const AxialPoint& p : el.axial) {
    const Eigen::Vector3d s0 = interp(p.dS, q0), s1 = interp(p.dS, q1), sm = 0.5 * (s0 + s1);
    const double e0 = 0.5 * s0.squaredNorm() - p.half_s0s0, e1 = 0.5 * s1.squaredNorm() - p.half_s0s0;
    const double N = sec.EA * (c0 * e0 + c1 * e1);  // averaged (xi = 0) axial force
    add_weighted(p.dS, p.w * N, sm, f);
    if (K) {
      // d/dq1 [N(q1) S'_a s_m]: N' = c1 EA S'_b s1^T, d s_m / d q1_b = 1/2 S'_b I
      add_dyad_block(p.dS, p.w * c1 * sec.EA, sm, s1, *K);
      add_scalar_block(p.dS, 0.5 * p.w * N, *K);
    }
  }
  for (const BendPoint& p : el.bend) {
    const Eigen::Vector3d k0 = interp(p.ddS, q0) - p.ddr0, k1 = interp(p.ddS, q1) - p.ddr0;
    add_weighted(p.ddS, p.w * sec.EI, c0 * k0 + c1 * k1, f);
    if (K) add_scalar_block(p.ddS, p.w * sec.EI * c1, *K);
  }
}

void kelvin_voigt(const AncfElement& el, double c_axial, double c_bend, double h, double theta, const ElVec& q0,
                  const ElVec& q1, ElVec& f, ElMat* K) {
  if (c_axial > 0.0)
    for (const AxialPoint& p : el.axial) {
      const Eigen::Vector3d s0 = interp(p.dS, q0), s1 = interp(p.dS, q1), sf = (1.0 - theta) * s0 + theta * s1;
      const double sigma = c_axial * 0.5 * (s1.squaredNorm() - s0.squaredNorm()) / h;
      add_weighted(p.dS, p.w * sigma, sf, f);
      if (K) {  // d/dq1 [sigma S'_a s_f]: d sigma = c_axial / h S'_b s1^T, d s_f = theta S'_b I
        add_dyad_block(p.dS, p.w * c_axial / h, sf, s1, *K);
        add_scalar_block(p.dS, p.w * sigma * theta, *K);
      }
    }
  if (c_bend > 0.0)
    for (const BendPoint& p : el.bend) {
      add_weighted(p.ddS, p.w * c_bend / h, interp(p.ddS, q1) - interp(p.ddS, q0), f);
      if (K) add_scalar_block(p.ddS, p.w * c_bend / h, *K);
    }
}

ElMat mass_matrix(const AncfSection& sec, const AncfElement& el) {
  ElMat M = ElMat::Zero();
  for (const AxialPoint& p : el.axial) add_scalar_block(p.S, p.w * sec.rhoA, M);
  return M;
}

ElVec gravity_load(const AncfSection& sec, const AncfElement& el, const Eigen::Vector3d& g) {
  ElVec f = ElVec::Zero();
  for (const AxialPoint& p : el.axial) add_weighted(p.S, p.w * sec.rhoA, g, f);
  return f;
}

CablePoint evaluate(double Le, double x, const ElVec& q) {
  CablePoint c;
  c.basis = hermite(x, Le);
  c.r = interp(c.basis.S, q);
  c.dr = interp(c.basis.dS, q);
  c.ddr = interp(c.basis.ddS, q);
  return c;
}

}  // namespace slidebeam::kernels::ancf
