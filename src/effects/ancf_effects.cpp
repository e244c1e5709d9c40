// SPDX-License-Identifier: MIT
/// @file Effects of an ANCF cable itself (kernels/ancf_kernels.hpp): elastic strain energy and
/// inertia. Element e couples the 12 coordinates of nodes e and e+1 (r, r' each); the cable has
/// no constraints of its own, so there is no counterpart of director_constraints.

#include "effects/common.hpp"

#include <Eigen/Dense>

namespace slidebeam::effects {

namespace ancf = kernels::ancf;
using RowMajorEl = Eigen::Matrix<double, ancf::kElDofs, ancf::kElDofs, Eigen::RowMajor>;

/// Strain energy of one cable: Green axial strain and |r'' - r0''|^2 bending. Endpoint and Theta
/// rules: the force at x_f (tangent times theta); EnergyMomentum: the averaged-strain force, an
/// exact discrete gradient (with the optional xi dissipation, as beam_elastic).
class AncfElastic final : public AncfElementEffect {
 public:
  AncfElastic(const Model& m, const EffectParams& p) : AncfElementEffect(m, p, "ancf_elastic") {}
  std::string type() const override { return "ancf_elastic"; }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    for (int e : elements_) {
      ancf::ElVec f;
      element(ctx, b, e, f, nullptr);
      scatter(r, ctx.map, b, e, f);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(beam_);
    for (int e : elements_) {
      ancf::ElVec f;
      ancf::ElMat K;
      element(ctx, b, e, f, &K);
      const RowMajorEl Kr = K;
      const auto d = element_dofs(ctx.map, b, e);
      PetscCall(J.add(ancf::kElDofs, d.data(), ancf::kElDofs, d.data(), Kr.data()));
    }
    PetscFunctionReturn(0);
  }
  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(beam_);
    double U = 0.0;
    for (int e : elements_) U += ancf::energy(b.ancf_section(), b.ancf_element(e), gather(ctx.x, ctx.map, b, e));
    return U;
  }

 private:
  void element(const EvalContext& ctx, const Beam& b, int e, ancf::ElVec& f, ancf::ElMat* K) const {
    if (ctx.rule == StepRule::EnergyMomentum) {
      ancf::internal_force_em(b.ancf_section(), b.ancf_element(e), gather(ctx.x_old, ctx.map, b, e),
                              gather(ctx.x, ctx.map, b, e), f, K, ctx.dissipation);
      return;
    }
    ancf::internal_force(b.ancf_section(), b.ancf_element(e), gather(ctx.xf, ctx.map, b, e), f, K);
    if (K && ctx.theta != 1.0) *K *= ctx.theta;
  }
};

/// Kinetic energy of one cable: the constant consistent mass int rhoA S^T S dx (no rotary
/// inertia). Assembled once into the mass matrix.
class AncfInertia final : public MassOnlyEffect<AncfElementEffect> {
 public:
  AncfInertia(const Model& m, const EffectParams& p) : MassOnlyEffect(m, p, "ancf_inertia") {}
  std::string type() const override { return "ancf_inertia"; }
  PetscErrorCode mass(const Model& m, const MatSink& M) const override {
    PetscFunctionBeginUser;
    const Beam& b = m.beam(beam_);
    for (int e : elements_) {
      const RowMajorEl A = ancf::mass_matrix(b.ancf_section(), b.ancf_element(e));
      const auto d = element_dofs(m.dof_map(), b, e);
      PetscCall(M.add(ancf::kElDofs, d.data(), ancf::kElDofs, d.data(), A.data()));
    }
    PetscFunctionReturn(0);
  }
};

void register_ancf_effects(EffectRegistry& r) {
  r.add(model_effect_spec("ancf_elastic", EnergyRole::Stored, "strain energy of an ANCF cable", "strain"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<AncfElastic>(m, p); });
  r.add(model_effect_spec("ancf_inertia", EnergyRole::Stored, "kinetic energy of an ANCF cable (its mass matrix)", "kinetic"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<AncfInertia>(m, p); });
}

}  // namespace slidebeam::effects
