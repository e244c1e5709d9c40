// SPDX-License-Identifier: MIT
/// @file Damping of the normal motion of a beam in contact with a fixed shape (`damping` > 0 on a
/// [[contact]] entry adds this effect beside the contact): a bed that takes energy out of the
/// beam's bounce on it, as a seabed's or a drum's lining does.
///
/// Per unit length of the beam at each mass quadrature point in contact at the step's end
/// (g1 < 0), a force against the step's mean rate of the gap, c (g1 - g0) / h, along a discrete
/// gradient w of the gap (w . (x1 - x0) = g1 - g0, gap_potential.hpp) under every scheme:
///
///   f = -c s(g1) (g1 - g0) / h w,   whose work over the step is -c s(g1) (g1 - g0)^2 / h <= 0,
///
/// exactly what the step dissipates (EnergyRole::Dissipative). The share s(g1) = min(1, -g1 / d)
/// sets the damping in over the first d of penetration (damping_depth): a force continuous in the
/// state, where a damping switched on whole at touch-down makes Newton chatter between contact
/// and none on a line that lands (a mooring chain lifting off and landing again). A penalty bed without it rings:
/// its normal mode (frequency sqrt(k / rho A)) is undamped under energy-momentum, and a rope
/// sliding over a drum then alternates between stick and slip at that frequency, which lowers
/// the friction it carries. c = 2 zeta sqrt(k rho A) damps that mode by the ratio zeta.

#include "effects/contact_shapes.hpp"

#include <Eigen/Dense>

#include <memory>
#include <string>

namespace slidebeam::effects {

namespace {

/// The penetration over which the damping sets in: the entry's damping_depth, by default the
/// sinkage of the beam's own weight in standard gravity, rho A g0 / k (a line on the bed sits
/// about that deep, so the damping is whole where it rests and continuous where it touches down).
double damping_depth(const Beam& b, const EffectParams& p) {
  if (p.num.count("damping_depth")) return p.number("damping_depth");
  return b.section().rhoA * 9.80665 / p.number("stiffness");
}

template <int W, class Shape>
class ContactDamping final : public CentreLineEffect<W> {
  using Base = CentreLineEffect<W>;
  using Base::position;
  using VecY = typename Base::VecY;
  using MatY = typename Base::MatY;

 public:
  ContactDamping(int beam, const Model& m, const EffectParams& p, const std::string& label, const Shape& shape)
      : Base(beam, m), shape_(shape), c_(p.number("damping")), depth_(damping_depth(m.beam(beam), p)), label_(label) {
    if (!(c_ > 0.0)) throw ParamError("damping", "the bed's damping must be > 0");
    if (!(depth_ > 0.0)) throw ParamError("damping_depth", "the depth over which the damping sets in must be > 0");
  }
  std::string type() const override { return "contact_damping"; }
  std::string label() const override { return label_; }

 protected:
  bool acts(const EvalContext& ctx) const override { return ctx.h > 0.0 && ctx.scheme != StepScheme::Static; }

  void element(const EvalContext& ctx, const Beam& b, int e, VecY& r, MatY* K) const override {
    const VecY y1 = this->gather(ctx, ctx.x, b, e), y0 = this->gather(ctx, ctx.x_old, b, e);
    const double c = c_ / ctx.h;
    for (int g = 0; g < Base::n_points(b); ++g) {
      const CentreLinePoint<W> q = Base::point(b, e, g);
      const GapStep s = shape_.step(position(q, y0), position(q, y1));
      if (!(s.g1 < 0.0)) continue;
      // the damping sets in over the first depth_ of penetration: a force continuous in the state
      const bool ramp = s.g1 > -depth_;
      const double share = ramp ? -s.g1 / depth_ : 1.0;
      const Eigen::Vector3d force = c * share * (s.g1 - s.g0) * s.w;
      for (int i = 0; i < W; ++i) r.template segment<3>(3 * i) += q.w * q.N[static_cast<size_t>(i)] * force;
      if (!K) continue;
      Eigen::Matrix3d stiffness = c * share * (s.w * s.n1.transpose() + (s.g1 - s.g0) * s.dw);
      if (ramp) stiffness -= (c / depth_) * (s.g1 - s.g0) * s.w * s.n1.transpose();
      for (int i = 0; i < W; ++i)
        for (int j = 0; j < W; ++j)
          K->template block<3, 3>(3 * i, 3 * j) += q.w * q.N[static_cast<size_t>(i)] * q.N[static_cast<size_t>(j)] * stiffness;
    }
  }

 private:
  Shape shape_;
  double c_, depth_;
  std::string label_;
};

}  // namespace

void register_contact_damping_effects(EffectRegistry& r) {
  EffectSpec s = model_effect_spec("contact_damping", EnergyRole::Dissipative,
                                   "damping of a beam's normal motion on a fixed [[contact]] shape (the entry's "
                                   "damping > 0), against the rate of its penetration");
  s.rate_force = true;
  r.add(s, [](const Model& m, const EffectParams& p) { return make_on_fixed_shape<ContactDamping>(m, p, "damping"); });
}

}  // namespace slidebeam::effects
