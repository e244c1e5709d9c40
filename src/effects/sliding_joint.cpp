// SPDX-License-Identifier: MIT
/// @file Sliding joint (formulation.md sections 5-6): a point of the slider beam stays on the
/// carrier's centre line, Phi = sum_A N_A(s) phi_A - p = 0, with the sliding coordinate s (no mass)
/// and three multipliers mu as extra unknowns, and the frictionless condition G_s . mu = 0 as the
/// equation of s. Relative rotations are free.
///
/// Within a time step the constraint force is G^T mu with, by rule:
///  - Endpoint (statics, Newmark, HHT): G at the end of the step;
///  - Theta (midpoint; the seed's form under energy-momentum): G at x_f, s_f;
///  - EnergyMomentum (exact, default): G_q = (N(s_n) + N(s_n+1))/2 on the carrier and
///    G_s = sum_A [N_A(s_n+1) - N_A(s_n)]/(s_n+1 - s_n) phi_A,n+1/2, so that
///    G_q dq + G_s ds = Phi_n+1 - Phi_n exactly, across any number of knots: the joint does no work.
/// The knot span of s is found again at every evaluation.
///
/// Carrier and slider may be director beams or ANCF cables. The carrier's centre line is a
/// sliding::Curve over coordinate 3-blocks ("curve blocks"): the phi of each control point of a
/// director beam (quadratic B-spline), or r and r' of each node of a cable (cubic Hermite,
/// kernels/ancf_sliding.hpp); the same formulas hold blockwise, because c(s) is linear in the
/// blocks. The slider point is a PositionStencil (Beam::position_at) of either formulation.

#include "effects/common.hpp"
#include "kernels/sliding.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace slidebeam::effects {

class SlidingJoint final : public Effect {
 public:
  SlidingJoint(const Model& m, const EffectParams& p)
      : slider_(static_cast<int>(p.number("slider"))), carrier_(static_cast<int>(p.number("carrier"))) {
    const int nb = static_cast<int>(m.beams().size());
    for (int beam : {slider_, carrier_})
      if (beam < 0 || beam >= nb) throw std::invalid_argument("sliding_joint: no beam with index " + std::to_string(beam));
    if (slider_ == carrier_) throw std::invalid_argument("sliding_joint: a beam cannot slide on itself");
    const Beam &S = m.beam(slider_), &C = m.beam(carrier_);
    curve_ = {C.is_ancf() ? sliding::Curve::Kind::Hermite : sliding::Curve::Kind::BSpline, C.n_spans(), C.length()};
    const double sigma = p.number("slider_s");
    if (sigma < -1e-12 * S.length() || sigma > S.length() * (1 + 1e-12))
      throw std::invalid_argument("sliding_joint: slider point s = " + std::to_string(sigma) + " outside beam '" + S.name() + "'");
    stencil_ = S.position_at(std::clamp(sigma, 0.0, S.length()));
    const std::string form = p.string("discrete_gradient", "exact");
    if (form == "exact") exact_ = true;
    else if (form == "midpoint") exact_ = false;
    else throw std::invalid_argument("sliding_joint: discrete_gradient must be 'exact' or 'midpoint', not '" + form + "'");

    // initial s: the closest point of the slider point on the carrier (reference configuration),
    // found by the model's parallel search (closest_point_queries / set_closest_points)
    for (int j = 0; j < stencil_.n; ++j)
      for (int k = 0; k < 3; ++k)
        point_[k] += stencil_.w[j] * S.q_ref()[static_cast<size_t>(S.coordinates_per_cp() * stencil_.cp[j] + stencil_.comp[j] + k)];
    tolerance_ = p.number("tolerance", 1e-6 * C.length());
    label_ = "sliding_joint[" + S.name() + "@" + std::to_string(sigma) + " on " + C.name() + "]";
  }
  void closest_point_queries(const Model&, std::vector<ClosestPointQuery>& q) const override {
    ClosestPointQuery query;
    query.carrier = carrier_;
    std::copy(point_, point_ + 3, query.point);
    q.push_back(query);
  }
  void set_closest_points(const Model& m, const ClosestPoint* found) override {
    s0_ = found[0].s;
    if (found[0].distance > tolerance_) {
      std::ostringstream msg;
      msg << "sliding_joint: the slider point of beam '" << m.beam(slider_).name() << "' (" << point_[0] << ", "
          << point_[1] << ", " << point_[2] << ") is " << found[0].distance << " from carrier '"
          << m.beam(carrier_).name() << "' (closest at s = " << s0_ << "); tolerance " << tolerance_;
      throw std::invalid_argument(msg.str());
    }
  }
  std::string type() const override { return "sliding_joint"; }
  std::string label() const override { return label_; }
  // mu (3), then s: the natural-order LU of serial steps then meets s after the multipliers,
  // whose elimination gives its pivot (s first: a zero pivot while mu = 0)
  PetscInt n_extra() const override { return 4; }
  bool extra_is_state(PetscInt k) const override { return k == 3; }
  int slider_beam() const override { return slider_; }
  void initial_values(const Model&, std::vector<PetscInt>& rows, std::vector<PetscScalar>& vals) const override {
    rows.push_back(s_index());
    vals.push_back(s0_);
  }

  PetscInt elimination_anchor(const Model& m) const override { return slider_cp(m, stencil_.n - 1); }
  void elimination_precedence(std::vector<std::pair<int, int>>& pairs) const override {
    pairs.emplace_back(slider_, carrier_);
  }
  void distribute(const Model& m) override {
    owned_ = m.dof_map().owns_cp(slider_cp(m, 0));
    const auto r = curve_.touched_blocks(s0_, s0_);
    move_window(r[0], r[1]);
    set_ghost_window(s0_, s0_);
  }
  /// The slider's points, the carrier points around s (the ghost window: the touched ones plus
  /// kGhostMargin on either side, moved by refresh_needed_dofs) and the joint's extras: the
  /// carrier points a joint reads come from whichever rank owns them, O(1) per joint.
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    if (!owned_) return;
    add_cp_blocks(m.dof_map(), slider_cp(m, 0), stencil_.cp[stencil_.n - 1] - stencil_.cp[0] + 1, dofs);
    add_cp_blocks(m.dof_map(), m.beam(carrier_).first_cp() + ghost_lo_, ghost_hi_ - ghost_lo_ + 1, dofs);
    for (int k = 0; k < 4; ++k) dofs.push_back(extra_offset() + k);
  }
  bool refresh_needed_dofs(const Model&, const LocalValues& x, const LocalValues& x_old) const override {
    if (!owned_) return false;
    const double s0 = x_old.at(s_index()), s1 = x.at(s_index());
    const auto r = curve_.touched_cps(s0, s1);
    if (r[0] >= ghost_lo_ && r[1] <= ghost_hi_) return false;
    set_ghost_window(s0, s1);
    return true;
  }
  /// The joint couples positions only with s and mu, never positions with positions: its
  /// pattern is the columns (s, mu) of the position rows and the rows (s, mu), over the slider's
  /// points and a window of carrier curve blocks around s (the touched ones plus kWindowMargin
  /// control points' blocks on either side; an ANCF node has two blocks, r and r'). When s
  /// leaves the window, the window moves: the Jacobian's pattern changes and the solvers set
  /// their factorisation up anew (reset_factorization_on_pattern_change).
  /// Rows over the whole carrier would fill the LU along the carrier for every joint.
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const int n = 3 * stencil_.n + 3 * (win_hi_ - win_lo_ + 1) + 4;
    const std::vector<double> zero(static_cast<size_t>(4 * (n - 4) + 4 * n), 0.0);
    PetscCall(add_blocks(dofs(m, win_lo_, win_hi_ + 1), zero.data(), sink));
    PetscFunctionReturn(0);
  }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const Terms t = terms(ctx);
    const Eigen::Vector3d mu = multipliers(ctx.x);
    const Beam& C = ctx.model.beam(carrier_);
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int A = t.lo; A <= t.hi; ++A) {
      Eigen::Map<Eigen::Vector3d>(block(r, ctx.map, C, A)) += t.Wq.at(A) * mu;
      g += t.N1.at(A) * position(ctx.x, ctx.map, C, A);
    }
    const Beam& S = ctx.model.beam(slider_);
    scatter_stencil(r, ctx.map, S, stencil_, -mu);
    for (int j = 0; j < stencil_.n; ++j)  // one block at a time (the director beam's rounding as before)
      g -= stencil_.w[j] * Eigen::Map<const Eigen::Vector3d>(ctx.x.cp(ctx.map, S.first_cp() + stencil_.cp[j]) + stencil_.comp[j]);
    r.at(s_index()) += t.Gs.dot(mu);
    for (int k = 0; k < 3; ++k) r.at(extra_offset() + k) += g(k);
    PetscFunctionReturn(0);
  }

  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const Terms t = terms(ctx);
    const Eigen::Vector3d mu = multipliers(ctx.x);
    const Beam& C = ctx.model.beam(carrier_);
    // The (s, mu) columns of the position rows and the (s, mu) rows over the slider and the
    // window of carrier points (see pattern()), filled directly: O(window) per joint.
    move_window(t.lo, t.hi);
    const int np = 3 * stencil_.n;  // slider coordinates first
    const int nr = win_hi_ - win_lo_ + 1, n = np + 3 * nr + 4;
    const int is = np + 3 * nr;  // local index of s; mu follows
    std::vector<double> blocks(static_cast<size_t>(4 * is + 4 * n), 0.0);
    auto col = [&](int row, int k) -> double& { return blocks[static_cast<size_t>(4 * row + k)]; };  // k: 0 s, 1-3 mu
    auto srow = [&](int k, int j) -> double& { return blocks[static_cast<size_t>(4 * is + n * k + j)]; };
    double ds_row_s = 0.0;
    Eigen::Vector3d dg_ds = Eigen::Vector3d::Zero();
    for (int a = t.lo; a <= t.hi; ++a) {
      const int ia = np + 3 * (a - win_lo_);
      const Eigen::Vector3d x1 = position(ctx.x, ctx.map, C, a);
      const Eigen::Vector3d xh = t.blend_old * position(ctx.x_old, ctx.map, C, a) + (1.0 - t.blend_old) * x1;
      for (int k = 0; k < 3; ++k) {
        col(ia + k, 1 + k) = t.Wq.at(a);           // carrier force  / d mu
        col(ia + k, 0) = t.dWq.at(a) * mu(k);      // carrier force  / d s
        srow(0, ia + k) = t.cphi.at(a) * mu(k);    // s equation     / d phi_A
        srow(1 + k, ia + k) = t.N1.at(a);          // constraint     / d phi_A
      }
      ds_row_s += t.dDs.at(a) * xh.dot(mu);
      dg_ds += t.dN1.at(a) * x1;
    }
    for (int b = 0; b < stencil_.n; ++b)
      for (int k = 0; k < 3; ++k) {
        col(3 * b + k, 1 + k) = -stencil_.w[b];
        srow(1 + k, 3 * b + k) = -stencil_.w[b];
      }
    for (int k = 0; k < 3; ++k) {
      srow(0, is + 1 + k) = t.Gs(k);
      srow(1 + k, is) = dg_ds(k);
    }
    srow(0, is) = ds_row_s;
    PetscCall(add_blocks(dofs(ctx.model, win_lo_, win_hi_ + 1), blocks.data(), J));
    PetscFunctionReturn(0);
  }

  /// J(positions, extras) += values[0 : 4 p] (p x 4, row-major), J(extras, all) += the next 4 x n,
  /// with dofs = positions (p of them), then s, mu.
  static PetscErrorCode add_blocks(const std::vector<PetscInt>& d, const double* values, const MatSink& J) {
    PetscFunctionBeginUser;
    const auto n = static_cast<PetscInt>(d.size()), p = n - 4;
    PetscCall(J.add(p, d.data(), 4, d.data() + p, values));
    PetscCall(J.add(4, d.data() + p, n, d.data(), values + 4 * p));
    PetscFunctionReturn(0);
  }

 private:
  /// Coefficients of one evaluation, over carrier curve blocks lo..hi.
  struct Terms {
    int lo = 0, hi = 0;
    sliding::Weights Wq, dWq;   // carrier force G_q^T mu = Wq mu, and d Wq / d s
    sliding::Weights Ds, dDs;   // G_s = sum Ds_A xhat_A, d Ds / d s (times d xhat / d x where it applies)
    sliding::Weights cphi;      // d G_s / d phi_A (n+1) coefficient
    sliding::Weights N1, dN1;   // constraint at the end of the step: N(s1), N'(s1)
    Eigen::Vector3d Gs = Eigen::Vector3d::Zero();
    double blend_old = 0.0;     // xhat = blend_old x_old + (1 - blend_old) x
  };

  Terms terms(const EvalContext& ctx) const {
    const Beam& C = ctx.model.beam(carrier_);
    const sliding::Curve& cv = curve_;
    const double s1 = ctx.x.at(s_index()), s0 = ctx.x_old.at(s_index());
    Terms t;
    const auto range = cv.touched_blocks(s0, s1);
    t.lo = range[0];
    t.hi = range[1];
    const int nr = t.hi - t.lo + 1;
    for (auto* w : {&t.Wq, &t.dWq, &t.Ds, &t.dDs, &t.cphi, &t.N1, &t.dN1}) w->reset(t.lo, nr);
    const int e1 = cv.span_of(s1);
    cv.add_basis(e1, s1, 0, 1.0, t.N1);
    cv.add_basis(e1, s1, 1, 1.0, t.dN1);
    if (ctx.rule == StepRule::EnergyMomentum && exact_) {
      const int e0 = cv.span_of(s0);
      cv.add_basis(e0, s0, 0, 0.5, t.Wq);
      cv.add_basis(e1, s1, 0, 0.5, t.Wq);
      cv.add_basis(e1, s1, 1, 0.5, t.dWq);
      cv.difference_quotient(s0, s1, t.Ds, t.dDs);
      for (size_t i = 0; i < t.Ds.w.size(); ++i) t.cphi.w[i] = 0.5 * t.Ds.w[i];
      t.blend_old = 0.5;
    } else {
      // forces at x_f (Endpoint: x_f = x, theta = 1)
      const double th = ctx.theta, sf = ctx.xf.at(s_index());
      const int ef = cv.span_of(sf);
      cv.add_basis(ef, sf, 0, 1.0, t.Wq);
      cv.add_basis(ef, sf, 1, th, t.dWq);
      cv.add_basis(ef, sf, 1, 1.0, t.Ds);
      cv.add_basis(ef, sf, 1, th, t.cphi);
      cv.add_basis(ef, sf, 2, th, t.dDs);
      t.blend_old = 1.0 - th;
    }
    for (int a = t.lo; a <= t.hi; ++a) {
      const Eigen::Vector3d xh = t.blend_old * position(ctx.x_old, ctx.map, C, a) + (1.0 - t.blend_old) * position(ctx.x, ctx.map, C, a);
      t.Gs += t.Ds.at(a) * xh;
    }
    return t;
  }

  /// Curve block A of the carrier in the state x, and a pointer to its 3 entries in r.
  Eigen::Vector3d position(const LocalValues& x, const DofMap& map, const Beam& C, int A) const {
    return Eigen::Map<const Eigen::Vector3d>(x.cp(map, C.first_cp() + curve_.cp_of_block(A)) + curve_.offset_of_block(A));
  }
  double* block(const LocalValues& r, const DofMap& map, const Beam& C, int A) const {
    return r.cp(map, C.first_cp() + curve_.cp_of_block(A)) + curve_.offset_of_block(A);
  }
  Eigen::Vector3d multipliers(const LocalValues& x) const {
    return {x.at(extra_offset()), x.at(extra_offset() + 1), x.at(extra_offset() + 2)};
  }
  PetscInt s_index() const { return extra_offset() + 3; }
  /// Global index of the slider stencil's control point (node) j.
  PetscInt slider_cp(const Model& m, int j) const { return m.beam(slider_).first_cp() + stencil_.cp[j]; }
  /// Slider stencil blocks (3 each), carrier curve blocks [c0, c1) (3 each), s, mu.
  std::vector<PetscInt> dofs(const Model& m, int c0, int c1) const {
    const DofMap& map = m.dof_map();
    std::vector<PetscInt> d = stencil_dofs(map, m.beam(slider_), stencil_);
    d.reserve(static_cast<size_t>(3 * stencil_.n + 3 * (c1 - c0) + 4));
    const PetscInt first = m.beam(carrier_).first_cp();
    for (int a = c0; a < c1; ++a)
      for (int k = 0; k < 3; ++k) d.push_back(map.q(first + curve_.cp_of_block(a), curve_.offset_of_block(a) + k));
    d.push_back(s_index());  // the local block's order: s, then mu
    for (int k = 0; k < 3; ++k) d.push_back(extra_offset() + k);
    return d;
  }

  /// Keep carrier curve blocks [lo, hi] inside the window; re-centre it (with margin) when they
  /// leave. Touched ranges of a Hermite curve start at an r block and end at an r' block, and the
  /// margin is whole nodes, so the window holds whole nodes.
  void move_window(int lo, int hi) const {
    if (lo >= win_lo_ && hi <= win_hi_) return;
    const int margin = kWindowMargin * curve_.blocks_per_cp();
    win_lo_ = std::max(0, lo - margin);
    win_hi_ = std::min(curve_.n_blocks() - 1, hi + margin);
  }
  /// Ghost the carrier points touched by [s0, s1] plus kGhostMargin on either side.
  void set_ghost_window(double s0, double s1) const {
    const auto r = curve_.touched_cps(s0, s1);
    ghost_lo_ = std::max(0, r[0] - kGhostMargin);
    ghost_hi_ = std::min(curve_.n_cp() - 1, r[1] + kGhostMargin);
  }
  static constexpr int kWindowMargin = 2;  ///< carrier points (nodes) beyond the touched ones
  /// Ghosted carrier points beyond the touched ones: wider than the Jacobian's window, which
  /// must lie within them (its values are read), so ghosts move less often than the pattern.
  static constexpr int kGhostMargin = 4;

  int slider_, carrier_;
  mutable int win_lo_ = 0, win_hi_ = -1;  ///< carrier curve blocks in the Jacobian pattern
  mutable int ghost_lo_ = 0, ghost_hi_ = -1;  ///< carrier points ghosted
  sliding::Curve curve_;        ///< the carrier's centre-line basis
  PositionStencil stencil_;     ///< the slider point on the slider beam
  bool exact_ = true;
  double s0_ = 0.0;
  double point_[3] = {0, 0, 0};  ///< the slider point, reference configuration
  double tolerance_ = 0.0;       ///< largest distance from the carrier at the start
  std::string label_;
  bool owned_ = false;
};

void register_sliding_effects(EffectRegistry& r) {
  r.add(model_effect_spec("sliding_joint", EnergyRole::Constraint, "a beam point sliding along another beam's centre line"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<SlidingJoint>(m, p); });
}

}  // namespace slidebeam::effects
