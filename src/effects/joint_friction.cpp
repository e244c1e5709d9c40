// SPDX-License-Identifier: MIT
/// @file Coulomb friction on a sliding joint (scene table [[friction]]), with true stick
/// (docs/theory.md, "Friction that sticks").
///
/// The friction force F on the joint's sliding coordinate s is an unknown of its own. It enters
/// the joint's s row, the force balance of the massless s: G_s . lambda - F = 0, so F is the
/// joint's tangential force on the slider (per unit of s: s is the carrier's reference arc
/// length, so on a stretched carrier the force itself is F / |c'|). Its own row is Coulomb's law
/// over the step, with the mean sliding rate sdot = (s_n+1 - s_n) / h and the normal force
/// N = |Lambda - (t . Lambda) t| (JointTarget::normal_force: the joint's force on the slider
/// transverse to the carrier's unit tangent t at s, at the joint's force state):
///
///   |F| <= mu N,   and   sdot = 0 where |F| < mu N,   F = -mu N sdot / |sdot| where sdot != 0,
///
/// written as one equation, C = F - proj_[-mu N, mu N](F - r sdot) = 0 for any r > 0 (the
/// natural map of the complementarity problem). C is piecewise smooth; with z = F - r sdot:
///   stick, |z| <= mu N:  C = r sdot            (s stays where the step started);
///   slip,  z > mu N:     C = F - mu N          (moving toward -s: the full force toward +s);
///   slip,  z < -mu N:    C = F + mu N.
/// Newton takes the branch of its iterate and that branch's derivative (semi-smooth Newton):
/// once the branch is right, the step converges as without friction. The solution does not
/// depend on r; the path does. An iterate that slipped past the stop (a sdot of the wrong sign,
/// of the order of the friction's deceleration times h) must fall into stick, not into a slip the
/// other way (which would alternate with it): r below the inverse Delassus scale m_eff / h of
/// the motion along s. r = m / (100 h), m the slider beam's translational mass
/// (Model::beam_mass). A tie within 1e-6 mu N counts as stick:
/// a load exactly at the limit (tan(alpha) = mu) holds, whatever the noise of the converged
/// multipliers and the slider's small oscillations in N (up to about 1e-7 of mu N).
///
/// A driven slider's s is prescribed ([[slider_drive]]): there is nothing to stick, and the
/// friction is -mu N times the sign of the prescribed rate (0 while the drive holds s still);
/// it adds to the drive's force.
///
/// Energy: the step's work of friction is F (s_n+1 - s_n): 0 in stick, -mu N |s_n+1 - s_n| in
/// slip, never positive, and under energy-momentum (the joint does no work) exactly what the
/// step dissipates (EnergyRole::Dissipative: D). No friction in statics (h = 0: no rate): F = 0.

#include "effects/common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace slidebeam::effects {

class JointFriction final : public Effect, public ExtraUnknowns, public SlidingJointLink {
 public:
  JointFriction(const Model& m, const EffectParams& p)
      : SlidingJointLink(m, p, "friction"), mu_(p.number("mu")) {
    if (!(mu_ >= 0.0)) throw ParamError("mu", "friction: mu must be >= 0");
  }
  std::string type() const override { return "friction"; }
  std::string label() const override { return label_; }
  /// F, the friction force on s.
  PetscInt n_extra() const override { return 1; }

  void distribute(const Model& m) override {
    label_ = link_label(m);
    owned_ = extra_offset() >= m.dof_map().owned_lo() && extra_offset() < m.dof_map().owned_hi();
  }
  /// F sits with the joint's own extras: after s, whose row holds F's pivot in stick.
  PetscInt elimination_anchor(const Model& m) const override {
    return joint_anchor(m);
  }
  /// What N reads is the joint's own unknowns, ghosted by the joint on the rank that evaluates it;
  /// s (and its step start) is among them.
  void needed_dofs(const Model&, std::vector<PetscInt>& dofs) const override {
    dofs.push_back(s_index());
    dofs.push_back(extra_offset());
  }
  /// The F row over (F, s, the multipliers) and the s row's F column; the rest of the F row (what
  /// N depends on: the carrier around s, the slider's directors) moves with s, and the
  /// Jacobian's COO assembly records it where it is.
  PetscErrorCode pattern(const Model&, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const PetscInt F = extra_offset(), s = s_index();
    const PetscInt mu = joint_->joint_unknowns().extra_offset();
    const PetscInt cols[5] = {F, s, mu, mu + 1, mu + 2};
    const double zero[5] = {0, 0, 0, 0, 0};
    PetscCall(sink.add(1, &F, 5, cols, zero));
    PetscCall(sink.add(1, &s, 1, &F, zero));
    PetscFunctionReturn(0);
  }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    Law law;
    if (!evaluate(ctx, law)) PetscFunctionReturn(0);
    const double F = ctx.x.at(extra_offset());
    r.at(s_index()) -= F;
    r.at(extra_offset()) += law.branch == Branch::Stick ? law.r * law.sdot : F - law.limit;
    PetscFunctionReturn(0);
  }

  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    Law law;
    if (!evaluate(ctx, law)) PetscFunctionReturn(0);
    const PetscInt F = extra_offset(), s = s_index();
    const double minus_one = -1.0;
    PetscCall(J.add(1, &s, 1, &F, &minus_one));
    // the F row over F, s and N's unknowns, whatever the branch (the pattern stays the same
    // when the branch changes)
    std::vector<PetscInt> cols{F, s};
    std::vector<double> row{0.0, 0.0};
    for (size_t k = 0; k < law.dofs.size(); ++k) {
      if (law.dofs[k] == s) continue;
      cols.push_back(law.dofs[k]);
      row.push_back(0.0);
    }
    if (law.branch == Branch::Stick) {
      row[1] = law.r / ctx.h;
    } else {
      row[0] = 1.0;
      // F - limit, limit = sign mu N: -sign mu dN
      for (size_t k = 0, j = 2; k < law.dofs.size(); ++k) {
        const double d = -law.sign * mu_ * law.dN[k];
        if (law.dofs[k] == s) row[1] += d;
        else row[j++] = d;
      }
    }
    PetscCall(J.add(1, &F, static_cast<PetscInt>(cols.size()), cols.data(), row.data()));
    PetscFunctionReturn(0);
  }

 private:
  enum class Branch { Stick, Slip };
  struct Law {
    Branch branch = Branch::Slip;
    double sign = 0.0;   // slip: F = sign mu N (+1: the force toward +s)
    double limit = 0.0;  // slip: sign mu N
    double r = 0.0, sdot = 0.0;
    std::vector<PetscInt> dofs;  // what N depends on
    std::vector<double> dN;
  };
  /// The branch of the law at the iterate, false where there is nothing to add (not the joint's
  /// rank). Statics: the slip branch with sign 0, F = 0.
  bool evaluate(const EvalContext& ctx, Law& law) const {
    double N = 0.0;
    if (!joint_->normal_force(ctx, N, law.dofs, law.dN)) return false;
    law.branch = Branch::Slip;
    law.sign = 0.0;
    if (ctx.h <= 0.0 || mu_ == 0.0) {
      law.limit = 0.0;
      return true;
    }
    const double s1 = ctx.x.at(s_index()), s0 = ctx.x_old.at(s_index());
    law.sdot = (s1 - s0) / ctx.h;
    if (driven(ctx.model)) {
      // the prescribed rate's sign; a rate at roundoff (s held still) has none
      const double ds = s1 - s0;
      if (std::abs(ds) > 64 * std::numeric_limits<double>::epsilon() * (std::abs(s0) + std::abs(s1)))
        law.sign = ds > 0.0 ? -1.0 : 1.0;
    } else {
      double m = joint_->sliding_mass(ctx.model);
      if (!(m > 0.0))  // a massless slider beam: the model's mass sets the scale
        for (size_t b = 0; b < ctx.model.beams().size(); ++b) m += ctx.model.beam_mass(static_cast<int>(b));
      law.r = kDelassusShare * std::max(m, std::numeric_limits<double>::min()) / ctx.h;
      const double z = ctx.x.at(extra_offset()) - law.r * law.sdot, muN = mu_ * N;
      if (std::abs(z) <= muN * (1.0 + kTie)) law.branch = Branch::Stick;
      else law.sign = z > 0.0 ? 1.0 : -1.0;
    }
    law.limit = law.sign * mu_ * N;
    return true;
  }
  /// True when another effect prescribes s (a slider drive). Looked up at the first evaluation,
  /// once every effect is distributed.
  bool driven(const Model& m) const {
    if (driven_ < 0) {
      driven_ = 0;
      for (const auto& e : m.effects()) {
        std::vector<PetscInt> rows;
        const auto* held = part_of<PrescribedMotion>(*e);
        if (held && part_of<JointTarget>(*e) != joint_) held->constrained_state(rows);
        if (std::find(rows.begin(), rows.end(), s_index()) != rows.end()) driven_ = 1;
      }
    }
    return driven_ == 1;
  }

  /// r = kDelassusShare m / h. m / h is the inverse Delassus scale of the slider beam's whole mass;
  /// what opposes the sliding rate can be much less (the top of a pendulum whose bob swings
  /// freely), and an r above that inverse makes slip-+ and slip-- alternate. A hundredth covers
  /// effective masses down to 1 % of the beam's (measured: docs/theory.md).
  static constexpr double kDelassusShare = 0.01;
  /// A load within this share of mu N above the limit still sticks (the converged multipliers' noise
  /// and the oscillation of N at the limit: 1e-8 alternated between the branches on a block at
  /// tan(alpha) = mu, 1e-7 held it).
  static constexpr double kTie = 1e-6;
  double mu_;
  mutable int driven_ = -1;
  bool owned_ = false;
  std::string label_ = "friction";
};

void register_friction_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const EffectSpec s = table_effect_spec(
      "friction", "friction", "", EnergyRole::Dissipative,
      "Coulomb friction on a sliding joint or a guide, from its normal force: the slider (the rope at a guide) "
      "sticks while the tangential load is below mu N",
      {optional_param({"beam", K::Beam, "", "the slider's beam (the slider of a [[sliding_joint]])", ""}),
       optional_param({"guide", K::Name, "", "or: the [[guide]] it acts at, by its name", ""}),
       {"mu", K::Number, "", "Coulomb friction coefficient", "", 0.0}});
  r.add(s, [](const Model& m, const EffectParams& p) { return std::make_unique<JointFriction>(m, p); });
}

}  // namespace slidebeam::effects