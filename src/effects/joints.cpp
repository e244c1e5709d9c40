// SPDX-License-Identifier: MIT
/// @file Joints between two beam points, anywhere along either beam ([[joint]]; [[rigid_joint]]
/// is the rigid kind at beam ends):
///  - spherical: the two centre-line points coincide (3 multipliers);
///  - universal: and an axis fixed to the first beam stays perpendicular to one fixed to the
///    second (the cross of a Cardan joint; 4);
///  - revolute: and a hinge axis fixed to the first beam stays perpendicular to two directions
///    fixed to the second, so that the hinge turns about it alone (5);
///  - rigid: and the relative orientation of the two triads is kept (welded; 6).
/// The same joints hold a beam point (or a body point) to a point fixed in space ([[support]]
/// type = "revolute", "universal", and a clamp inside a beam or on a body): the second side is
/// then the ground, whose position and triad (the global axes) are constants.
/// Positions are the beams' centre-line interpolation at the two arc lengths (director beams and
/// ANCF cables); orientations use the director triad interpolated there, D(s) = sum_j N_j(s)
/// (d1, d2, d3)_j. An ANCF cable has no section frame: a rigid joint holds its slope r' at a node
/// (D = [r', 0, 0]), perpendicular to two directions fixed to the other side's frame (2
/// constraints), or, between two cables, equal to the other's slope scaled as drawn (3, linear:
/// the cable continues as through one of its own nodes). Each orientation
/// constraint is a bilinear form (D_A u) . (D_B v) - g0 with constant component vectors u, v and
/// its reference value g0; the positions are linear. So the midpoint gradient is every
/// constraint's exact discrete gradient, and under energy-momentum a joint does no work over a step.

#include "effects/common.hpp"

#include <Eigen/Dense>
#include <stdexcept>

namespace slidebeam::effects {

namespace {

enum class JointKind { Spherical, Universal, Revolute, Rigid };

int orientation_constraints(JointKind k) {
  switch (k) {
    case JointKind::Spherical: return 0;
    case JointKind::Universal: return 1;
    case JointKind::Revolute: return 2;
    case JointKind::Rigid: return 3;
  }
  return 0;
}

const char* kind_type(JointKind k) {
  switch (k) {
    case JointKind::Spherical: return "spherical_joint";
    case JointKind::Universal: return "universal_joint";
    case JointKind::Revolute: return "revolute_joint";
    case JointKind::Rigid: return "welded_joint";
  }
  return "joint";
}

/// One side of a joint: the control points its beam point interpolates from; default-constructed
/// (beam -1), the ground.
struct JointSide {
  int beam = -1;
  double s = 0.0;
  int coords = 12;  ///< coordinates per control point (director 12, ANCF 6)
  int n = 0;        ///< control points with a nonzero weight
  std::array<int, 4> cp{};  ///< their indices within the beam
  /// The position r(s) = sum_e w[e] y(point[e], comp[e] .. + 2): director beams one entry per
  /// control point (phi), ANCF cables r and r' of the element's two nodes.
  int entries = 0;
  std::array<int, 4> point{}, comp{};
  std::array<double, 4> w{};
  /// Director beams (and bodies: 1): N_j of control point j, which also interpolates the directors.
  std::array<double, 4> N{};
  /// The control point with the largest weight: where the joint's multipliers find pivots.
  int main = 0;
  /// The ground (beam < 0): the fixed point.
  Eigen::Vector3d X = Eigen::Vector3d::Zero();
  /// Columns of the side's triad D that are unknowns: 3 (d1, d2, d3), 1 (an ANCF node's r').
  int directors = 3;

  JointSide() = default;
  /// From the point's position stencil (a beam's at arc length s, or a body point's).
  JointSide(const PositionStencil& st, int index, double s_, int coords_) : beam(index), s(s_), coords(coords_) {
    double largest = -1.0;
    for (int e = 0; e < st.n; ++e) {
      if (std::abs(st.w[e]) <= 1e-14) continue;  // (the other points of a span at its end)
      int j = 0;
      while (j < n && cp[j] != st.cp[e]) ++j;
      if (j == n) cp[n++] = st.cp[e];
      point[entries] = j;
      comp[entries] = st.comp[e];
      w[entries] = st.w[e];
      ++entries;
      if (st.comp[e] == 0) {
        N[j] = st.w[e];
        if (std::abs(st.w[e]) > largest) {
          largest = std::abs(st.w[e]);
          main = j;
        }
      }
    }
  }
  int size() const { return n * coords; }
  bool ground() const { return beam < 0; }
};


}  // namespace

class Joint final : public Effect, public ExtraUnknowns, public NumberingHints, public ReactionSource {
 public:
  /// Two beam (or body) points: beam_a at s_a and beam_b at s_b (on a body: point_a, point_b,
  /// where drawn). to_ground: one point, beam at s (on a body: point), held to the ground.
  Joint(const Model& m, const EffectParams& p, JointKind kind, std::string type, bool to_ground = false)
      : kind_(kind), type_(std::move(type)), n_orient_(orientation_constraints(kind)) {
    const int a = static_cast<int>(p.number(to_ground ? "beam" : "beam_a"));
    const int b = to_ground ? -1 : static_cast<int>(p.number("beam_b"));
    const auto valid = [&](int beam) { return beam >= 0 && beam < static_cast<int>(m.beams().size()); };
    for (int beam : {a, b})
      if (!valid(beam) && !(to_ground && beam == b))
        throw std::invalid_argument(type_ + ": no beam with index " + std::to_string(beam));
    if (a == b) throw std::invalid_argument(type_ + ": a beam cannot be joined to itself");
    for (int beam : {a, b})
      if (beam >= 0 && n_orient_ > 0 && kind_ != JointKind::Rigid && m.beam(beam).is_ancf())
        throw ParamError(to_ground ? "beam" : "beams",
                         "beam '" + m.beam(beam).name() + "' is an ANCF cable: it has no section frame for a " + type_ +
                             " (a spherical or rigid " + (to_ground ? "support holds" : "joint joins") +
                             " ANCF cables)");
    side_[0] = side_at(m, p, a, to_ground ? "s" : "s_a", to_ground ? "point" : "point_a");
    if (to_ground) {  // a default side is the ground: no unknowns, at A's point as drawn
      side_[1] = JointSide();
      side_[1].X = position(0, reference(m));
    } else {
      side_[1] = side_at(m, p, b, "s_b", "point_b");
    }
    const Beam& A = m.beam(a);
    label_ = type_ + "[" + where(A, side_[0].s) + (to_ground ? "" : "-" + where(m.beam(b), side_[1].s)) + "]";
    // the reference state: the points must meet (the discretised centre lines')
    const Eigen::VectorXd y0 = reference(m);
    const Eigen::Vector3d pa = position(0, y0), pb = position(1, y0);
    if (!to_ground) {
      const Beam& B = m.beam(b);
      if ((pa - pb).norm() > 1e-9 * std::max(A.length(), B.length()))
        throw ParamError("beams", describe(A, side_[0].s) + " at " + format_point(pa) + " and " +
                                      describe(B, side_[1].s) + " at " + format_point(pb) + " do not meet (distance " +
                                      format_number((pa - pb).norm()) + ")");
    }
    if (n_orient_ == 0) return;
    for (int k = 0; k < 2; ++k) {
      JointSide& S = side_[k];
      if (S.ground() || !m.beam(S.beam).is_ancf()) continue;
      if (S.n != 1 || S.entries != 1)
        throw ParamError("at", "an ANCF cable's slope is held at a node: put the " + type_ + " on '" +
                                   m.beam(S.beam).name() + "' at one of its " +
                                   std::to_string(m.beam(S.beam).n_spans() + 1) + " nodes (s = k L / " +
                                   std::to_string(m.beam(S.beam).n_spans()) + "), not at s = " + format_number(S.s));
      S.directors = 1;
    }
    const Eigen::Matrix3d DA = triad(0, y0), DB = triad(1, y0);
    if (side_[0].directors == 1 || side_[1].directors == 1) {
      ancf_rigid(DA, DB);
      return;
    }
    switch (kind_) {
      case JointKind::Rigid: {
        // e_a . dB_b = 0 for the pairs (a, b) below, e_a = DA C e_a turned into B's reference
        // orientation (C = DA^T DB): their gradients are the three axes of the relative rotation
        constexpr int kPairs[3][2] = {{0, 1}, {1, 2}, {2, 0}};
        const Eigen::Matrix3d C = DA.transpose() * DB;
        for (int k = 0; k < 3; ++k) {
          u_[k] = C.col(kPairs[k][0]);
          v_[k] = Eigen::Vector3d::Unit(kPairs[k][1]);
        }
        break;
      }
      case JointKind::Revolute: {
        const Eigen::Vector3d axis = unit_vector_param(p, "axis", "the axis");
        const auto [e1, e2] = perpendicular_pair(axis);
        u_[0] = u_[1] = DA.transpose() * axis;
        v_[0] = DB.transpose() * e1;
        v_[1] = DB.transpose() * e2;
        break;
      }
      case JointKind::Universal: {
        const Eigen::Vector3d na = unit_vector_param(p, "axis", "the axis"), nb = unit_vector_param(p, "axis_b", "the second arm");
        if (std::abs(na.dot(nb)) > 1e-6)
          throw ParamError("axis_b", "must be perpendicular to axis (the cross's two arms), but axis . axis_b = " +
                                         format_number(na.dot(nb)) + " for unit vectors");
        u_[0] = DA.transpose() * na;
        v_[0] = DB.transpose() * nb;
        break;
      }
      case JointKind::Spherical: break;
    }
    // (interpolated triads inside a span of a curved beam are not exactly orthonormal)
    for (int k = 0; k < n_orient_; ++k) g0_[k] = (DA * u_[k]).dot(DB * v_[k]);
  }

  std::string type() const override { return type_; }
  std::string label() const override { return label_; }
  PetscInt n_extra() const override { return 3 + n_orient_; }

  // evaluated where its multipliers live
  void distribute(const Model& m) override { owned_ = m.dof_map().owns_cp(anchor()); }
  bool reaction_reads_own() const override { return true; }
  /// The force and moment on the first beam's point: minus the joint's own constraint forces on
  /// its coordinates (the moment about the joint: M = sum d x f over its directors' rows).
  void reaction(const Model& m, const ReactionInput& in, Reaction& out) const override {
    const JointSide& S = side_[0];
    const Beam& b = m.beam(S.beam);
    const DofMap& map = m.dof_map();
    Eigen::Vector3d M = Eigen::Vector3d::Zero();
    for (int j = 0; j < S.n; ++j) {
      const PetscInt c = b.first_cp() + S.cp[j];
      if (!map.owns_cp(c)) continue;
      for (int e = 0; e < S.entries; ++e)
        if (S.point[e] == j && S.comp[e] == 0)
          for (int k = 0; k < 3; ++k) out.force[k] -= in.own(map.q(c, k));
      // an ANCF node's r' (in a rigid joint) turns as a director would
      const int directors = b.is_ancf() ? (S.directors == 1 ? 1 : 0) : 3;
      for (int i = 0; i < directors; ++i) {
        Eigen::Vector3d d, f;
        for (int k = 0; k < 3; ++k) {
          d(k) = in.x(map.q(c, 3 + 3 * i + k));
          f(k) = in.own(map.q(c, 3 + 3 * i + k));
        }
        M -= d.cross(f);
      }
    }
    if (b.is_rigid() && map.owns_cp(b.first_cp())) {
      // M is about the centre of mass there (a body's directors also carry the force's lever
      // r - phi = X_i d_i, the stencil's director entries): about the joint, M - (r - phi) x F
      Eigen::Vector3d lever = Eigen::Vector3d::Zero(), F;
      for (int e = 0; e < S.entries; ++e)
        if (S.comp[e] > 0)
          for (int k = 0; k < 3; ++k) lever(k) += S.w[e] * in.x(map.q(b.first_cp(), S.comp[e] + k));
      for (int k = 0; k < 3; ++k) F(k) = -in.own(map.q(b.first_cp(), k));
      M -= lever.cross(F);
    }
    for (int k = 0; k < 3; ++k) out.moment[k] += M(k);
    out.has_moment = n_orient_ > 0;
  }
  PetscInt elimination_anchor(const Model& m) const override { return main_cp(m, 0); }
  void anchor_choices(const Model& m, std::vector<PetscInt>& cps) const override {
    cps.push_back(main_cp(m, 0));
    if (!side_[1].ground()) cps.push_back(main_cp(m, 1));
  }
  /// The anchor's side: its multipliers' pivots are in the coordinates of that side's points.
  void anchor_points(const Model& m, std::vector<PetscInt>& cps) const override {
    if (anchor() < 0) return;
    const int k = side_[1].ground() || anchor() == main_cp(m, 0) ? 0 : 1;
    for (int j = 0; j < side_[k].n; ++j) cps.push_back(m.beam(side_[k].beam).first_cp() + side_[k].cp[j]);
  }
  void reference_couplings(const Model& m, std::vector<std::pair<PetscInt, PetscInt>>& pairs) const override {
    if (!side_[1].ground()) pairs.emplace_back(main_cp(m, 0), main_cp(m, 1));
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    if (!owned_) return;
    const auto d = local_dofs(m);
    dofs.insert(dofs.end(), d.begin(), d.end());
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (owned_) PetscCall(add_block_pattern(sink, local_dofs(m)));
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const auto [y, yf, mu] = step_values(ctx);
    const Eigen::VectorXd f = gradient(yf).transpose() * mu;  // constraint forces at the force state
    const Eigen::VectorXd g = value(y);                        // constraints at the end of the step
    const auto d = local_dofs(ctx.model);
    const int nq = coordinates();
    for (int k = 0; k < nq; ++k) r.at(d[static_cast<size_t>(k)]) += f(k);
    for (int k = 0; k < g.size(); ++k) r.at(d[static_cast<size_t>(nq + k)]) += g(k);
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const auto [y, yf, mu] = step_values(ctx);
    const int nq = coordinates(), nc = 3 + n_orient_, n = nq + nc;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMajor A = RowMajor::Zero(n, n);
    // d/dq (G(q_f)^T mu) = theta sum_k mu_k H_k; H_k couples director i of A's point j with
    // director m of B's point l by N_j u_ki N_l v_km I3
    const JointSide &SA = side_[0], &SB = side_[1];
    const int offB = SA.size();
    for (int k = 0; k < (slopes_equal_ ? 0 : n_orient_); ++k)
      for (int j = 0; j < SA.n; ++j)
        for (int i = 0; i < SA.directors; ++i)
          for (int l = 0; l < SB.n; ++l)
            for (int mm = 0; mm < SB.directors; ++mm) {
              const double h = ctx.theta * mu(3 + k) * SA.N[j] * u_[k](i) * SB.N[l] * v_[k](mm);
              for (int c = 0; c < 3; ++c) {
                const int ra = j * SA.coords + 3 + 3 * i + c, rb = offB + l * SB.coords + 3 + 3 * mm + c;
                A(ra, rb) += h;
                A(rb, ra) += h;
              }
            }
    A.block(0, nq, nq, nc) = gradient(yf).transpose();
    A.block(nq, 0, nc, nq) = gradient(y);
    const auto d = local_dofs(ctx.model);
    PetscCall(J.add(n, d.data(), n, d.data(), A.data()));
    PetscFunctionReturn(0);
  }

 private:
  /// The side at a beam's arc length p[s_key], or at a body's point p[point_key] as drawn.
  static JointSide side_at(const Model& m, const EffectParams& p, int index, const char* s_key, const char* point_key) {
    const Beam& X = m.beam(index);
    if (X.is_rigid()) {
      const Eigen::Vector3d at = vector3_param(p, point_key);
      return JointSide(X.body_point_drawn({at(0), at(1), at(2)}), index, 0.0, X.coordinates_per_cp());
    }
    const double s = p.number(s_key);
    if (s < -1e-12 * X.length() || s > X.length() * (1 + 1e-12))
      throw ParamError("at", "s = " + format_number(s) + " is outside beam '" + X.name() + "'");
    const double at = std::clamp(s, 0.0, X.length());
    return JointSide(X.position_at(at), index, at, X.coordinates_per_cp());
  }
  /// A rigid joint with an ANCF cable's node on one side or both: n_orient_ and the constraints.
  void ancf_rigid(const Eigen::Matrix3d& DA, const Eigen::Matrix3d& DB) {
    const bool cable_a = side_[0].directors == 1, cable_b = side_[1].directors == 1;
    if (cable_a && cable_b) {  // r'_A = kappa r'_B: the drawn slopes must be parallel
      const Eigen::Vector3d ta = DA.col(0), tb = DB.col(0);
      if (ta.cross(tb).norm() > 1e-9 * ta.norm() * tb.norm())
        throw ParamError("beams", "two ANCF cables are welded only where their drawn slopes are parallel (a cable has "
                                  "no section frame to hold an angle): the slopes here are " + format_point(ta) +
                                      " and " + format_point(tb));
      slopes_equal_ = true;
      kappa_ = ta.dot(tb) / tb.squaredNorm();
      n_orient_ = 3;
      return;
    }
    // the slope stays perpendicular to two directions fixed to the other side's frame
    const Eigen::Vector3d t = (cable_a ? DA : DB).col(0);
    const auto [p, q] = perpendicular_pair(t.normalized());
    const Eigen::Matrix3d& frame = cable_a ? DB : DA;
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d in_frame = frame.transpose() * (k == 0 ? p : q);
      u_[k] = cable_a ? Eigen::Vector3d::UnitX() : in_frame;
      v_[k] = cable_a ? in_frame : Eigen::Vector3d::UnitX();
      g0_[k] = (DA * u_[k]).dot(DB * v_[k]);
    }
    n_orient_ = 2;
  }
  /// "name@start", "name@end" or "name@s" (labels); a body: its name.
  static std::string where(const Beam& b, double s) {
    if (b.is_rigid()) return b.name();
    const int c = end_cp(b, s);
    return b.name() + "@" + (c == 0 ? "start" : c > 0 ? "end" : "s=" + format_number(s));
  }
  /// "'name' start", "'name' end" or "'name' at s = 1.5" (messages).
  static std::string describe(const Beam& b, double s) {
    if (b.is_rigid()) return "body '" + b.name() + "'";
    const int c = end_cp(b, s);
    return "'" + b.name() + "' " + (c == 0 ? "start" : c > 0 ? "end" : "at s = " + format_number(s));
  }
  PetscInt main_cp(const Model& m, int k) const { return m.beam(side_[k].beam).first_cp() + side_[k].cp[side_[k].main]; }
  int coordinates() const { return side_[0].size() + side_[1].size(); }
  /// Both sides' control points' coordinates, then the multipliers.
  std::vector<PetscInt> local_dofs(const Model& m) const {
    std::vector<PetscInt> d;
    for (const JointSide& S : side_)
      for (int j = 0; j < S.n; ++j)
        for (int c = 0; c < S.coords; ++c) d.push_back(m.dof_map().q(m.beam(S.beam).first_cp() + S.cp[j], c));
    for (int k = 0; k < 3 + n_orient_; ++k) d.push_back(extra_offset() + k);
    return d;
  }
  Eigen::VectorXd gather(const EvalContext& ctx, const LocalValues& x) const {
    Eigen::VectorXd y(coordinates());
    int o = 0;
    for (const JointSide& S : side_)
      for (int j = 0; j < S.n; ++j, o += S.coords)
        y.segment(o, S.coords) =
            Eigen::Map<const Eigen::VectorXd>(x.cp(ctx.map, ctx.model.beam(S.beam).first_cp() + S.cp[j]), S.coords);
    return y;
  }
  Eigen::VectorXd reference(const Model& m) const {
    Eigen::VectorXd y(coordinates());
    int o = 0;
    for (const JointSide& S : side_)
      for (int j = 0; j < S.n; ++j, o += S.coords)
        y.segment(o, S.coords) =
            Eigen::Map<const Eigen::VectorXd>(m.beam(S.beam).q_ref().data() + S.coords * S.cp[j], S.coords);
    return y;
  }
  /// The coordinates at the end of the step and at the force state, and the multipliers.
  struct StepValues {
    Eigen::VectorXd y, yf, mu;
  };
  StepValues step_values(const EvalContext& ctx) const {
    return {gather(ctx, ctx.x), gather(ctx, ctx.xf), multipliers(ctx)};
  }
  Eigen::VectorXd multipliers(const EvalContext& ctx) const {
    Eigen::VectorXd mu(3 + n_orient_);
    for (int k = 0; k < mu.size(); ++k) mu(k) = ctx.x.at(extra_offset() + k);
    return mu;
  }
  int offset(int k) const { return k == 0 ? 0 : side_[0].size(); }
  Eigen::Vector3d position(int k, const Eigen::VectorXd& y) const {
    const JointSide& S = side_[k];
    if (S.ground()) return S.X;
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for (int e = 0; e < S.entries; ++e) r += S.w[e] * y.segment<3>(offset(k) + S.point[e] * S.coords + S.comp[e]);
    return r;
  }
  /// The interpolated triad (d1, d2, d3)(s) as columns.
  Eigen::Matrix3d triad(int k, const Eigen::VectorXd& y) const {
    const JointSide& S = side_[k];
    if (S.ground()) return Eigen::Matrix3d::Identity();
    Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
    for (int j = 0; j < S.n; ++j)
      for (int i = 0; i < S.directors; ++i) D.col(i) += S.N[j] * y.segment<3>(offset(k) + j * S.coords + 3 + 3 * i);
    return D;
  }
  Eigen::VectorXd value(const Eigen::VectorXd& y) const {
    Eigen::VectorXd g(3 + n_orient_);
    g.head<3>() = position(0, y) - position(1, y);
    if (n_orient_ > 0) {
      const Eigen::Matrix3d DA = triad(0, y), DB = triad(1, y);
      if (slopes_equal_) {
        g.tail<3>() = DA.col(0) - kappa_ * DB.col(0);
        return g;
      }
      for (int k = 0; k < n_orient_; ++k) g(3 + k) = (DA * u_[k]).dot(DB * v_[k]) - g0_[k];
    }
    return g;
  }
  Eigen::MatrixXd gradient(const Eigen::VectorXd& y) const {
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(3 + n_orient_, coordinates());
    for (int k = 0; k < 2; ++k) {
      const JointSide& S = side_[k];
      const double sign = k == 0 ? 1.0 : -1.0;
      for (int e = 0; e < S.entries; ++e)
        G.block<3, 3>(0, offset(k) + S.point[e] * S.coords + S.comp[e]) += sign * S.w[e] * Eigen::Matrix3d::Identity();
    }
    if (n_orient_ == 0) return G;
    if (slopes_equal_) {  // each side one node, its r' at 3..5
      G.block<3, 3>(3, 3) = side_[0].N[0] * Eigen::Matrix3d::Identity();
      G.block<3, 3>(3, offset(1) + 3) = -kappa_ * side_[1].N[0] * Eigen::Matrix3d::Identity();
      return G;
    }
    const Eigen::Matrix3d DA = triad(0, y), DB = triad(1, y);
    for (int k = 0; k < n_orient_; ++k) {
      const Eigen::Vector3d a = DA * u_[k], b = DB * v_[k];
      for (int j = 0; j < side_[0].n; ++j)
        for (int i = 0; i < side_[0].directors; ++i)
          G.block<1, 3>(3 + k, j * side_[0].coords + 3 + 3 * i) += side_[0].N[j] * u_[k](i) * b.transpose();
      for (int l = 0; l < side_[1].n; ++l)
        for (int i = 0; i < side_[1].directors; ++i)
          G.block<1, 3>(3 + k, offset(1) + l * side_[1].coords + 3 + 3 * i) += side_[1].N[l] * v_[k](i) * a.transpose();
    }
    return G;
  }

  JointKind kind_;
  std::string type_, label_;
  int n_orient_ = 0;
  std::array<JointSide, 2> side_;
  std::array<Eigen::Vector3d, 3> u_{}, v_{};  ///< the orientation constraints' component vectors
  std::array<double, 3> g0_{};                ///< their reference values
  bool slopes_equal_ = false;  ///< two ANCF cables welded: r'_A - kappa r'_B = 0 instead
  double kappa_ = 1.0;
  bool owned_ = false;
};

std::unique_ptr<Effect> make_clamp_inside(const Model& m, const EffectParams& p) {
  return std::make_unique<Joint>(m, p, JointKind::Rigid, "clamp", true);
}

void register_joint_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const ParamSpec points{"at", K::Points, "m",
                         "where on each beam: \"start\", \"end\" or an arc length in [0, L]; the two points must meet",
                         "", 0, 0, false, 2};
  const std::string director_only =
      "the two beams' names, e.g. [\"boom\", \"jib\"] (director beams: the joint holds their section frames)";
  const ParamSpec director_beams{"beams", K::Beams, "", director_only, "", 0, 0, false, 2, {"director"}};
  const ParamSpec axis{"axis", K::Vector, "", "", "", -kInf, kInf, false, 3};
  struct Variant {
    const char* name;
    JointKind kind;
    const char* meaning;
    std::vector<ParamSpec> params;
  };
  ParamSpec hinge = axis;
  hinge.meaning = "the hinge axis in the drawn state (any length); it turns with both beams";
  ParamSpec arm_a = axis, arm_b = axis;
  arm_a.meaning = "the cross's arm fixed to the first beam, in the drawn state (any length)";
  arm_b.key = "axis_b";
  arm_b.meaning = "the arm fixed to the second beam, perpendicular to `axis`";
  const std::vector<Variant> variants = {
      {"spherical", JointKind::Spherical, "two beam points held together, free to turn",
       {{"beams", K::Beams, "", "the two beams' names, e.g. [\"rope\", \"net\"] (director beams or ANCF cables)", "", 0,
         0, false, 2},
        points}},
      {"universal", JointKind::Universal,
       "two beam points held together, an arm of each kept perpendicular (a Cardan joint: no twist passes freely)",
       {director_beams, points, arm_a, arm_b}},
      {"revolute", JointKind::Revolute, "two beam points held together, turning about a common hinge axis only",
       {director_beams, points, hinge}},
      {"rigid", JointKind::Rigid,
       "two beam points welded together, positions and section frames (an ANCF cable: its slope at a node)",
       {{"beams", K::Beams, "",
         "the two beams' names, e.g. [\"boom\", \"jib\"] (an ANCF cable at one of its nodes: the joint holds its slope)",
         "", 0, 0, false, 2},
        points}},
  };
  for (const Variant& v : variants) {
    const JointKind kind = v.kind;
    r.add(table_effect_spec(kind_type(kind), "joint", v.name, EnergyRole::Constraint, v.meaning, v.params),
          [kind](const Model& m, const EffectParams& p) { return std::make_unique<Joint>(m, p, kind, kind_type(kind)); });
  }
  // the ground's joints: [[support]] variants
  const ParamSpec held_beam{"beam", K::Beam, "", "the beam (or body) it holds (director beams: the support holds "
                            "its section frame)", "", 0, 0, false, 0, {"director"}};
  // (a clamp's beam may be an ANCF cable: at an end it fixes r and r', at a node inside its slope)
  const ParamSpec held_point{"at", K::Point, "m",
                             "the point: \"start\", \"end\" or an arc length in [0, L]; on a body, where it is drawn",
                             ""};
  ParamSpec ground_hinge = axis, ground_arm_a = arm_a, ground_arm_b = arm_b;
  ground_hinge.meaning = "the hinge axis, fixed in space (any length)";
  ground_arm_a.meaning = "the cross's arm fixed to the beam, in the drawn state (any length)";
  ground_arm_b.meaning = "the arm fixed in space, perpendicular to `axis`";
  r.add(table_effect_spec("revolute", "support", "revolute", EnergyRole::Constraint,
                          "a beam point held in place, turning about an axis fixed in space only (a pin)",
                          {held_beam, held_point, ground_hinge}),
        [](const Model& m, const EffectParams& p) {
          return std::make_unique<Joint>(m, p, JointKind::Revolute, "revolute", true);
        });
  r.add(table_effect_spec("universal", "support", "universal", EnergyRole::Constraint,
                          "a beam point held in place, an arm of the beam kept perpendicular to one fixed in space "
                          "(a Cardan joint to the ground)",
                          {held_beam, held_point, ground_arm_a, ground_arm_b}),
        [](const Model& m, const EffectParams& p) {
          return std::make_unique<Joint>(m, p, JointKind::Universal, "universal", true);
        });
  r.add(table_effect_spec("rigid_joint", "rigid_joint", "", EnergyRole::Constraint,
                          "two beam ends welded together, positions and directors ([[joint]] type = \"rigid\" welds "
                          "any two points)",
                          {{"beams", K::Beams, "", "the two beams' names, e.g. [\"leg1\", \"leg2\"] (the joint welds director triads, which an ANCF "
                            "cable has not)", "", 0, 0, false, 2,
                            {"director"}},
                           {"at", K::Ends, "", "which end of each beam", "[\"end\", \"start\"]", 0, 0, false, 2}}),
        [](const Model& m, const EffectParams& p) { return std::make_unique<Joint>(m, p, JointKind::Rigid, "rigid_joint"); });
}

}  // namespace slidebeam::effects
