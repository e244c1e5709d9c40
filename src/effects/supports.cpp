// SPDX-License-Identifier: MIT
/// @file Supports. At a beam end a support prescribes unknowns of the interpolating end control
/// point (eliminated from the Newton system by identity rows); a spherical support inside a
/// beam adds three multipliers for r(s) = X (director: sum_A N^A(s) phi^A; ANCF: the Hermite
/// interpolation of the element's r and r'). On an ANCF cable a clamp fixes the end node's r and
/// r' (so also the stretch |r'| = 1 at that point, as in Exudyn's clamped cables).

#include "effects/common.hpp"
#include "model/time_function.hpp"

#include <Eigen/Dense>
#include <stdexcept>

namespace slidebeam::effects {

namespace {
/// Prescribe coordinates (component range [k0, k1)) of one control point, and optionally its
/// multipliers (director control points; ANCF nodes have none).
void prescribe_cp(const Model& m, const Beam& b, int c, int k0, int k1, const double* values, bool multipliers,
                  std::vector<PetscInt>& rows, std::vector<PetscScalar>& vals) {
  const PetscInt cp = b.first_cp() + c;
  for (int k = k0; k < k1; ++k) {
    rows.push_back(m.dof_map().q(cp, k));
    vals.push_back(values[k - k0]);
  }
  if (multipliers)
    for (int k = 0; k < b.multipliers_per_cp(); ++k) {
      rows.push_back(m.dof_map().lambda(cp, k));
      vals.push_back(0.0);
    }
}

/// The force on a control point's prescribed position rows and the moment of its director rows,
/// M = sum_i d_i x f_di (a rotation dtheta moves d_i by dtheta x d_i): what a support holding the
/// point supplies. ANCF nodes: r and r', with r' in the place of the one director.
void add_point_reaction(const Model& m, const Beam& b, int c, bool moment, const Eigen::Vector3d& about,
                        const ReactionInput& in, Reaction& out) {
  const PetscInt cp = b.first_cp() + c;
  if (!m.dof_map().owns_cp(cp)) return;
  Eigen::Vector3d f, phi;
  for (int k = 0; k < 3; ++k) {
    f(k) = in.raw(m.dof_map().q(cp, k));
    phi(k) = in.x(m.dof_map().q(cp, k));
  }
  Eigen::Vector3d M = (phi - about).cross(f);
  const int n_dirs = b.is_ancf() ? 1 : 3;
  for (int i = 0; i < n_dirs; ++i) {
    Eigen::Vector3d d, fd;
    for (int k = 0; k < 3; ++k) {
      d(k) = in.x(m.dof_map().q(cp, 3 + 3 * i + k));
      fd(k) = in.raw(m.dof_map().q(cp, 3 + 3 * i + k));
    }
    M += d.cross(fd);
  }
  for (int k = 0; k < 3; ++k) {
    out.force[k] += f(k);
    if (moment) out.moment[k] += M(k);
  }
  out.has_moment = moment;
}

/// A support's prescribed motion (scene: [[support]] motion = {displacement, rotation,
/// time_function}): at time t the held point is displaced by f(t) U and (clamps) its directors
/// turned by the rotation vector f(t) Theta; f(0) = 0, so the reference state meets it.
struct SupportMotion {
  Eigen::Vector3d U = Eigen::Vector3d::Zero(), Theta = Eigen::Vector3d::Zero();
  TimeFunction f;
  bool active = false;

  explicit SupportMotion(const EffectParams& p) {
    if (p.vec.count("motion_displacement")) {
      U = vector3_param(p, "motion_displacement");
      active = true;
    }
    if (p.vec.count("motion_rotation")) {
      Theta = vector3_param(p, "motion_rotation");
      active = true;
    }
    f = TimeFunction::from(p);
  }
  Eigen::Vector3d displacement(double t) const { return f(t) * U; }
  Eigen::Matrix3d rotation(double t) const {
    const Eigen::Vector3d th = f(t) * Theta;
    const double a = th.norm();
    if (a == 0.0) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(a, th / a).toRotationMatrix();
  }
  /// A control point's coordinates q (nq of them: the position, then 3-blocks that turn: the
  /// directors, an ANCF node's r') moved rigidly at time t about pivot: X -> pivot + f U +
  /// R (X - pivot), each block -> R block.
  void move(double* q, int nq, const Eigen::Vector3d& pivot, double t) const {
    const Eigen::Matrix3d R = rotation(t);
    Eigen::Map<Eigen::Vector3d> x(q);
    x = pivot + displacement(t) + R * (Eigen::Vector3d(x) - pivot);
    for (int blk = 1; blk < nq / 3; ++blk) {
      Eigen::Map<Eigen::Vector3d> d(q + 3 * blk);
      d = R * Eigen::Vector3d(d);
    }
  }
};

/// The prescribed motion of a support, from its `motion` table: at rest, or moved by it (then
/// it drives: the energy balance counts its work).
class MovableSupport : public PrescribedMotion {
 public:
  explicit MovableSupport(const EffectParams& p) : motion_(p) {}
  bool drives() const override { return motion_.active; }
  void prescribed(const Model& m, std::vector<PetscInt>& rows, std::vector<PetscScalar>& vals) const override {
    prescribed_at(m, 0.0, rows, vals);
  }

 protected:
  SupportMotion motion_;
};

/// Base of effects with no residual of their own (pure elimination).
class PrescribingSupport : public Effect, public MovableSupport {
 public:
  explicit PrescribingSupport(const EffectParams& p) : MovableSupport(p) {}
  void distribute(const Model&) override {}
  void needed_dofs(const Model&, std::vector<PetscInt>&) const override {}
  PetscErrorCode pattern(const Model&, const MatSink&) const override { return 0; }
  PetscErrorCode residual(const EvalContext&, const LocalValues&) const override { return 0; }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override { return 0; }
};
}  // namespace

/// Clamp at a beam end: position and directors of the end control point fixed. Its orthonormality
/// multipliers are dropped too (fixed orthonormal directors satisfy the constraints identically).
class Clamp final : public PrescribingSupport, public ReactionSource {
 public:
  Clamp(const Model& m, const EffectParams& p) : PrescribingSupport(p), beam_(beam_param(m, p)) {
    const Beam& b = m.beam(beam_);
    cp_ = end_cp(b, p.number("s"));
    if (cp_ < 0) throw std::invalid_argument("clamp on beam '" + b.name() + "': only at a beam end (s = 0 or L)");
  }
  std::string type() const override { return "clamp"; }
  std::string label() const override { return "clamp[" + std::to_string(beam_) + (cp_ == 0 ? ":start]" : ":end]"); }
  /// The reference position displaced, the reference directors (ANCF: r') turned.
  void prescribed_at(const Model& m, double t, std::vector<PetscInt>& rows, std::vector<PetscScalar>& vals) const override {
    const Beam& b = m.beam(beam_);
    const int nq = b.coordinates_per_cp();
    std::vector<double> q(b.q_ref().begin() + nq * cp_, b.q_ref().begin() + nq * (cp_ + 1));
    if (motion_.active) {  // about the held point itself: displaced, its directors turned
      const Eigen::Vector3d held = Eigen::Map<const Eigen::Vector3d>(q.data());
      motion_.move(q.data(), nq, held, t);
    }
    prescribe_cp(m, b, cp_, 0, nq, q.data(), true, rows, vals);
  }
  /// The force and the moment about the held point (where it is now).
  void reaction(const Model& m, const ReactionInput& in, Reaction& out) const override {
    const Beam& b = m.beam(beam_);
    Eigen::Vector3d X = Eigen::Map<const Eigen::Vector3d>(b.q_ref().data() + b.coordinates_per_cp() * cp_);
    const PetscInt cp = b.first_cp() + cp_;
    if (m.dof_map().owns_cp(cp))
      for (int k = 0; k < 3; ++k) X(k) = in.x(m.dof_map().q(cp, k));
    add_point_reaction(m, b, cp_, true, X, in, out);
  }

 private:
  int beam_;
  int cp_;
};

/// Every control point of a beam prescribed: a rigid rail. At its reference state, or moved
/// rigidly: displaced by f(t) U and turned by the rotation vector f(t) Theta about the beam's
/// start (its points X -> X_0 + f U + R (X - X_0), its directors, ANCF: r', turned by R).
class Fixed final : public PrescribingSupport, public ReactionSource {
 public:
  Fixed(const Model& m, const EffectParams& p) : PrescribingSupport(p), beam_(beam_param(m, p)) {}
  std::string type() const override { return "fixed"; }
  std::string label() const override { return "fixed[" + std::to_string(beam_) + "]"; }
  void prescribed_at(const Model& m, double t, std::vector<PetscInt>& rows, std::vector<PetscScalar>& vals) const override {
    const Beam& b = m.beam(beam_);
    const int nq = b.coordinates_per_cp();
    if (!motion_.active) {
      for (int c = 0; c < b.n_cp(); ++c) prescribe_cp(m, b, c, 0, nq, b.q_ref().data() + nq * c, true, rows, vals);
      return;
    }
    const Eigen::Vector3d X0 = Eigen::Map<const Eigen::Vector3d>(b.q_ref().data());
    std::vector<double> q(static_cast<size_t>(nq));
    for (int c = 0; c < b.n_cp(); ++c) {
      std::copy(b.q_ref().begin() + nq * c, b.q_ref().begin() + nq * (c + 1), q.begin());
      motion_.move(q.data(), nq, X0, t);
      prescribe_cp(m, b, c, 0, nq, q.data(), true, rows, vals);
    }
  }
  /// The force, and the moment about the beam's start in the reference configuration (the
  /// same point on every rank).
  void reaction(const Model& m, const ReactionInput& in, Reaction& out) const override {
    const Beam& b = m.beam(beam_);
    const Eigen::Vector3d X = Eigen::Map<const Eigen::Vector3d>(b.q_ref().data());
    for (int c = 0; c < b.n_cp(); ++c) add_point_reaction(m, b, c, true, X, in, out);
  }

 private:
  int beam_;
};

/// Spherical support: the centre line passes through X at beam point s; directors free.
class Spherical final : public Effect, public MovableSupport, public ExtraUnknowns, public ReactionSource {
 public:
  Spherical(const Model& m, const EffectParams& p) : MovableSupport(p), beam_(beam_param(m, p)), s_(p.number("s")) {
    const Beam& b = m.beam(beam_);
    if (s_ < -1e-12 * b.length() || s_ > b.length() * (1 + 1e-12))
      throw std::invalid_argument("spherical support: s = " + std::to_string(s_) + " outside beam '" + b.name() + "'");
    if (b.is_rigid()) {  // a body's point, given where it is drawn: held by multipliers
      const Eigen::Vector3d at = vector3_param(p, "point");
      stencil_ = b.body_point_drawn({at(0), at(1), at(2)});
    } else {
      cp_ = end_cp(b, s_);
      stencil_ = b.position_at(s_);
    }
    // the discretised reference centre line's point (a spline through a polyline's corner or
    // along an arc passes beside the drawn one): the reference state meets the support
    X_ = drawn_point(b, stencil_);
  }
  std::string type() const override { return "spherical"; }
  std::string label() const override { return "spherical[" + std::to_string(beam_) + "@" + std::to_string(s_) + "]"; }
  PetscInt n_extra() const override { return cp_ < 0 ? 3 : 0; }
  void prescribed_at(const Model& m, double t, std::vector<PetscInt>& rows, std::vector<PetscScalar>& vals) const override {
    const Eigen::Vector3d X = held(t);
    if (cp_ >= 0) prescribe_cp(m, m.beam(beam_), cp_, 0, 3, X.data(), false, rows, vals);
  }
  void distribute(const Model& m) override { owned_ = cp_ < 0 && owns_span(m, m.beam(beam_), stencil_.span); }
  /// At a beam end the prescribed position rows' force; inside, -mu (the multipliers are the
  /// force of the beam on the support).
  void reaction(const Model& m, const ReactionInput& in, Reaction& out) const override {
    if (cp_ >= 0) {
      add_point_reaction(m, m.beam(beam_), cp_, false, X_, in, out);  // a force only: the point is immaterial
      return;
    }
    for (int k = 0; k < 3; ++k) out.force[k] -= in.x(extra_offset() + k);
  }
  /// The last control point the support couples to.
  PetscInt elimination_anchor(const Model& m) const override {
    return m.beam(beam_).first_cp() + stencil_.cp[stencil_.n - 1];
  }
  void anchor_points(const Model& m, std::vector<PetscInt>& cps) const override {
    for (int j = 0; j < stencil_.n; ++j) cps.push_back(m.beam(beam_).first_cp() + stencil_.cp[j]);
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    if (!owned_) return;
    for (int j = 0; j < stencil_.n; ++j) add_cp_blocks(m.dof_map(), m.beam(beam_).first_cp() + stencil_.cp[j], 1, dofs);
    for (int k = 0; k < 3; ++k) dofs.push_back(extra_offset() + k);
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (owned_) PetscCall(add_block_pattern(sink, dofs(m.dof_map(), m)));
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const Eigen::Vector3d mu(ctx.x.at(extra_offset()), ctx.x.at(extra_offset() + 1), ctx.x.at(extra_offset() + 2));
    const Beam& b = ctx.model.beam(beam_);
    // the constraint holds at the end of the step (a step's h > 0), else at the evaluation's time
    const Eigen::Vector3d gap = stencil_point(ctx.x, ctx.map, b, stencil_) - held(ctx.h > 0.0 ? ctx.t_end : ctx.t);
    scatter_stencil(r, ctx.map, b, stencil_, mu);
    for (int k = 0; k < 3; ++k) r.at(extra_offset() + k) += gap(k);
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const int n = 3 * stencil_.n + 3;  // stencil coordinates, then the multipliers
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMajor A = RowMajor::Zero(n, n);
    for (int a = 0; a < stencil_.n; ++a)
      for (int k = 0; k < 3; ++k) A(3 * a + k, n - 3 + k) = A(n - 3 + k, 3 * a + k) = stencil_.w[a];
    const auto d = dofs(ctx.map, ctx.model);
    PetscCall(J.add(n, d.data(), n, d.data(), A.data()));
    PetscFunctionReturn(0);
  }

 private:
  /// The stencil's coordinates (director: phi of the span's 3 control points), then the 3 multipliers.
  std::vector<PetscInt> dofs(const DofMap& map, const Model& m) const {
    std::vector<PetscInt> d = stencil_dofs(map, m.beam(beam_), stencil_);
    for (int k = 0; k < 3; ++k) d.push_back(extra_offset() + k);
    return d;
  }
  Eigen::Vector3d held(double t) const { return motion_.active ? Eigen::Vector3d(X_ + motion_.displacement(t)) : X_; }
  int beam_;
  double s_;
  Eigen::Vector3d X_;
  int cp_ = -1;
  PositionStencil stencil_;
  bool owned_ = false;
};

void register_support_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const ParamSpec beam{"beam", K::Beam, "", "the beam it holds", ""};
  const ParamSpec motion{"motion", K::Motion, "",
                         "prescribed motion: {displacement = [m], time_function = {...}} (the held point moves by "
                         "f(t) times the displacement; f(0) = 0)",
                         "", 0, 0, false, 3};
  ParamSpec clamp_motion = motion;
  clamp_motion.size = 6;
  clamp_motion.meaning =
      "prescribed motion: {displacement = [m], rotation = [rad], time_function = {...}} (the end moves by f(t) times "
      "the displacement and turns by the rotation vector f(t) times rotation; f(0) = 0)";
  r.add(table_effect_spec("clamp", "support", "clamp", EnergyRole::Constraint,
                          "a beam point held in place and orientation",
                          {beam,
                           {"at", K::Point, "m",
                            "the point: \"start\", \"end\" or an arc length in [0, L] (inside a beam, a rigid joint "
                            "to the ground); on a body, where it is drawn",
                            ""},
                           optional_param(clamp_motion)}),
        [](const Model& m, const EffectParams& p) -> std::unique_ptr<Effect> {
          const Beam& b = m.beam(beam_param(m, p));
          if (!b.is_rigid() && end_cp(b, p.number("s")) >= 0) return std::make_unique<Clamp>(m, p);
          if (SupportMotion(p).active)
            throw ParamError("motion", "only a clamp at a beam end moves (a clamp inside a beam or on a body is welded "
                                       "to the ground; a body moves with [[support]] type = \"fixed\")");
          return make_clamp_inside(m, p);
        });
  ParamSpec fixed_motion = clamp_motion;
  fixed_motion.meaning =
      "prescribed rigid motion: {displacement = [m], rotation = [rad], time_function = {...}} (the beam moves by "
      "f(t) times the displacement and turns about its start by the rotation vector f(t) times rotation; f(0) = 0)";
  r.add(table_effect_spec("fixed", "support", "fixed", EnergyRole::Constraint, "every control point of a beam held",
                          {beam, optional_param(fixed_motion)}),
        [](const Model& m, const EffectParams& p) { return std::make_unique<Fixed>(m, p); });
  r.add(table_effect_spec("spherical", "support", "spherical", EnergyRole::Constraint,
                          "a beam point held in place, free to turn",
                          {beam, {"at", K::Point, "m", "the point: \"start\", \"end\" or an arc length in [0, L]", ""},
                           optional_param({"position", K::Position, "m",
                                           "the point's position, as a check: it must be the beam's point at `at`", ""}),
                           optional_param(motion)}),
        [](const Model& m, const EffectParams& p) { return std::make_unique<Spherical>(m, p); });
}

}  // namespace slidebeam::effects
