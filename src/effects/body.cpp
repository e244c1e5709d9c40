// SPDX-License-Identifier: MIT
/// @file A rigid body's inertia (docs/theory.md, "Rigid bodies"). The body is one director
/// control point: its centre of mass phi and its body frame d1, d2, d3, kept orthonormal by the
/// same six constraints as a beam's control point (director_constraints). A material point X
/// (body-frame components) is at phi + X_i d_i, so the kinetic energy is
///   T = 1/2 m |phi'|^2 + 1/2 sum_ij E_ij d_i' . d_j',   E = int X X^T dm (the Euler tensor),
/// a constant mass matrix: m I3 on phi, E_ij I3 between d_i and d_j. Energy-momentum then keeps
/// energy and momenta of a free body exactly, as it does a beam's.

#include "effects/common.hpp"

#include <Eigen/Dense>

namespace slidebeam::effects {

class BodyInertia final : public Effect, public MassSource {
 public:
  BodyInertia(const Model& m, const EffectParams& p) : body_(beam_param(m, p)) {
    if (!m.beam(body_).is_rigid())
      throw std::invalid_argument("body_inertia: '" + m.beam(body_).name() + "' is not a rigid body");
  }
  std::string type() const override { return "body_inertia"; }
  std::string label() const override { return "body_inertia[" + std::to_string(body_) + "]"; }
  void distribute(const Model& m) override { owned_ = m.dof_map().owns_cp(m.beam(body_).first_cp()); }
  void needed_dofs(const Model&, std::vector<PetscInt>&) const override {}  // reads no state
  PetscErrorCode pattern(const Model&, const MatSink&) const override { return 0; }
  PetscErrorCode residual(const EvalContext&, const LocalValues&) const override { return 0; }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override { return 0; }
  PetscErrorCode mass(const Model& m, const MatSink& M) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const Beam& b = m.beam(body_);
    const PetscInt cp = b.first_cp();
    // per Cartesian component k: the 4 x 4 block over (phi, d1, d2, d3) of that component
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    A(0, 0) = b.body_mass();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) A(1 + i, 1 + j) = b.euler()[static_cast<size_t>(3 * i + j)];
    for (int k = 0; k < 3; ++k) {
      const PetscInt idx[4] = {m.dof_map().q(cp, k), m.dof_map().q(cp, 3 + k), m.dof_map().q(cp, 6 + k),
                               m.dof_map().q(cp, 9 + k)};
      PetscCall(M.add(4, idx, 4, idx, A.data()));  // symmetric: row- and column-major alike
    }
    PetscFunctionReturn(0);
  }

 private:
  int body_;
  bool owned_ = false;
};

void register_body_effects(EffectRegistry& r) {
  r.add(model_effect_spec("body_inertia", EnergyRole::Stored, "kinetic energy of a rigid body (its mass matrix)", "kinetic"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<BodyInertia>(m, p); });
}

}  // namespace slidebeam::effects
