// SPDX-License-Identifier: MIT
/// @file Effects of a director beam itself: elastic strain energy and the orthonormality
/// constraints of its control points.

#include "effects/common.hpp"

#include <Eigen/Dense>

namespace slidebeam::effects {

using kernels::MatEl;
using kernels::VecEl;
using RowMajorEl = Eigen::Matrix<double, kernels::kNqEl, kernels::kNqEl, Eigen::RowMajor>;

/// Strain energy of one beam (formulation.md section 3), integrated span by span.
class BeamElastic final : public Effect {
 public:
  BeamElastic(const Model& m, const EffectParams& p) : beam_(beam_param(m, p)), name_(m.beam(beam_).name()) {}
  std::string type() const override { return "beam_elastic"; }
  std::string label() const override { return "beam_elastic[" + name_ + "]"; }

  void distribute(const Model& m) override {
    const Beam& b = m.beam(beam_);
    for (int e = 0; e < b.n_spans(); ++e)
      if (owns_span(m, b, e)) spans_.push_back(e);
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    const Beam& b = m.beam(beam_);
    for (int e : spans_) add_cp_blocks(m.dof_map(), b.first_cp() + e, 3, dofs);
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    const Beam& b = m.beam(beam_);
    const RowMajorEl zero = RowMajorEl::Zero();
    for (int e : spans_) {
      const auto d = span_q_dofs(m.dof_map(), b, e);
      PetscCall(sink.add(kernels::kNqEl, d.data(), kernels::kNqEl, d.data(), zero.data()));
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    for (int e : spans_) {
      const VecEl q = gather_span(ctx, b, e);
      VecEl re = VecEl::Zero();
      for (int g = 0; g < b.n_gp(); ++g)
        kernels::beam_gp_residual_tangent(b.strain_table(), b.stiffness(), b.eps0(e, g), b.gp(e, g), q, re, nullptr);
      scatter_span(ctx.map, r, b, e, re);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    for (int e : spans_) {
      const VecEl q = gather_span(ctx, b, e);
      VecEl re = VecEl::Zero();
      MatEl K = MatEl::Zero();
      for (int g = 0; g < b.n_gp(); ++g)
        kernels::beam_gp_residual_tangent(b.strain_table(), b.stiffness(), b.eps0(e, g), b.gp(e, g), q, re, &K);
      const RowMajorEl Kr = K;
      const auto d = span_q_dofs(ctx.map, b, e);
      PetscCall(J.add(kernels::kNqEl, d.data(), kernels::kNqEl, d.data(), Kr.data()));
    }
    PetscFunctionReturn(0);
  }
  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(beam_);
    double U = 0.0;
    for (int e : spans_) {
      const VecEl q = gather_span(ctx, b, e);
      for (int g = 0; g < b.n_gp(); ++g)
        U += kernels::beam_gp_energy(b.strain_table(), b.stiffness(), b.eps0(e, g), b.gp(e, g), q);
    }
    return U;
  }

 private:
  int beam_;
  std::string name_;
  std::vector<int> spans_;
};

/// Six orthonormality constraints per control point with their multipliers (seed eq. 2).
class DirectorConstraints final : public Effect {
 public:
  DirectorConstraints(const Model& m, const EffectParams& p)
      : beam_(beam_param(m, p)), name_(m.beam(beam_).name()) {}
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
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    const double zero[DofMap::kBlock * DofMap::kBlock] = {};
    for (PetscInt cp : cps_) {
      PetscInt d[DofMap::kBlock];
      for (int k = 0; k < DofMap::kBlock; ++k) d[k] = m.dof_map().q(cp, 0) + k;
      PetscCall(sink.add(DofMap::kBlock, d, DofMap::kBlock, d, zero));
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    for (PetscInt cp : cps_) {
      const PetscScalar* x = ctx.x.cp(ctx.map, cp);
      const kernels::Vec12 q = Eigen::Map<const kernels::Vec12>(x);
      const kernels::Vec6 lam = Eigen::Map<const kernels::Vec6>(x + kernels::kNq);
      PetscScalar* rc = r.cp(ctx.map, cp);
      Eigen::Map<kernels::Vec12>(rc) += kernels::orthonormality_jacobian(q).transpose() * lam;
      Eigen::Map<kernels::Vec6>(rc + kernels::kNq) += kernels::orthonormality(q);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    using Mat18 = Eigen::Matrix<double, DofMap::kBlock, DofMap::kBlock, Eigen::RowMajor>;
    for (PetscInt cp : cps_) {
      const PetscScalar* x = ctx.x.cp(ctx.map, cp);
      const kernels::Vec12 q = Eigen::Map<const kernels::Vec12>(x);
      const kernels::Vec6 lam = Eigen::Map<const kernels::Vec6>(x + kernels::kNq);
      const kernels::Mat6x12 G = kernels::orthonormality_jacobian(q);
      Mat18 A = Mat18::Zero();
      A.topLeftCorner<12, 12>() = kernels::orthonormality_hessian(lam);
      A.topRightCorner<12, 6>() = G.transpose();
      A.bottomLeftCorner<6, 12>() = G;
      PetscInt d[DofMap::kBlock];
      for (int k = 0; k < DofMap::kBlock; ++k) d[k] = ctx.map.q(cp, 0) + k;
      PetscCall(J.add(DofMap::kBlock, d, DofMap::kBlock, d, A.data()));
    }
    PetscFunctionReturn(0);
  }

 private:
  int beam_;
  std::string name_;
  std::vector<PetscInt> cps_;
};

void register_beam_effects(EffectRegistry& r) {
  r.add("beam_elastic", [](const Model& m, const EffectParams& p) { return std::make_unique<BeamElastic>(m, p); });
  r.add("director_constraints",
        [](const Model& m, const EffectParams& p) { return std::make_unique<DirectorConstraints>(m, p); });
}

}  // namespace slidebeam::effects
