// SPDX-License-Identifier: MIT
/// @file Contact of a beam with a rigid plane (scene table [[contact]], type = "plane"): the
/// ground, a seabed, a slope.
///
/// A penalty potential per unit length of the beam, checked at the mass quadrature points (3 per
/// span, 5 per ANCF element):
///   V = 1/2 k <-g>^2,   g = n . (x - p),   <-g> = max(-g, 0),
/// n the plane's unit normal (pointing to the free side), p a point of it, k the bed's stiffness
/// (force per unit length of beam per unit of penetration). The beam sinks w / k into the bed
/// under a line weight w: the stiffer, the closer to a rigid bed, at the price of a stiffer step.
///
/// Energy: V is part of H (potential). Under energy-momentum each point's force is the discrete
/// gradient of V along its gap, DG = (V(g1) - V(g0)) / (g1 - g0) (V' at the mean where g1 = g0),
/// so the contact's work over a step is exactly V(g1) - V(g0): energy is conserved through
/// touch-down and lift-off without locating them. The other schemes take V' at their force state.
/// The plane is fixed: the contact takes linear momentum along n (and the angular momentum about
/// axes not parallel to n), as a support does.

#include "effects/common.hpp"

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace slidebeam::effects {

namespace {
using Vec3 = Eigen::Vector3d;

/// The penalty potential of a gap g and its derivatives.
struct Penalty {
  double k = 0.0;
  double V(double g) const { return g < 0.0 ? 0.5 * k * g * g : 0.0; }
  double dV(double g) const { return g < 0.0 ? k * g : 0.0; }
  // at g = 0 the contact branch: a beam drawn on the bed starts with the bed's stiffness in its
  // tangent (else the first Newton step lets it fall through as if nothing held it)
  double ddV(double g) const { return g <= 0.0 ? k : 0.0; }
  /// Discrete gradient (V(g1) - V(g0)) / (g1 - g0) and its derivative with respect to g1.
  std::pair<double, double> discrete(double g0, double g1) const {
    if (g0 >= 0.0 && g1 >= 0.0) return {0.0, 0.0};
    if (g0 <= 0.0 && g1 <= 0.0) return {0.5 * k * (g0 + g1), 0.5 * k};  // both in contact: exact, no division
    const double d = g1 - g0;  // the signs differ: |d| >= max(|g0|, |g1|) > 0
    const double dg = (V(g1) - V(g0)) / d;
    return {dg, (dV(g1) - dg) / d};
  }
};

}  // namespace

/// The plane's contact on one beam: W = 3 a director beam, W = 4 an ANCF cable (CentreLineEffect).
template <int W>
class PlaneContact final : public CentreLineEffect<W> {
  using Base = CentreLineEffect<W>;
  using typename Base::MatY;
  using typename Base::VecY;
  using Base::beam_;
  using Base::gather;
  using Base::n_points;
  using Base::point;

 public:
  PlaneContact(int beam, const Model& m, const EffectParams& p) : Base(beam, m) {
    const auto& n = p.vector("normal", 3);
    const auto& x = p.vector("point", 3);
    normal_ = Vec3(n[0], n[1], n[2]);
    point_ = Vec3(x[0], x[1], x[2]);
    law_.k = p.number("stiffness");
    if (!(normal_.norm() > 0.0) || !normal_.allFinite() || !point_.allFinite())
      throw ParamError("normal", "the plane's normal must be a nonzero vector");
    if (!(law_.k > 0.0)) throw ParamError("stiffness", "the bed's stiffness must be > 0");
    normal_.normalize();
  }
  std::string type() const override { return "plane_contact"; }

  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(beam_);
    double U = 0.0;
    for (int e : this->elements_) {
      const VecY y = gather(ctx, ctx.x, b, e);
      for (int g = 0; g < n_points(b); ++g) {
        const CentreLinePoint<W> q = point(b, e, g);
        U += q.w * law_.V(gap(q, y));
      }
    }
    return U;
  }

 private:
  double gap(const CentreLinePoint<W>& q, const VecY& y) const {
    Vec3 x = Vec3::Zero();
    for (int i = 0; i < W; ++i) x += q.N[static_cast<size_t>(i)] * y.template segment<3>(3 * i);
    return normal_.dot(x - point_);
  }

  /// r += the element's generalised contact force with the sign of a residual (int N^T dV/dx), and
  /// K += its derivative with respect to the step's end state.
  void element(const EvalContext& ctx, const Beam& b, int e, VecY& r, MatY* K) const override {
    const bool em = ctx.rule == StepRule::EnergyMomentum;
    const VecY y1 = gather(ctx, ctx.x, b, e);
    const VecY yf = em ? gather(ctx, ctx.x_old, b, e) : gather(ctx, ctx.xf, b, e);  // em: the step's start
    for (int g = 0; g < n_points(b); ++g) {
      const CentreLinePoint<W> q = point(b, e, g);
      double force = 0.0, stiffness = 0.0;  // dV/dg and its derivative with respect to g at the step's end
      if (em) {
        std::tie(force, stiffness) = law_.discrete(gap(q, yf), gap(q, y1));
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

  Penalty law_;
  Vec3 normal_, point_;
};

void register_contact_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const double inf = std::numeric_limits<double>::infinity();
  EffectSpec s;
  s.type = "plane_contact";
  s.table = "contact";
  s.variant = "plane";
  s.meaning = "contact of a beam with a rigid plane (the ground, a seabed, a slope): a penalty 1/2 k <-g>^2 per "
              "unit length, g the distance of the centre line from the plane, checked at the mass quadrature points";
  s.role = EnergyRole::Stored;
  s.stored = "potential";
  s.params = {
      {"beam", K::Beam, "", "the beam that touches the plane (director beam or ANCF cable)", ""},
      {"point", K::Vector, "m", "a point of the plane", "", -inf, inf, false, 3},
      {"normal", K::Vector, "", "the plane's normal, towards the side the beam is on (e.g. [0, 0, 1] for the ground)",
       "", -inf, inf, false, 3},
      {"stiffness", K::Number, "N/m^2",
       "k, the bed's stiffness: force per unit length of beam per unit of penetration (a line weight w sinks w / k "
       "into it)",
       "", 0.0, inf, true},
  };
  r.add(s, [](const Model& m, const EffectParams& p) -> std::unique_ptr<Effect> {
    const int beam = beam_param(m, p);
    if (m.beam(beam).is_ancf()) return std::make_unique<PlaneContact<4>>(beam, m, p);
    return std::make_unique<PlaneContact<3>>(beam, m, p);
  });
}

}  // namespace slidebeam::effects
