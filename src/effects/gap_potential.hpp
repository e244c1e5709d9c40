// SPDX-License-Identifier: MIT
#pragma once
/// @file A potential per unit length of a beam that depends on each point's gap g(x) to a shape
/// alone: contact with the ground, a drum or a ball (a penalty where g < 0), buoyancy (the part of
/// the section below the water's surface, g the height above it). Checked at the mass quadrature
/// points (CentreLineEffect). Shapes: a plane, g = n . (x - p); round ones, g = |P (x - c)| - R
/// with P = I (a sphere) or the projection normal to an axis (a cylinder).
///
/// Under energy-momentum each point's force is a discrete gradient of V(g(x)): the product of
///   DG_V(g0, g1) = (V(g1) - V(g0)) / (g1 - g0) = int_0^1 V'(g0 + tau (g1 - g0)) dtau
/// and a discrete gradient w of the gap, w . (x1 - x0) = g1 - g0, so that the term's work over a
/// step is exactly V(g1) - V(g0). DG_V is computed as the integral, by Gauss quadrature on the
/// pieces between the law's breakpoints (exact for the polynomial pieces of the laws here), not as
/// the quotient: where V is linear or g1 = g0 the quotient loses every digit to cancellation, and
/// its derivative more. Its derivative with respect to g1 is int_0^1 V''(g0 + tau (g1 - g0)) tau
/// dtau, by the same quadrature. The plane's w is n; a round shape's is the norm's exact discrete
/// gradient P (y0 + y1) / (|y0| + |y1|), y = P (x - c), since (y0 + y1) . (y1 - y0) = |y1|^2 - |y0|^2.
/// The other schemes take V'(g) grad g at their force state.

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
  // insertion sort of the few breakpoints inside (std::sort's unrolled code misleads -Warray-bounds)
  for (int i = 2; i < n; ++i)
    for (int j = i; j > 1 && tau[static_cast<size_t>(j - 1)] > tau[static_cast<size_t>(j)]; --j)
      std::swap(tau[static_cast<size_t>(j - 1)], tau[static_cast<size_t>(j)]);
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

/// A point's gaps at a step's start and end, a discrete gradient w of the gap (w . (x1 - x0) =
/// g1 - g0), the gap's gradient n1 at the end and dw / dx1.
struct GapStep {
  double g0 = 0.0, g1 = 0.0;
  Eigen::Vector3d w, n1;
  Eigen::Matrix3d dw;
};

/// A plane through p with unit normal n: g = n . (x - p) (g > 0 on n's side).
struct PlaneGap {
  Eigen::Vector3d n, p;
  double gap(const Eigen::Vector3d& x) const { return n.dot(x - p); }
  Eigen::Vector3d gradient(const Eigen::Vector3d&) const { return n; }
  Eigen::Matrix3d hessian(const Eigen::Vector3d&) const { return Eigen::Matrix3d::Zero(); }
  GapStep step(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1) const {
    return {gap(x0), gap(x1), n, n, Eigen::Matrix3d::Zero()};
  }
};

/// A round surface: g = |P (x - c)| - R, P = I (a sphere of centre c) or I - a a^T (a cylinder of
/// axis a through c). g > 0 outside. Undefined on the axis (the centre), which a beam in contact
/// is far from.
struct RoundGap {
  Eigen::Vector3d c;
  Eigen::Matrix3d P;
  double R = 0.0;
  Eigen::Vector3d y(const Eigen::Vector3d& x) const { return P * (x - c); }
  double gap(const Eigen::Vector3d& x) const { return y(x).norm() - R; }
  Eigen::Vector3d gradient(const Eigen::Vector3d& x) const { return y(x).normalized(); }
  Eigen::Matrix3d hessian(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d v = y(x);
    const double r = v.norm();
    return (P - v * v.transpose() / (r * r)) / r;
  }
  GapStep step(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1) const {
    const Eigen::Vector3d y0 = y(x0), y1 = y(x1);
    const double r0 = y0.norm(), r1 = y1.norm(), m = r0 + r1;
    GapStep s;
    s.g0 = r0 - R;
    s.g1 = r1 - R;
    s.w = (y0 + y1) / m;  // in P's range already
    s.n1 = y1 / r1;
    s.dw = (P - s.w * s.n1.transpose()) / m;
    return s;
  }
};

/// A point's force d(energy)/dx of V(g(x)) within a step, from the force state xf (the step's start
/// under energy-momentum) and the end state x1, and (with K) its derivative with respect to x1:
/// the discrete gradient under energy-momentum, V'(g) grad g at xf otherwise. false: no force.
template <class Law, class Shape>
bool gap_force(const Law& law, const Shape& shape, const EvalContext& ctx, const Eigen::Vector3d& xf,
               const Eigen::Vector3d& x1, bool with_K, Eigen::Vector3d& force, Eigen::Matrix3d& stiffness) {
  stiffness.setZero();
  if (ctx.rule == StepRule::EnergyMomentum) {
    const GapStep s = shape.step(xf, x1);
    const auto [dg, ddg] = gap_discrete_gradient(law, s.g0, s.g1);
    if (dg == 0.0 && ddg == 0.0) return false;
    force = dg * s.w;
    if (with_K) stiffness = ddg * s.w * s.n1.transpose() + dg * s.dw;
    return true;
  }
  const double gf = shape.gap(xf), dv = law.dV(gf), ddv = law.ddV(gf);
  if (dv == 0.0 && ddv == 0.0) return false;
  const Eigen::Vector3d n = shape.gradient(xf);
  force = dv * n;
  if (with_K) stiffness = ctx.theta * (ddv * n * n.transpose() + dv * shape.hessian(xf));
  return true;
}

/// The potential of Law on one beam against Shape: W = 3 a director beam, W = 4 an ANCF cable.
/// Its outputs: the force the shape (the water) exerts on the beam and the length of the beam on
/// which it acts (in contact; submerged), both at the mass quadrature points of the state.
template <int W, class Law, class Shape = PlaneGap>
class GapPotential : public CentreLineEffect<W>, public OutputSource {
  using Base = CentreLineEffect<W>;
  using Base::position;

 public:
  GapPotential(int beam, const Model& m, const Shape& shape, const Law& law) : Base(beam, m), shape_(shape), law_(law) {}

  std::vector<std::string> output_names() const override { return {"force.x", "force.y", "force.z", "length"}; }
  void outputs(const EvalContext& ctx, double* values) const override {
    at_points(ctx, [&](double w, const Eigen::Vector3d& x) {
      const double dv = law_.dV(shape_.gap(x));
      if (dv == 0.0) return;
      const Eigen::Vector3d f = -w * dv * shape_.gradient(x);
      for (int k = 0; k < 3; ++k) values[k] += f(k);
      values[3] += w;
    });
  }

  double energy(const EvalContext& ctx) const override {
    double U = 0.0;
    at_points(ctx, [&](double w, const Eigen::Vector3d& x) { U += w * law_.V(shape_.gap(x)); });
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
      Eigen::Vector3d force;       // d(energy)/dx at the point
      Eigen::Matrix3d stiffness;   // its derivative with respect to the step's end
      if (!gap_force(law_, shape_, ctx, position(q, yf), position(q, y1), K != nullptr, force, stiffness)) continue;
      for (int i = 0; i < W; ++i) r.template segment<3>(3 * i) += q.w * q.N[static_cast<size_t>(i)] * force;
      if (!K) continue;
      for (int i = 0; i < W; ++i)
        for (int j = 0; j < W; ++j)
          K->template block<3, 3>(3 * i, 3 * j) += q.w * q.N[static_cast<size_t>(i)] * q.N[static_cast<size_t>(j)] * stiffness;
    }
  }

 private:
  /// f(weight, position) at every mass quadrature point of this rank's elements, in the state x.
  template <class F>
  void at_points(const EvalContext& ctx, F&& f) const {
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      const typename Base::VecY y = this->gather(ctx, ctx.x, b, e);
      for (int g = 0; g < Base::n_points(b); ++g) {
        const CentreLinePoint<W> q = Base::point(b, e, g);
        f(q.w, position(q, y));
      }
    }
  }

  Shape shape_;
  Law law_;
};

}  // namespace slidebeam::effects
