// SPDX-License-Identifier: MIT
#pragma once
/// @file A potential per unit length of a beam that depends on each point's signed distance from
/// a plane alone, g = n . (x - p): contact with the ground (a penalty below it), buoyancy (the
/// submerged part of the section below the water's surface). Checked at the mass quadrature
/// points (CentreLineEffect).
///
/// Under energy-momentum each point's force is the discrete gradient of V along its gap,
///   DG(g0, g1) = (V(g1) - V(g0)) / (g1 - g0) = int_0^1 V'(g0 + tau (g1 - g0)) dtau,
/// so that the term's work over a step is exactly V(g1) - V(g0). It is computed as the integral,
/// by Gauss quadrature on the pieces between the law's breakpoints (exact for the polynomial
/// pieces of the laws here), not as the quotient: where V is linear or g1 = g0 the quotient loses
/// every digit to cancellation, and its derivative more. Its derivative with respect to g1 is
/// int_0^1 V''(g0 + tau (g1 - g0)) tau dtau, by the same quadrature. The other schemes take V' at
/// their force state.

#include "effects/common.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <utility>

namespace slidebeam::effects {

/// DG(g0, g1) and d DG / d g1 of a law with V'(g) (dV), V''(g) (ddV) and its breakpoints (where
/// the polynomial pieces meet; each piece of degree <= 5 in V').
template <class Law>
std::pair<double, double> gap_discrete_gradient(const Law& law, double g0, double g1) {
  // 3-point Gauss on [0, 1]: exact for polynomials of degree 5
  static constexpr std::array<double, 3> x = {0.11270166537925831, 0.5, 0.8872983346207417};
  static constexpr std::array<double, 3> w = {0.2777777777777778, 0.4444444444444444, 0.2777777777777778};
  const double d = g1 - g0;
  std::array<double, Law::kBreakpoints + 2> tau{};  // the pieces' ends in tau
  int n = 0;
  tau[static_cast<size_t>(n++)] = 0.0;
  if (d != 0.0)
    for (double b : law.breakpoints()) {
      const double t = (b - g0) / d;
      if (t > 0.0 && t < 1.0) tau[static_cast<size_t>(n++)] = t;
    }
  std::sort(tau.begin() + 1, tau.begin() + n);
  tau[static_cast<size_t>(n++)] = 1.0;
  double dg = 0.0, ddg = 0.0;
  for (int p = 0; p + 1 < n; ++p) {
    const double a = tau[static_cast<size_t>(p)], len = tau[static_cast<size_t>(p + 1)] - a;
    for (int q = 0; q < 3; ++q) {
      const double t = a + len * x[static_cast<size_t>(q)], g = g0 + t * d;
      dg += len * w[static_cast<size_t>(q)] * law.dV(g);
      ddg += len * w[static_cast<size_t>(q)] * law.ddV(g) * t;
    }
  }
  return {dg, ddg};
}

/// The potential of Law on one beam: W = 3 a director beam, W = 4 an ANCF cable.
template <int W, class Law>
class GapPotential : public CentreLineEffect<W> {
  using Base = CentreLineEffect<W>;

 public:
  /// The plane through `point` with unit normal `normal` (g > 0 on its side).
  GapPotential(int beam, const Model& m, const Eigen::Vector3d& normal, const Eigen::Vector3d& point, const Law& law)
      : Base(beam, m), normal_(normal.normalized()), point_(point), law_(law) {}

  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(this->beam_);
    double U = 0.0;
    for (int e : this->elements_) {
      const typename Base::VecY y = this->gather(ctx, ctx.x, b, e);
      for (int g = 0; g < Base::n_points(b); ++g) {
        const CentreLinePoint<W> q = Base::point(b, e, g);
        U += q.w * law_.V(gap(q, y));
      }
    }
    return U;
  }

 protected:
  void element(const EvalContext& ctx, const Beam& b, int e, typename Base::VecY& r,
               typename Base::MatY* K) const override {
    const bool em = ctx.rule == StepRule::EnergyMomentum;
    const typename Base::VecY y1 = this->gather(ctx, ctx.x, b, e);
    const typename Base::VecY yf = this->gather(ctx, em ? ctx.x_old : ctx.xf, b, e);  // em: the step's start
    for (int g = 0; g < Base::n_points(b); ++g) {
      const CentreLinePoint<W> q = Base::point(b, e, g);
      double force = 0.0, stiffness = 0.0;  // dV/dg and its derivative with respect to the step's end
      if (em) {
        std::tie(force, stiffness) = gap_discrete_gradient(law_, gap(q, yf), gap(q, y1));
      } else {
        const double gf = gap(q, yf);
        force = law_.dV(gf);
        stiffness = ctx.theta * law_.ddV(gf);
      }
      if (force == 0.0 && stiffness == 0.0) continue;
      for (int i = 0; i < W; ++i) r.template segment<3>(3 * i) += q.w * q.N[static_cast<size_t>(i)] * force * normal_;
      if (!K) continue;
      const Eigen::Matrix3d nn = stiffness * normal_ * normal_.transpose();
      for (int i = 0; i < W; ++i)
        for (int j = 0; j < W; ++j)
          K->template block<3, 3>(3 * i, 3 * j) += q.w * q.N[static_cast<size_t>(i)] * q.N[static_cast<size_t>(j)] * nn;
    }
  }

 private:
  double gap(const CentreLinePoint<W>& q, const typename Base::VecY& y) const {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int i = 0; i < W; ++i) x += q.N[static_cast<size_t>(i)] * y.template segment<3>(3 * i);
    return normal_.dot(x - point_);
  }

  Eigen::Vector3d normal_, point_;
  Law law_;
};

}  // namespace slidebeam::effects
