// SPDX-License-Identifier: MIT
/// @file Coulomb friction on a sliding joint (scene table [[friction]]): a force on the joint's
/// sliding coordinate s that opposes the mean sliding rate of the step, sdot = (s_n+1 - s_n) / h,
///
///   F = -mu N sdot / sqrt(sdot^2 + v_reg^2),
///
/// with N = |Lambda - (t . Lambda) t| the joint's force on the slider transverse to the carrier's
/// unit tangent t at s (Effect::normal_force; both at the joint's force state). It adds
/// -F to the joint's s row, the force balance of the massless s: G_s . lambda - F = 0, so the
/// joint's tangential force on the slider is F (per unit of s; s is the carrier's reference arc
/// length, so on an inextensible carrier F is the tangential force itself, on a stretched one it
/// is F / |c'|).
///
/// Regularised, not semi-smooth: below the velocity scale v_reg the force grows linearly with the
/// sliding rate (a viscous law of coefficient mu N / v_reg), above it it tends to mu N. The
/// residual stays smooth, Newton converges as without friction and the step Jacobian is exact;
/// the price is that sticking is a creep: a slider held by friction against a tangential load
/// T < mu N slides at sdot = v_reg r / sqrt(1 - r^2), r = T / (mu N) (docs/theory.md).
///
/// Energy: the step's work of the friction force is F ds = -mu N h sdot^2 / sqrt(sdot^2 + v_reg^2)
/// <= 0 whatever N, so under energy-momentum (where the joint does no work) the step dissipates
/// exactly that (EnergyRole::Dissipative: D). No force in statics (h = 0: no rate).

#include "effects/common.hpp"

#include <cmath>
#include <stdexcept>

namespace slidebeam::effects {

class JointFriction final : public Effect {
 public:
  JointFriction(const Model& m, const EffectParams& p)
      : slider_(beam_param(m, p)), mu_(p.number("mu")), v_reg_(p.number("regularization", 1e-3)) {
    if (!(mu_ >= 0.0)) throw std::invalid_argument("friction: mu must be >= 0");
    if (!(v_reg_ > 0.0)) throw std::invalid_argument("friction: regularization must be > 0");
  }
  std::string type() const override { return "friction"; }
  std::string label() const override { return label_; }

  void distribute(const Model& m) override {
    // the sliding joint whose slider is this beam (the model creates constraints first: model.py)
    for (const auto& e : m.effects()) {
      if (e.get() == this) break;
      if (e->slider_beam() == slider_) joint_ = e.get();
    }
    if (!joint_)
      throw std::invalid_argument("friction: beam '" + m.beam(slider_).name() + "' is not the slider of a sliding_joint");
    label_ = "friction[" + m.beam(slider_).name() + "]";
  }
  /// What N reads is the joint's own unknowns, ghosted by the joint on the rank that evaluates it;
  /// s (and its step start) is among them.
  void needed_dofs(const Model&, std::vector<PetscInt>& dofs) const override { dofs.push_back(s_index()); }
  /// Every entry (the s row over s, the multipliers and what N depends on) lies in the joint's
  /// pattern of its s row.
  PetscErrorCode pattern(const Model&, const MatSink&) const override { return 0; }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    Eval ev;
    if (!evaluate(ctx, ev)) PetscFunctionReturn(0);
    r.at(s_index()) += mu_ * ev.N * ev.g;  // -F
    PetscFunctionReturn(0);
  }

  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    Eval ev;
    if (!evaluate(ctx, ev)) PetscFunctionReturn(0);
    // d(mu N g)/dx = mu g dN/dx + mu N g'(sdot) / h on s_n+1
    std::vector<double> row(ev.dofs.size());
    for (size_t k = 0; k < ev.dofs.size(); ++k) row[k] = mu_ * ev.g * ev.dN[k];
    const PetscInt s = s_index();
    bool has_s = false;
    for (size_t k = 0; k < ev.dofs.size(); ++k)
      if (ev.dofs[k] == s) {
        row[k] += mu_ * ev.N * ev.dg / ctx.h;
        has_s = true;
      }
    if (!has_s) {
      ev.dofs.push_back(s);
      row.push_back(mu_ * ev.N * ev.dg / ctx.h);
    }
    PetscCall(J.add(1, &s, static_cast<PetscInt>(ev.dofs.size()), ev.dofs.data(), row.data()));
    PetscFunctionReturn(0);
  }

 private:
  struct Eval {
    double N = 0.0, g = 0.0, dg = 0.0;  // normal force, sdot / sqrt(sdot^2 + v^2), d g / d sdot
    std::vector<PetscInt> dofs;
    std::vector<double> dN;
  };
  /// False where there is nothing to add: no step (statics), no friction, or not the joint's rank.
  bool evaluate(const EvalContext& ctx, Eval& ev) const {
    if (ctx.h <= 0.0 || mu_ == 0.0) return false;
    if (!joint_->normal_force(ctx, ev.N, ev.dofs, ev.dN)) return false;
    const double sdot = (ctx.x.at(s_index()) - ctx.x_old.at(s_index())) / ctx.h;
    const double q = std::sqrt(sdot * sdot + v_reg_ * v_reg_);
    ev.g = sdot / q;
    ev.dg = v_reg_ * v_reg_ / (q * q * q);
    return true;
  }
  /// The joint's s: its fourth extra (after the three multipliers).
  PetscInt s_index() const { return joint_->extra_offset() + 3; }

  int slider_;
  double mu_, v_reg_;
  const Effect* joint_ = nullptr;
  std::string label_ = "friction";
};

void register_friction_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  EffectSpec s;
  s.type = "friction";
  s.table = "friction";
  s.meaning = "regularised Coulomb friction on a sliding joint, from its normal force";
  s.role = EnergyRole::Dissipative;
  s.params = {
      {"beam", K::Beam, "", "the slider's beam (the slider of a [[sliding_joint]])", ""},
      {"mu", K::Number, "", "Coulomb friction coefficient", "", 0.0},
      {"regularization", K::Number, "m/s",
       "sliding rate below which the force grows linearly with the rate (sticking creeps at about this rate)", "1.0e-3",
       0.0, std::numeric_limits<double>::infinity(), true},
  };
  r.add(s, [](const Model& m, const EffectParams& p) { return std::make_unique<JointFriction>(m, p); });
}

}  // namespace slidebeam::effects
