// SPDX-License-Identifier: MIT
/// @file Effects of a director beam itself: elastic strain energy, inertia and the
/// orthonormality constraints of its control points.

#include "effects/common.hpp"

#include <Eigen/Dense>

namespace slidebeam::effects {

using kernels::MatEl;
using kernels::VecEl;
using RowMajorEl = Eigen::Matrix<double, kernels::kNqEl, kernels::kNqEl, Eigen::RowMajor>;

/// An effect integrated span by span over one director beam: three control points, the 36 x 36
/// block of their coordinates.
class SpanEffect : public ElementEffect<3, kernels::kNqEl> {
 public:
  SpanEffect(const Model& m, const EffectParams& p, const std::string& who)
      : ElementEffect(director_beam_param(m, p, who), m) {}

 protected:
  Dofs element_dofs(const DofMap& map, const Beam& b, int e) const override { return span_q_dofs(map, b, e); }
};

/// Strain energy of one beam (formulation.md section 3), integrated span by span.
class BeamElastic final : public SpanEffect {
 public:
  BeamElastic(const Model& m, const EffectParams& p) : SpanEffect(m, p, "beam_elastic") {}
  std::string type() const override { return "beam_elastic"; }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    if (ctx.rule == StepRule::EnergyMomentum) {
      // z(q_n) and eps(q_n) are constant during the step: computed at its first residual
      if (start_key_ != ctx.step_start || !has_start_) {
        start_.resize(elements_.size());
        for (size_t k = 0; k < elements_.size(); ++k) {
          const int e = elements_[k];
          start_[k] = kernels::span_em_state(b.strain_table(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                             b.projection(e), gather_span(ctx.x_old, ctx.map, b, e));
        }
        start_key_ = ctx.step_start;
        has_start_ = true;
      }
      for (size_t k = 0; k < elements_.size(); ++k) {
        const int e = elements_[k];
        VecEl re = VecEl::Zero();
        kernels::span_residual_em(b.strain_table(), b.stiffness(), start_[k], gather_span(ctx.x, ctx.map, b, e), re,
                                  ctx.dissipation);
        scatter_span(ctx.map, r, b, e, re);
      }
      PetscFunctionReturn(0);
    }
    for (int e : elements_) {
      VecEl re = VecEl::Zero();
      element(ctx, b, e, re, nullptr);
      scatter_span(ctx.map, r, b, e, re);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    for (int e : elements_) {
      VecEl re = VecEl::Zero();
      MatEl K = MatEl::Zero();
      element(ctx, b, e, re, &K);
      const RowMajorEl Kr = K;
      const auto d = span_q_dofs(ctx.map, b, e);
      PetscCall(J.add(kernels::kNqEl, d.data(), kernels::kNqEl, d.data(), Kr.data()));
    }
    PetscFunctionReturn(0);
  }
  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(beam_);
    double U = 0.0;
    for (int e : elements_) {
      U += kernels::span_energy(b.strain_table(), b.stiffness(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                b.projection(e), gather_span(ctx.x, ctx.map, b, e));
    }
    return U;
  }

 private:
  /// Internal force (and tangent d/dx) of span e under the context's step rule.
  void element(const EvalContext& ctx, const Beam& b, int e, VecEl& re, MatEl* K) const {
    if (ctx.rule == StepRule::EnergyMomentum) {
      const VecEl q0 = gather_span(ctx.x_old, ctx.map, b, e), q1 = gather_span(ctx.x, ctx.map, b, e);
      kernels::span_residual_tangent_em(b.strain_table(), b.stiffness(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                        b.projection(e), q0, q1, re, K, ctx.dissipation);
      return;
    }
    kernels::span_residual_tangent(b.strain_table(), b.stiffness(), &b.gp(e, 0), &b.eps0(e, 0), b.n_gp(),
                                   b.projection(e), gather_span(ctx.xf, ctx.map, b, e), re, K);
    if (K && ctx.theta != 1.0) *K *= ctx.theta;
  }
  // energy-momentum: the state of every owned span at the step start
  mutable std::vector<kernels::SpanEmState> start_;
  mutable unsigned long start_key_ = 0;
  mutable bool has_start_ = false;
};

/// Six orthonormality constraints per control point with their multipliers (seed eq. 2).
class DirectorConstraints final : public Effect {
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

/// Kinetic energy of one beam (formulation.md section 4): the constant consistent mass
/// M^AB = int N^A N^B ds (x) diag(rho A, 0, rho I3, rho I2). d1 carries no inertia. Assembled
/// once into the mass matrix; the time integrator applies it.
class BeamInertia final : public SpanEffect {
 public:
  BeamInertia(const Model& m, const EffectParams& p) : SpanEffect(m, p, "beam_inertia") {}
  std::string type() const override { return "beam_inertia"; }
  void needed_dofs(const Model&, std::vector<PetscInt>&) const override {}  // reads no state
  PetscErrorCode residual(const EvalContext&, const LocalValues&) const override { return 0; }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override { return 0; }
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
  r.add("beam_inertia", [](const Model& m, const EffectParams& p) { return std::make_unique<BeamInertia>(m, p); });
  r.add("beam_elastic", [](const Model& m, const EffectParams& p) { return std::make_unique<BeamElastic>(m, p); });
  r.add("director_constraints",
        [](const Model& m, const EffectParams& p) { return std::make_unique<DirectorConstraints>(m, p); });
}

}  // namespace slidebeam::effects
