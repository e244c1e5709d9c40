// SPDX-License-Identifier: MIT
/// @file Structural damping of a beam (scene table [[damping]]): Kelvin-Voigt on the strain rates
/// and mass-proportional damping, for director beams and ANCF cables.
///
/// Kelvin-Voigt: every strain eps_i gains the viscous stress sigma_i = tau_i C_i d eps_i/dt
/// (tau_i: retardation time, C_i: the section stiffness), so that the damping matrix of small
/// motions is tau K for equal tau_i (stiffness-proportional Rayleigh damping). Mass-proportional:
/// the force alpha M v on every coordinate. Both use the mean rate over the step,
/// (eps(q_n+1) - eps(q_n)) / h and (q_n+1 - q_n) / h. The viscous stress acts through the strain
/// gradient at the step's force state z_f (the midpoint for energy-momentum and midpoint, the end
/// for Newmark and HHT), at the beam's own quadrature points; with assumed strains the membrane
/// and shear rates are the knots' as in the strain energy, so that small motions see exactly
/// tau K (a locking Gauss-point rate would over-damp bending). The strains being quadratic forms, grad eps(z_mid) . (z_n+1 - z_n) =
/// eps(z_n+1) - eps(z_n) exactly: under energy-momentum a step dissipates exactly
/// sum_gp w tau C (delta eps)^2 / h + alpha dq^T M dq / h >= 0, and the energy balance
/// H - H_0 = W - D closes to the Newton tolerance. HHT's history term leaves rate forces out
/// (their force at t_n would need the previous step's rate): they act with weight 1 + alpha.

#include "effects/common.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <stdexcept>

namespace slidebeam::effects {

namespace {
using kernels::kNqEl;
using kernels::MatEl;
using kernels::Vec6;
using kernels::VecEl;
using Vec3 = Eigen::Vector3d;

/// The retardation time of each strain (axial, shear 2, shear 3, torsion, bending about d2, about
/// d3): retardation_time for all, or retardation_times one by one; both given is a contradiction
/// the scene must resolve (the array used to win silently).
std::array<double, 6> retardation_times(const EffectParams& p) {
  const bool each = p.vec.count("retardation_times") && !p.vec.at("retardation_times").empty();
  if (each && p.num.count("retardation_time"))
    throw ParamError("retardation_times",
                     "give retardation_time (one for every strain) or retardation_times (one per strain), not both");
  std::array<double, 6> tau;
  tau.fill(p.number("retardation_time", 0.0));
  if (each) {
    const auto& v = p.vector("retardation_times", 6);
    std::copy(v.begin(), v.begin() + 6, tau.begin());
  }
  return tau;
}
}  // namespace

class BeamDamping final : public KnotBandSpanEffect {
 public:
  BeamDamping(const Model& m, const EffectParams& p)
      : KnotBandSpanEffect(m, p, "damping"), alpha_(p.number("mass_proportional", 0.0)) {
    const std::array<double, 6> tau = retardation_times(p);
    for (int i = 0; i < 6; ++i) tau_[i] = tau[static_cast<size_t>(i)];
    if (!(alpha_ >= 0.0) || !(tau_.minCoeff() >= 0.0))
      throw std::invalid_argument("damping: retardation times and mass_proportional must be >= 0");
    c_ = tau_.cwiseProduct(m.beam(beam_).stiffness());
    const Section& sec = m.beam(beam_).section();
    rho_ = {sec.rhoA, 0.0, sec.rhoI3, sec.rhoI2};  // phi, d1, d2, d3: the inertia's blocks
  }
  std::string type() const override { return "beam_damping"; }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (ctx.h <= 0.0) PetscFunctionReturn(0);  // no step, no rate
    const Beam& b = ctx.model.beam(beam_);
    knot_stresses(ctx, b);
    add_span_residuals(ctx, b, r);
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (ctx.h <= 0.0) PetscFunctionReturn(0);
    const Beam& b = ctx.model.beam(beam_);
    knot_stresses(ctx, b);
    span_tangents_into_band(ctx, b);
    knot_tangents(ctx, b);
    PetscCall(band_.flush(ctx.map, b, J));
    PetscFunctionReturn(0);
  }

 protected:

 private:
  // With assumed strains the membrane and shear strains are the knots' (as in the strain energy,
  // so that the damping of small motions is tau K): the same knots and coupled spans as there.
  bool knots_used(const Beam& b) const override { return b.gamma_at_knots() && c_.head<3>().maxCoeff() > 0.0; }

  /// The knots' viscous stresses tau C (b_i(q1) - b_i(q0)) / h.
  void knot_stresses(const EvalContext& ctx, const Beam& b) const {
    if (!knots_used(b)) return;
    const auto b0 = b.knot_gamma(patches_.moment_spans, [&](int f) { return gather_span(ctx.x_old, ctx.map, b, f); });
    const auto b1 = b.knot_gamma(patches_.moment_spans, [&](int f) { return gather_span(ctx.x, ctx.map, b, f); });
    knot_sigma_.resize(b1.size());
    for (size_t i = 0; i < b1.size(); ++i) knot_sigma_[i] = c_.head<3>().cwiseProduct(b1[i] - b0[i]) / ctx.h;
  }

  void element(const EvalContext& ctx, const Beam& b, int e, VecEl& r, MatEl* K) const override {
    const VecEl q0 = gather_span(ctx.x_old, ctx.map, b, e), q1 = gather_span(ctx.x, ctx.map, b, e);
    const double h = ctx.h, theta = ctx.theta;
    const bool knots = knots_used(b);
    if (c_.maxCoeff() > 0.0) {
      Vec3 gs[kernels::kSpanLanes];  // the knots' Gamma stresses at the points
      if (knots)
        for (int g = 0; g < b.n_gp(); ++g) {
          const double t = b.gp(e, g).t;
          gs[g] = (1.0 - t) * knot_sigma_[static_cast<size_t>(e)] + t * knot_sigma_[static_cast<size_t>(e + 1)];
        }
      kernels::span_kelvin_voigt(b.strain_table(), &b.gp(e, 0), b.n_gp(), c_, knots ? gs : nullptr, h, theta, q0, q1, r,
                                 K);
    }
    if (alpha_ == 0.0) return;
    // alpha M (q1 - q0) / h, M the span's consistent mass (the inertia's blocks)
    Eigen::Matrix3d NN = Eigen::Matrix3d::Zero();  // int N^a N^c ds over the span
    for (int g = 0; g < 3; ++g) {
      const kernels::GaussPoint& gp = b.gp_full(e, g);
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) NN(a, c) += gp.w * gp.N[a] * gp.N[c];
    }
    const VecEl dq = q1 - q0;
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        for (int blk = 0; blk < 4; ++blk) {
          const double m = alpha_ * rho_[static_cast<size_t>(blk)] * NN(a, c) / h;
          if (m == 0.0) continue;
          for (int k = 0; k < 3; ++k) {
            const int i = kernels::kNq * a + 3 * blk + k, j = kernels::kNq * c + 3 * blk + k;
            r[i] += m * dq[j];
            if (K) (*K)(i, j) += m;
          }
        }
  }

  /// band_ += the knots' material tangents: tau C / (h m_i) G(q_f)^T G(q1), G the gradient of a
  /// knot's Gamma moment (its spans' moments toward it).
  void knot_tangents(const EvalContext& ctx, const Beam& b) const {
    const auto q0 = [&](int f) { return gather_span(ctx.x_old, ctx.map, b, f); };
    const auto q1 = [&](int f) { return gather_span(ctx.x, ctx.map, b, f); };
    grad_f_.compute(b, patches_.moment_spans,
                    [&](int f) { return VecEl((1.0 - ctx.theta) * q0(f) + ctx.theta * q1(f)); });
    grad_1_.compute(b, patches_.moment_spans, q1);
    for (int i : patches_.knots) {
      const Eigen::Vector3d w = c_.head<3>() / (ctx.h * b.knot_mass(i));
      const KnotGradient Gf = grad_f_.knot(b, i);
      band_.add_outer(knot_first_cp(b, i), static_cast<int>(Gf.cols()) / kernels::kNq, Gf, w, grad_1_.knot(b, i));
    }
  }

  double alpha_;
  Vec6 tau_, c_;
  std::array<double, 4> rho_{};
  mutable std::vector<Vec3> knot_sigma_;
  mutable SpanMomentGradients grad_f_, grad_1_;
};

/// The same damping of an ANCF cable: Kelvin-Voigt on its two strains, the Green axial strain
/// eps = 1/2 (r'.r' - r0'.r0') (stress tau EA d eps/dt) and the bending vector r'' (tau EI d r''/dt:
/// the bending retardation time is the fifth, about d2, of retardation_times), and alpha M v.
/// eps is quadratic and r'' linear in the coordinates, so under energy-momentum the step
/// dissipates exactly int (tau EA deps^2 + tau EI |dr''|^2) / h dx + alpha dq^T M dq / h.
class AncfDamping final : public AncfElementEffect {
  using ElVec = kernels::ancf::ElVec;
  using ElMat = kernels::ancf::ElMat;

 public:
  AncfDamping(const Model& m, const EffectParams& p) : AncfElementEffect(m, p, "damping") {
    const std::array<double, 6> tau = retardation_times(p);
    const double tau_axial = tau[0], tau_bend = tau[4];
    alpha_ = p.number("mass_proportional", 0.0);
    if (!(alpha_ >= 0.0 && tau_axial >= 0.0 && tau_bend >= 0.0))
      throw std::invalid_argument("damping: retardation times and mass_proportional must be >= 0");
    const auto sec = m.beam(beam_).ancf_section();
    c_axial_ = tau_axial * sec.EA;
    c_bend_ = tau_bend * sec.EI;
  }
  std::string type() const override { return "beam_damping"; }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (ctx.h <= 0.0) PetscFunctionReturn(0);
    const Beam& b = ctx.model.beam(beam_);
    for (int e : elements_) {
      ElVec f = ElVec::Zero();
      element(ctx, b, e, f, nullptr);
      scatter(r, ctx.map, b, e, f);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (ctx.h <= 0.0) PetscFunctionReturn(0);
    const Beam& b = ctx.model.beam(beam_);
    using RowMajor = Eigen::Matrix<double, kernels::ancf::kElDofs, kernels::ancf::kElDofs, Eigen::RowMajor>;
    for (int e : elements_) {
      ElVec f = ElVec::Zero();
      ElMat K = ElMat::Zero();
      element(ctx, b, e, f, &K);
      const RowMajor Kr = K;
      const auto d = element_dofs(ctx.map, b, e);
      PetscCall(J.add(kernels::ancf::kElDofs, d.data(), kernels::ancf::kElDofs, d.data(), Kr.data()));
    }
    PetscFunctionReturn(0);
  }

 private:
  void element(const EvalContext& ctx, const Beam& b, int e, ElVec& f, ElMat* K) const {
    namespace ancf = kernels::ancf;
    const ancf::AncfElement& el = b.ancf_element(e);
    const ElVec q0 = gather(ctx.x_old, ctx.map, b, e), q1 = gather(ctx.x, ctx.map, b, e);
    const double h = ctx.h;
    ancf::kelvin_voigt(el, c_axial_, c_bend_, h, ctx.theta, q0, q1, f, K);
    if (alpha_ > 0.0) {
      const ElMat M = ancf::mass_matrix(b.ancf_section(), el);
      f += (alpha_ / h) * M * (q1 - q0);
      if (K) *K += (alpha_ / h) * M;
    }
  }

  double alpha_ = 0.0, c_axial_ = 0.0, c_bend_ = 0.0;
};

void register_damping_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  EffectSpec s;
  s.type = "beam_damping";
  s.table = "damping";
  s.meaning = "structural damping of a beam or cable: Kelvin-Voigt on the strain rates and mass-proportional";
  s.role = EnergyRole::Dissipative;
  s.rate_force = true;
  s.params = {
      {"beam", K::Beam, "", "the beam it damps", ""},
      {"retardation_time", K::Number, "s",
       "Kelvin-Voigt retardation time tau of every strain: viscous stress tau C d eps/dt (a mode of angular "
       "frequency omega gets the damping ratio tau omega / 2); 0 when left out",
       "", 0.0, std::numeric_limits<double>::infinity(), false, 0, {}, true},
      {"retardation_times", K::Vector, "s",
       "per strain (axial, shear 2, shear 3, torsion, bending about d2, about d3), instead of retardation_time",
       "[]", 0.0, std::numeric_limits<double>::infinity(), false, 6},
      {"mass_proportional", K::Number, "1/s",
       "alpha of the force alpha M v (damping ratio alpha / (2 omega); it damps rigid motion too)", "0.0", 0.0},
  };
  r.add(s, [](const Model& m, const EffectParams& p) -> std::unique_ptr<Effect> {
    if (m.beam(beam_param(m, p)).is_ancf()) return std::make_unique<AncfDamping>(m, p);
    return std::make_unique<BeamDamping>(m, p);
  });
}

}  // namespace slidebeam::effects
