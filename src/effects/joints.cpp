// SPDX-License-Identifier: MIT
/// @file Joints between beams. A rigid joint welds the end of one beam to the end of another:
/// same position, and the relative orientation of their end triads kept as in the reference
/// (an elbow, a T). Six multipliers: 3 for the positions, 3 for the orientation.

#include "effects/common.hpp"

#include <Eigen/Dense>
#include <stdexcept>

namespace slidebeam::effects {

namespace {
/// Control point index at a beam end, or an error naming the joint and the beam.
int joint_end_cp(const Beam& b, double s) {
  const int c = end_cp(b, s);
  if (c < 0) throw std::invalid_argument("rigid_joint: beam '" + b.name() + "' can only be joined at an end (start or end)");
  return c;
}
// The three orientation constraints e_a . dB_b = 0 with e_a = sum_i C_ia dA_i, for these (a, b)
// pairs: their gradients are the three axes of the relative rotation, hence independent.
constexpr int kPairs[3][2] = {{0, 1}, {1, 2}, {2, 0}};
}  // namespace

/// Rigid connection of two beam ends (formulation: position coincidence, plus e_a . dB_b = 0 for
/// three pairs, where e = A's triad turned into B's reference orientation). All constraints are
/// linear or bilinear in q, so the midpoint gradient is their exact discrete gradient.
class RigidJoint final : public Effect, public ReactionSource {
 public:
  RigidJoint(const Model& m, const EffectParams& p)
      : a_(static_cast<int>(p.number("beam_a"))), b_(static_cast<int>(p.number("beam_b"))) {
    for (int beam : {a_, b_})
      if (beam < 0 || beam >= static_cast<int>(m.beams().size()))
        throw std::invalid_argument("rigid_joint: no beam with index " + std::to_string(beam));
    if (a_ == b_) throw std::invalid_argument("rigid_joint: a beam cannot be joined to itself");
    const Beam &A = m.beam(a_), &B = m.beam(b_);
    for (const Beam* X : {&A, &B})
      if (X->is_ancf())
        throw std::invalid_argument("rigid_joint: beam '" + X->name() + "' is an ANCF cable (it has no directors to weld)");
    ca_ = joint_end_cp(A, p.number("s_a"));
    cb_ = joint_end_cp(B, p.number("s_b"));
    const double* qa = A.q_ref().data() + 12 * ca_;
    const double* qb = B.q_ref().data() + 12 * cb_;
    const Eigen::Vector3d pa(qa[0], qa[1], qa[2]), pb(qb[0], qb[1], qb[2]);
    const double scale = std::max(A.length(), B.length());
    if ((pa - pb).norm() > 1e-9 * scale)
      throw ParamError("beams", "'" + A.name() + "' " + (ca_ == 0 ? "start" : "end") + " at " + format_point(pa) +
                                    " and '" + B.name() + "' " + (cb_ == 0 ? "start" : "end") + " at " +
                                    format_point(pb) + " do not meet (distance " + format_number((pa - pb).norm()) + ")");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        C_(i, j) = Eigen::Map<const Eigen::Vector3d>(qa + 3 + 3 * i).dot(Eigen::Map<const Eigen::Vector3d>(qb + 3 + 3 * j));
    label_ = "rigid_joint[" + A.name() + (ca_ == 0 ? "@start" : "@end") + "-" + B.name() + (cb_ == 0 ? "@start" : "@end") + "]";
  }
  std::string type() const override { return "rigid_joint"; }
  std::string label() const override { return label_; }
  PetscInt n_extra() const override { return 6; }

  // evaluated where its multipliers live
  void distribute(const Model& m) override { owned_ = m.dof_map().owns_cp(anchor()); }
  bool reaction_reads_own() const override { return true; }
  /// The force and moment on beam A's end: minus the joint's own constraint forces there.
  void reaction(const Model& m, const ReactionInput& in, Reaction& out) const override {
    const PetscInt c = cp(m, a_, ca_);
    if (!m.dof_map().owns_cp(c)) return;
    Eigen::Vector3d M = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) out.force[k] -= in.own(m.dof_map().q(c, k));
    for (int i = 0; i < 3; ++i) {
      Eigen::Vector3d d, f;
      for (int k = 0; k < 3; ++k) {
        d(k) = in.x(m.dof_map().q(c, 3 + 3 * i + k));
        f(k) = in.own(m.dof_map().q(c, 3 + 3 * i + k));
      }
      M -= d.cross(f);
    }
    for (int k = 0; k < 3; ++k) out.moment[k] += M(k);
    out.has_moment = true;
  }
  PetscInt elimination_anchor(const Model& m) const override { return cp(m, a_, ca_); }
  void anchor_choices(const Model& m, std::vector<PetscInt>& cps) const override {
    cps.push_back(cp(m, a_, ca_));
    cps.push_back(cp(m, b_, cb_));
  }
  void reference_couplings(const Model& m, std::vector<std::pair<PetscInt, PetscInt>>& pairs) const override {
    pairs.emplace_back(cp(m, a_, ca_), cp(m, b_, cb_));
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    if (!owned_) return;
    add_cp_blocks(m.dof_map(), cp(m, a_, ca_), 1, dofs);
    add_cp_blocks(m.dof_map(), cp(m, b_, cb_), 1, dofs);
    for (int k = 0; k < 6; ++k) dofs.push_back(extra_offset() + k);
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const auto d = dofs(m);
    const double zero[30 * 30] = {};
    PetscCall(sink.add(30, d.data(), 30, d.data(), zero));
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const Vec24 y = gather(ctx, ctx.x), yf = gather(ctx, ctx.xf);
    const Vec6 mu = multipliers(ctx);
    const Mat6x24 Gf = gradient(yf);
    const Vec24 f = Gf.transpose() * mu;  // constraint forces at the force state
    const Vec6 g = value(y);              // constraints at the end of the step
    const auto d = dofs(ctx.model);
    for (int k = 0; k < 24; ++k) r.at(d[k]) += f(k);
    for (int k = 0; k < 6; ++k) r.at(d[24 + k]) += g(k);
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const Vec24 y = gather(ctx, ctx.x), yf = gather(ctx, ctx.xf);
    const Vec6 mu = multipliers(ctx);
    Eigen::Matrix<double, 30, 30, Eigen::RowMajor> A = Eigen::Matrix<double, 30, 30, Eigen::RowMajor>::Zero();
    // d/dq (G(q_f)^T mu) = theta sum_k mu_k H_k, H_k: C_ia I3 between dA_i and dB_b
    for (int k = 0; k < 3; ++k) {
      const int a = kPairs[k][0], b = kPairs[k][1];
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) {
          const double h = ctx.theta * mu(3 + k) * C_(i, a);
          A(3 + 3 * i + c, 15 + 3 * b + c) += h;
          A(15 + 3 * b + c, 3 + 3 * i + c) += h;
        }
    }
    A.block<24, 6>(0, 24) = gradient(yf).transpose();
    A.block<6, 24>(24, 0) = gradient(y);
    const auto d = dofs(ctx.model);
    PetscCall(J.add(30, d.data(), 30, d.data(), A.data()));
    PetscFunctionReturn(0);
  }

 private:
  using Vec24 = Eigen::Matrix<double, 24, 1>;
  using Mat6x24 = Eigen::Matrix<double, 6, 24>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;

  static PetscInt cp(const Model& m, int beam, int c) { return m.beam(beam).first_cp() + c; }
  /// The 12 coordinates of A's end control point, B's, then the 6 multipliers.
  std::array<PetscInt, 30> dofs(const Model& m) const {
    std::array<PetscInt, 30> d{};
    for (int k = 0; k < 12; ++k) {
      d[k] = m.dof_map().q(cp(m, a_, ca_), k);
      d[12 + k] = m.dof_map().q(cp(m, b_, cb_), k);
    }
    for (int k = 0; k < 6; ++k) d[24 + k] = extra_offset() + k;
    return d;
  }
  Vec24 gather(const EvalContext& ctx, const LocalValues& x) const {
    Vec24 y;
    y.head<12>() = Eigen::Map<const Eigen::Matrix<double, 12, 1>>(x.cp(ctx.map, cp(ctx.model, a_, ca_)));
    y.tail<12>() = Eigen::Map<const Eigen::Matrix<double, 12, 1>>(x.cp(ctx.map, cp(ctx.model, b_, cb_)));
    return y;
  }
  Vec6 multipliers(const EvalContext& ctx) const {
    Vec6 mu;
    for (int k = 0; k < 6; ++k) mu(k) = ctx.x.at(extra_offset() + k);
    return mu;
  }
  /// e_a = sum_i C_ia dA_i
  Eigen::Vector3d turned(const Vec24& y, int a) const {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i) e += C_(i, a) * y.segment<3>(3 + 3 * i);
    return e;
  }
  Vec6 value(const Vec24& y) const {
    Vec6 g;
    g.head<3>() = y.segment<3>(0) - y.segment<3>(12);
    for (int k = 0; k < 3; ++k) g(3 + k) = turned(y, kPairs[k][0]).dot(y.segment<3>(15 + 3 * kPairs[k][1]));
    return g;
  }
  Mat6x24 gradient(const Vec24& y) const {
    Mat6x24 G = Mat6x24::Zero();
    G.block<3, 3>(0, 0) = Eigen::Matrix3d::Identity();
    G.block<3, 3>(0, 12) = -Eigen::Matrix3d::Identity();
    for (int k = 0; k < 3; ++k) {
      const int a = kPairs[k][0], b = kPairs[k][1];
      const Eigen::Vector3d dB = y.segment<3>(15 + 3 * b);
      for (int i = 0; i < 3; ++i) G.block<1, 3>(3 + k, 3 + 3 * i) = C_(i, a) * dB.transpose();
      G.block<1, 3>(3 + k, 15 + 3 * b) = turned(y, a).transpose();
    }
    return G;
  }

  int a_, b_, ca_ = 0, cb_ = 0;
  Eigen::Matrix3d C_;  ///< C_ij = dA_i . dB_j in the reference
  std::string label_;
  bool owned_ = false;
};

void register_joint_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  r.add(table_effect_spec("rigid_joint", "rigid_joint", "", EnergyRole::Constraint,
                          "two beam ends welded together, positions and directors",
                          {{"beams", K::Beams, "", "the two beams' names, e.g. [\"leg1\", \"leg2\"] (the joint welds director triads, which an ANCF "
                            "cable has not)", "", 0, 0, false, 2,
                            {"director"}},
                           {"at", K::Ends, "", "which end of each beam", "[\"end\", \"start\"]", 0, 0, false, 2}}),
        [](const Model& m, const EffectParams& p) { return std::make_unique<RigidJoint>(m, p); });
}

}  // namespace slidebeam::effects
