// SPDX-License-Identifier: MIT
/// @file Effects of a director beam itself: elastic strain energy, inertia and the
/// orthonormality constraints of its control points.

#include "effects/common.hpp"

#include <Eigen/Dense>

#include <algorithm>

namespace slidebeam::effects {

using kernels::MatEl;
using kernels::VecEl;

/// An effect integrated span by span over one director beam: three control points, the 36 x 36
/// block of their coordinates.
/// Strain energy of one beam (docs/theory.md; docs/developer.md, "Design notes"), integrated span by span. With the
/// assumed-strain quadrature the membrane and shear strains enter through their values at the
/// knots (kernels::GammaMoments): a knot's value takes the moments of the spans on both sides,
/// the spans' Gamma stresses are the knots' interpolated, and the material part of the tangent
/// couples a knot's two spans (four control points).
class BeamElastic final : public KnotBandSpanEffect {
  using Vec3 = Eigen::Vector3d;

 public:
  BeamElastic(const Model& m, const EffectParams& p) : KnotBandSpanEffect(m, p, "beam_elastic") {}
  std::string type() const override { return "beam_elastic"; }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    const bool knots = b.gamma_at_knots();
    if (ctx.rule == StepRule::EnergyMomentum) {
      // z(q_n), eps(q_n) and the knots' strains at q_n are constant during the step: computed at its first residual
      if (start_key_ != ctx.step_start || !has_start_) {
        start_.resize(elements_.size());
        for (size_t k = 0; k < elements_.size(); ++k) {
          const int e = elements_[k];
          start_[k] = kernels::span_em_state(b.strain_table(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                             gather_span(ctx.x_old, ctx.map, b, e));
        }
        if (knots) knot_strains(ctx, ctx.x_old, b, knot_start_);
        start_key_ = ctx.step_start;
        has_start_ = true;
      }
      if (knots) update_knot_sigma(ctx, b);
      for (size_t k = 0; k < elements_.size(); ++k) {
        const int e = elements_[k];
        VecEl re = VecEl::Zero();
        double lanes[3][kernels::kSpanLanes] = {};
        if (knots) gamma_sigma_lanes(b, e, lanes);
        kernels::span_residual_em(b.strain_table(), b.stiffness(), start_[k], gather_span(ctx.x, ctx.map, b, e), re,
                                  ctx.dissipation, knots ? lanes : nullptr);
        scatter_span(ctx.map, r, b, e, re);
      }
      PetscFunctionReturn(0);
    }
    if (knots) update_knot_sigma(ctx, b);
    add_span_residuals(ctx, b, r);
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    const bool knots = b.gamma_at_knots();
    if (knots) {
      // (not the residual's cache of the step start: the Jacobian may come first)
      if (ctx.rule == StepRule::EnergyMomentum) knot_strains(ctx, ctx.x_old, b, knot_start_);
      update_knot_sigma(ctx, b);
    }
    span_tangents_into_band(ctx, b);
    if (knots) knot_tangents(ctx, b);
    PetscCall(band_.flush(ctx.map, b, J));
    PetscFunctionReturn(0);
  }
  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(beam_);
    double U = 0.0;
    for (int e : elements_)
      U += kernels::span_energy(b.strain_table(), b.stiffness(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                b.gamma_at_knots(), gather_span(ctx.x, ctx.map, b, e));
    if (b.gamma_at_knots()) {
      knot_strains(ctx, ctx.x, b, knot_now_);
      for (int i : patches_.knots) {
        const Vec3& v = knot_now_[static_cast<size_t>(i)];
        U += 0.5 * b.knot_mass(i) * v.dot(b.stiffness().head<3>().cwiseProduct(v));
      }
    }
    return U;
  }

 private:
  /// Internal force (and tangent d/dx) of span e under the context's step rule; with knots, the
  /// Gamma stresses of knot_sigma_.
  void element(const EvalContext& ctx, const Beam& b, int e, VecEl& re, MatEl* K) const override {
    Vec3 gs[kernels::kSpanLanes];
    const bool knots = b.gamma_at_knots();
    if (knots)
      for (int g = 0; g < b.n_gp(); ++g) gs[g] = point_gamma_sigma(b, e, g);
    if (ctx.rule == StepRule::EnergyMomentum) {
      const VecEl q0 = gather_span(ctx.x_old, ctx.map, b, e), q1 = gather_span(ctx.x, ctx.map, b, e);
      kernels::span_residual_tangent_em(b.strain_table(), b.stiffness(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                        knots ? gs : nullptr, q0, q1, re, K, ctx.dissipation);
      return;
    }
    kernels::span_residual_tangent(b.strain_table(), b.stiffness(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                   knots ? gs : nullptr, gather_span(ctx.xf, ctx.map, b, e), re, K);
    if (K && ctx.theta != 1.0) *K *= ctx.theta;
  }
  /// knot_sigma_ = C_Gamma times the knots' strains at the force state; energy-momentum: at the
  /// step's averaged strain (knot_start_ at q_n), shifted by xi/2 (b(x) - b(q_n)) for the
  /// energy-decaying variant.
  void update_knot_sigma(const EvalContext& ctx, const Beam& b) const {
    const bool em = ctx.rule == StepRule::EnergyMomentum;
    knot_strains(ctx, em ? ctx.x : ctx.xf, b, knot_now_);
    const double a0 = 0.5 * (1.0 - ctx.dissipation), a1 = 0.5 * (1.0 + ctx.dissipation);
    knot_sigma_.assign(knot_now_.size(), Vec3::Zero());
    for (size_t i = 0; i < knot_now_.size(); ++i)
      knot_sigma_[i] = b.stiffness().head<3>().cwiseProduct(em ? a0 * knot_start_[i] + a1 * knot_now_[i] : knot_now_[i]);
  }
  /// The Gamma stress at point g of span e: the knots' stresses interpolated.
  Vec3 point_gamma_sigma(const Beam& b, int e, int g) const {
    const double t = b.gp(e, g).t;
    return (1.0 - t) * knot_sigma_[static_cast<size_t>(e)] + t * knot_sigma_[static_cast<size_t>(e + 1)];
  }
  /// The knots' strains b_i in the state x (entries of the knots next to owned spans).
  void knot_strains(const EvalContext& ctx, const LocalValues& x, const Beam& b, std::vector<Vec3>& out) const {
    out = b.knot_gamma(patches_.moment_spans, [&](int f) { return gather_span(x, ctx.map, b, f); });
  }
  /// Span e's Gamma stresses at its points, lane by lane.
  void gamma_sigma_lanes(const Beam& b, int e, double (&lanes)[3][kernels::kSpanLanes]) const {
    for (int g = 0; g < b.n_gp(); ++g) {
      const Vec3 v = point_gamma_sigma(b, e, g);
      for (int k = 0; k < 3; ++k) lanes[k][g] = v(k);
    }
  }
  /// band_ += the material tangents of the knots' Gamma energy, s / m_i Gbar_a^T C Gbar_b, with
  /// Gbar the gradient of a knot's moment: at the force state (statics), or the midpoint and the
  /// end of the step (energy-momentum, s = (1 + xi) / 2).
  void knot_tangents(const EvalContext& ctx, const Beam& b) const {
    const auto q0 = [&](int f) { return gather_span(ctx.x_old, ctx.map, b, f); };
    const auto q1 = [&](int f) { return gather_span(ctx.x, ctx.map, b, f); };
    const bool em = ctx.rule == StepRule::EnergyMomentum;
    if (em) {
      grad_a_.compute(b, patches_.moment_spans, [&](int f) { return VecEl(0.5 * (q0(f) + q1(f))); });
      grad_b_.compute(b, patches_.moment_spans, q1);
    } else
      grad_a_.compute(b, patches_.moment_spans, [&](int f) { return gather_span(ctx.xf, ctx.map, b, f); });
    const SpanMomentGradients& gb = em ? grad_b_ : grad_a_;
    for (int i : patches_.knots) {
      const double s = (em ? 0.5 * (1.0 + ctx.dissipation) : ctx.theta) / b.knot_mass(i);
      const KnotGradient Ga = grad_a_.knot(b, i);
      band_.add_outer(knot_first_cp(b, i), static_cast<int>(Ga.cols()) / kernels::kNq, Ga,
                      s * b.stiffness().head<3>(), gb.knot(b, i));
    }
  }

  mutable std::vector<Vec3> knot_start_, knot_now_, knot_sigma_;
  mutable SpanMomentGradients grad_a_, grad_b_;
  // energy-momentum: the state of every owned span at the step start
  mutable std::vector<kernels::SpanEmState> start_;
  mutable unsigned long start_key_ = 0;
  mutable bool has_start_ = false;
};

/// Six orthonormality constraints per control point with their multipliers (seed eq. 2).
class DirectorConstraints final : public Effect, public NumberingHints {
  static constexpr int kBlock = kernels::kNq + 6;  ///< a director control point's DofMap block

 public:
  DirectorConstraints(const Model& m, const EffectParams& p)
      : beam_(director_beam_param(m, p, "director_constraints")), name_(m.beam(beam_).name()) {}
  std::string type() const override { return "director_constraints"; }
  std::string label() const override { return "director_constraints[" + name_ + "]"; }

  void distribute(const Model& m) override {
    const Beam& b = m.beam(beam_);
    for (int c = 0; c < b.n_cp(); ++c)
      if (m.dof_map().owns_cp(b.first_cp() + c)) cps_.push_back(b.first_cp() + c);
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    for (PetscInt cp : cps_) add_cp_blocks(m.dof_map(), cp, 1, dofs);
  }
  void director_triads(const Model&, std::vector<PetscInt>& cps) const override {
    cps.insert(cps.end(), cps_.begin(), cps_.end());
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    const double zero[kBlock * kBlock] = {};
    for (PetscInt cp : cps_) {
      PetscInt d[kBlock];
      for (int k = 0; k < kBlock; ++k) d[k] = m.dof_map().q(cp, 0) + k;
      PetscCall(sink.add(kBlock, d, kBlock, d, zero));
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    for (PetscInt cp : cps_) {
      const PetscScalar* x = ctx.x.cp(ctx.map, cp);
      PetscScalar* rc = r.cp(ctx.map, cp);
      // Constraint forces at the force state (exact discrete gradient of quadratic constraints
      // at the midpoint), constraints themselves at the end of the step.
      kernels::orthonormality_residual(x, ctx.xf.cp(ctx.map, cp), x + kernels::kNq, rc, rc + kernels::kNq);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    using Mat18 = Eigen::Matrix<double, kBlock, kBlock, Eigen::RowMajor>;
    for (PetscInt cp : cps_) {
      const PetscScalar* x = ctx.x.cp(ctx.map, cp);
      const kernels::Vec12 q = Eigen::Map<const kernels::Vec12>(x);
      const kernels::Vec12 qf = Eigen::Map<const kernels::Vec12>(ctx.xf.cp(ctx.map, cp));
      const kernels::Vec6 lam = Eigen::Map<const kernels::Vec6>(x + kernels::kNq);
      Mat18 A = Mat18::Zero();
      A.topLeftCorner<12, 12>() = ctx.theta * kernels::orthonormality_hessian(lam);
      A.topRightCorner<12, 6>() = kernels::orthonormality_jacobian(qf).transpose();
      A.bottomLeftCorner<6, 12>() = kernels::orthonormality_jacobian(q);
      PetscInt d[kBlock];
      for (int k = 0; k < kBlock; ++k) d[k] = ctx.map.q(cp, 0) + k;
      PetscCall(J.add(kBlock, d, kBlock, d, A.data()));
    }
    PetscFunctionReturn(0);
  }

 private:
  int beam_;
  std::string name_;
  std::vector<PetscInt> cps_;
};

/// Kinetic energy of one beam (docs/theory.md, "Inertia, gravity, point masses"): the constant consistent mass
/// M^AB = int N^A N^B ds (x) diag(rho A, 0, rho I3, rho I2). d1 carries no inertia. Assembled
/// once into the mass matrix; the time integrator applies it.
class BeamInertia final : public MassOnlyEffect<SpanEffect> {
 public:
  BeamInertia(const Model& m, const EffectParams& p) : MassOnlyEffect(m, p, "beam_inertia") {}
  std::string type() const override { return "beam_inertia"; }
  PetscErrorCode mass(const Model& m, const MatSink& M) const override {
    PetscFunctionBeginUser;
    const Beam& b = m.beam(beam_);
    const Section& sec = b.section();
    const double rho[4] = {sec.rhoA, 0.0, sec.rhoI3, sec.rhoI2};  // phi, d1, d2, d3
    // Only the true nonzeros: M couples a coordinate with the same coordinate of the other
    // control points (3 x 3 per field and component). Adding the whole 36 x 36 block made the
    // mass matrix 10x denser than it is, and its product is part of every residual.
    for (int e : elements_) {
      Eigen::Matrix3d NN = Eigen::Matrix3d::Zero();  // int N^a N^c ds over the span
      for (int g = 0; g < 3; ++g) {
        const auto& gp = b.gp_full(e, g);
        for (int a = 0; a < 3; ++a)
          for (int c = 0; c < 3; ++c) NN(a, c) += gp.w * gp.N[a] * gp.N[c];
      }
      const auto d = span_q_dofs(m.dof_map(), b, e);
      for (int blk = 0; blk < 4; ++blk) {
        if (rho[blk] == 0.0) continue;
        const Eigen::Matrix3d A = rho[blk] * NN;  // symmetric: row- and column-major alike
        for (int k = 0; k < 3; ++k) {
          const PetscInt idx[3] = {d[3 * blk + k], d[kernels::kNq + 3 * blk + k], d[2 * kernels::kNq + 3 * blk + k]};
          PetscCall(M.add(3, idx, 3, idx, A.data()));
        }
      }
    }
    PetscFunctionReturn(0);
  }
};

void register_beam_effects(EffectRegistry& r) {
  r.add(model_effect_spec("beam_inertia", EnergyRole::Stored, "kinetic energy of a director beam (its mass matrix)", "kinetic"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<BeamInertia>(m, p); });
  r.add(model_effect_spec("beam_elastic", EnergyRole::Stored, "strain energy of a director beam", "strain"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<BeamElastic>(m, p); });
  r.add(model_effect_spec("director_constraints", EnergyRole::Constraint, "orthonormality of a director beam's control-point triads"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<DirectorConstraints>(m, p); });
}

}  // namespace slidebeam::effects
