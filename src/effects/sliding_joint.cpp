// SPDX-License-Identifier: MIT
/// @file Sliding joint (docs/theory.md): a point p of the slider beam stays on the
/// carrier's centre line c(s) = sum_A N_A(s) phi_A, with the sliding coordinate s (no mass) and
/// three multipliers as extra unknowns, and the frictionless condition (the s row: G_s . multipliers
/// = 0) as the equation of s. Relative rotations are free. Two forms of the same constraints:
///  - Frame (director sliders, the default): Phi_i = e_i . (c(s) - p), i = 1..3, with e_i the
///    slider point's interpolated directors. Energy-momentum keeps energy, linear and angular
///    momentum exactly (docs/theory.md, "The frame-projected sliding joint").
///  - Spatial (ANCF sliders, which have no directors; or chosen): Phi = c(s) - p. Equivariant, not
///    invariant: its energy-momentum force keeps energy and linear momentum, but has the moment
///    (sum_A Nbar_A xbar_A - pbar) x mu = -1/4 (sum_A dN_A dx_A) x mu over a step.
///
/// Spatial form. Within a time step the constraint force is G^T mu with, by rule:
///  - Endpoint (statics, Newmark, HHT): G at the end of the step;
///  - Theta (midpoint; the seed's form under energy-momentum): G at x_f, s_f;
///  - EnergyMomentum (exact, default): G_q = (N(s_n) + N(s_n+1))/2 on the carrier and
///    G_s = sum_A [N_A(s_n+1) - N_A(s_n)]/(s_n+1 - s_n) phi_A,n+1/2, so that
///    G_q dq + G_s ds = Phi_n+1 - Phi_n exactly, across any number of knots: the joint does no work.
/// The knot span of s is found again at every evaluation.
///
/// Frame form, with lambda_i the multipliers, ebar_i, xbar_A, pbar the force state (mid-step under
/// energy-momentum, x_f otherwise) and W_A the force weights on the carrier:
///   carrier block A:  W_A Lambda,  Lambda = sum_i lambda_i ebar_i  (the force on the slider)
///   slider point:     -Lambda
///   slider e_i:       lambda_i v,  v = sum_A W_A xbar_A - pbar     (v x Lambda + Lambda x v = 0)
///   s:                sum_i lambda_i sum_A D_A pi_iA
/// EnergyMomentum (exact): W = (N(s_n) + N(s_n+1))/2, D the exact difference quotient of N and
/// pi_iA = (e_i,n . x_A,n + e_i,n+1 . x_A,n+1)/2: the product rule with the exact midpoint rule
/// of the bilinear e_i . x_A and e_i . p, so G* dq = Phi_n+1 - Phi_n exactly. Otherwise W = N(s_f),
/// D = N'(s_f), pi_iA = e_i,f . x_A,f. The force state's derivative with respect to the end state
/// is b = theta (1/2 under energy-momentum).
///
/// A guide ([[guide]]: a ring, fairlead, saddle or small sheave the rope runs through) is the
/// same joint with the carrier the rope and the slider a point fixed in space (no unknowns of its
/// own: p constant) or a point of a rigid body (p = phi + X_i d_i, a stencil over the body's
/// coordinates), in the spatial form. Energy-momentum keeps its energy exactly; the rope's
/// moment about the guide over a step is the spatial form's -1/4 (sum_A dN_A dx_A) x mu.
///
/// Carrier and slider may be director beams or ANCF cables. The carrier's centre line is a
/// sliding::Curve over coordinate 3-blocks ("curve blocks"): the phi of each control point of a
/// director beam (quadratic B-spline), or r and r' of each node of a cable (cubic Hermite,
/// kernels/ancf_sliding.hpp); the same formulas hold blockwise, because c(s) is linear in the
/// blocks. The slider point is a PositionStencil (Beam::position_at) of either formulation.
///
/// A slider's carrier may be a track: several carriers joined end to end, each run through either
/// way, one s along them (sliding::Track; docs/theory.md, "Tracks"). Curve blocks are then the
/// track's, each mapped to its carrier's control point (carrier_cp); everything above holds over
/// them unchanged, the discrete derivative taken piece by piece.

#include "effects/common.hpp"
#include "kernels/sliding.hpp"
#include "model/effect_parts.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace slidebeam::effects {

class SlidingJoint final : public Effect, public ExtraUnknowns, public MovingPoints, public NumberingHints, public JointTarget,
                           public EventSource, public OutputSource {
 public:
  struct GuideTag {};
  /// A [[guide]]: the rope `rope` runs through `point`, fixed, or drawn on the [[body]] `body`.
  SlidingJoint(const Model& m, const EffectParams& p, GuideTag)
      : slider_(p.num.count("body") ? static_cast<int>(p.number("body")) : -1),
        carrier_(static_cast<int>(p.number("rope"))) {
    const int nb = static_cast<int>(m.beams().size());
    if (carrier_ < 0 || carrier_ >= nb) throw std::invalid_argument("guide: no beam with index " + std::to_string(carrier_));
    const Beam& C = m.beam(carrier_);
    if (C.is_rigid()) throw ParamError("rope", "'" + C.name() + "' is a [[body]]: a guide takes a rope (a beam)");
    carriers_ = {carrier_};
    track_.append(curve_of(C), false);
    const std::vector<double>& at = p.vector("point", 3);
    std::copy(at.begin(), at.end(), point_);
    if (slider_ >= 0) {
      if (slider_ >= nb || !m.beam(slider_).is_rigid())
        throw ParamError("body", "'" + (slider_ < nb ? m.beam(slider_).name() : std::to_string(slider_)) +
                                     "' is not a [[body]]: a guide is fixed in space or carried by a body");
      stencil_ = m.beam(slider_).body_point_drawn({at[0], at[1], at[2]});
    } else {
      offset_ = Eigen::Vector3d(at[0], at[1], at[2]);
    }
    // a drawn corner at the guide is cut by the spline by about a quarter span: half a span by
    // default, a gap that the equilibrium start closes (a start from the drawing steps onto it)
    tolerance_ = p.number("tolerance", 0.5 * C.length() / C.n_spans());
    fail_at_end_ = p.string("at_rope_end", "stop") == "fail";
    held_at_start_ = p.string("static", "free") == "held";
    name_ = p.string("name");
    label_ = "guide[" + C.name() + " on " + name_ + "]";
    prefix_ = C.name() + "_at_" + name_;
  }
  SlidingJoint(const Model& m, const EffectParams& p)
      : slider_(static_cast<int>(p.number("slider"))), carrier_(static_cast<int>(p.number("carrier"))) {
    const int nb = static_cast<int>(m.beams().size());
    if (slider_ < 0 || slider_ >= nb) throw std::invalid_argument("sliding_joint: no beam with index " + std::to_string(slider_));
    const Beam& S = m.beam(slider_);
    build_track(m, p);
    const double sigma = p.number("slider_s");
    if (sigma < -1e-12 * S.length() || sigma > S.length() * (1 + 1e-12))
      throw std::invalid_argument("sliding_joint: slider point s = " + std::to_string(sigma) + " outside beam '" + S.name() + "'");
    stencil_ = S.position_at(std::clamp(sigma, 0.0, S.length()));
    // The frame form reads the stencil's directors too and couples them with the carrier: only
    // the control points that carry weight (one at a beam end), to keep the pattern small.
    for (int j = 0; j < stencil_.n; ++j) {
      if (stencil_.w[j] == 0.0) continue;
      const int k = frame_st_.n++;
      frame_st_.cp[k] = stencil_.cp[j];
      frame_st_.comp[k] = stencil_.comp[j];
      frame_st_.w[k] = stencil_.w[j];
    }
    frame_st_.span = stencil_.span;
    const std::string form = p.string("discrete_gradient", "exact");
    if (form == "exact") exact_ = true;
    else if (form == "midpoint") exact_ = false;
    else throw std::invalid_argument("sliding_joint: discrete_gradient must be 'exact' or 'midpoint', not '" + form + "'");
    const std::string frame = p.string("form", S.is_ancf() || !exact_ ? "spatial" : "frame");
    if (frame == "frame") frame_ = true;
    else if (frame != "spatial") throw std::invalid_argument("sliding_joint: form must be 'frame' or 'spatial', not '" + frame + "'");
    if (frame_ && S.is_ancf())
      throw ParamError("form", "'frame' needs a director slider: '" + S.name() +
                                   "' is an ANCF cable, which has no directors (use 'spatial')");

    // initial s: the closest point of the slider point on the carrier (reference configuration),
    // found by the model's parallel search (closest_point_queries / set_closest_points)
    const Eigen::Vector3d drawn = drawn_point(S, stencil_);
    std::copy(drawn.data(), drawn.data() + 3, point_);
    tolerance_ = p.number("tolerance", 1e-6 * track_.length());
    fail_at_end_ = p.string("at_carrier_end", "stop") == "fail";
    held_at_start_ = p.string("static", "held") == "held";
    std::string track = m.beam(carrier_).name();
    for (size_t k = 1; k < carriers_.size(); ++k) track += "+" + m.beam(carriers_[k]).name();
    label_ = "sliding_joint[" + S.name() + "@" + std::to_string(sigma) + " on " + track + "]";
    prefix_ = S.name() + "_on_" + m.beam(carrier_).name();
  }
  /// One query per carrier of the track; the nearest wins.
  void closest_point_queries(const Model&, std::vector<ClosestPointQuery>& q) const override {
    for (int c : carriers_) {
      ClosestPointQuery query;
      query.carrier = c;
      std::copy(point_, point_ + 3, query.point);
      q.push_back(query);
    }
  }
  void set_closest_points(const Model& m, const ClosestPoint* found) override {
    size_t best = 0;
    for (size_t i = 1; i < carriers_.size(); ++i)
      if (found[i].distance < found[best].distance) best = i;
    const sliding::Track::Piece& piece = track_.pieces[best];
    s0_ = track_.single() ? found[0].s : piece.begin + (piece.reversed ? piece.curve.L - found[best].s : found[best].s);
    const int carrier = carriers_[best];
    if (found[best].distance > tolerance_) {
      std::ostringstream msg;
      if (is_guide())
        msg << "guide: guide '" << name_ << "' at (" << point_[0] << ", " << point_[1] << ", " << point_[2] << ") is "
            << found[best].distance << " from rope '" << m.beam(carrier).name() << "' (closest at s = " << s0_
            << "); tolerance " << tolerance_;
      else
        msg << "sliding_joint: the slider point of beam '" << m.beam(slider_).name() << "' (" << point_[0] << ", "
            << point_[1] << ", " << point_[2] << ") is " << found[best].distance << " from carrier '"
            << m.beam(carrier).name() << "' (closest at s = " << s0_ << (track_.single() ? "" : " on its track")
            << "); tolerance " << tolerance_;
      throw std::invalid_argument(msg.str());
    }
  }
  std::string type() const override { return is_guide() ? "guide" : "sliding_joint"; }
  std::string joint_name() const override { return name_; }
  double sliding_mass(const Model& m) const override { return m.beam_mass(is_guide() ? carrier_ : slider_); }
  std::string label() const override { return label_; }
  // mu (3), then s: the natural-order LU of serial steps then meets s after the multipliers,
  // whose elimination gives its pivot (s first: a zero pivot while mu = 0)
  PetscInt n_extra() const override { return 4; }
  bool extra_is_state(PetscInt k) const override { return k == 3; }
  int slider_beam() const override { return slider_; }
  const ExtraUnknowns& joint_unknowns() const override { return *this; }
  void initial_values(const Model&, std::vector<PetscInt>& rows, std::vector<PetscScalar>& vals) const override {
    rows.push_back(s_index());
    vals.push_back(s0_);
  }
  void bounds(const Model&, std::vector<PetscInt>& rows, std::vector<double>& lo, std::vector<double>& hi) const override {
    rows.push_back(s_index());
    lo.push_back(0.0);
    hi.push_back(track_.length());
  }
  void held_at_start(std::vector<PetscInt>& rows) const override {
    if (held_at_start_) rows.push_back(s_index());
  }

  /// The slider's last stencil point; a fixed guide's: the rope's point nearest it.
  PetscInt elimination_anchor(const Model& m) const override {
    return stencil_.n > 0 ? slider_cp(m, stencil_.n - 1) : nearest_carrier_cp(m);
  }
  void anchor_points(const Model& m, std::vector<PetscInt>& cps) const override {
    for (int j = 0; j < stencil_.n; ++j) cps.push_back(slider_cp(m, j));
  }
  /// A fixed guide: its pivots come from whichever rope points are at the guide (the rope runs).
  void pivots_along(std::vector<int>& beams) const override {
    if (stencil_.n == 0) beams.insert(beams.end(), carriers_.begin(), carriers_.end());
  }
  void elimination_precedence(std::vector<std::pair<int, int>>& pairs) const override {
    if (slider_ >= 0)
      for (int c : carriers_) pairs.emplace_back(slider_, c);
  }
  void reference_couplings(const Model& m, std::vector<std::pair<PetscInt, PetscInt>>& pairs) const override {
    if (stencil_.n > 0) pairs.emplace_back(slider_cp(m, stencil_.n - 1), nearest_carrier_cp(m));
  }
  void distribute(const Model& m) override {
    owned_ = m.dof_map().owns_cp(stencil_.n > 0 ? slider_cp(m, 0) : elimination_anchor(m));
    const auto r = track_.touched_blocks(s0_, s0_);
    move_window(r[0], r[1]);
    set_ghost_window(s0_, s0_);
  }
  /// The slider's points, the carrier points around s (the ghost window: the touched ones plus
  /// kGhostMargin on either side, moved by refresh_needed_dofs) and the joint's extras: the
  /// carrier points a joint reads come from whichever rank owns them, O(1) per joint.
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    if (!owned_) return;
    if (stencil_.n > 0) add_cp_blocks(m.dof_map(), slider_cp(m, 0), stencil_.cp[stencil_.n - 1] - stencil_.cp[0] + 1, dofs);
    for (size_t k = 0; k < carriers_.size(); ++k) {  // the window's control points on each carrier
      const sliding::Track::Piece& piece = track_.pieces[k];
      const int lo = std::max(ghost_lo_, piece.first_cp), hi = std::min(ghost_hi_, piece.first_cp + piece.curve.n_cp() - 1);
      if (lo > hi) continue;
      const int first = std::min(track_.local_cp(lo), track_.local_cp(hi));
      add_cp_blocks(m.dof_map(), m.beam(carriers_[k]).first_cp() + first, hi - lo + 1, dofs);
    }
    for (int k = 0; k < 4; ++k) dofs.push_back(extra_offset() + k);
  }
  bool refresh_needed_dofs(const Model&, const LocalValues& x, const LocalValues& x_old) const override {
    if (!owned_) return false;
    const double s0 = x_old.at(s_index()), s1 = x.at(s_index());
    const auto r = track_.touched_cps(s0, s1);
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
    if (frame_) {
      const FrameDofs d = frame_dofs(m, win_lo_, win_hi_ + 1);
      std::vector<double> zero(d.value_count(), 0.0);
      PetscCall(d.add(zero.data(), sink));
      PetscFunctionReturn(0);
    }
    const int n = 3 * stencil_.n + 3 * (win_hi_ - win_lo_ + 1) + 4;
    const std::vector<double> zero(static_cast<size_t>(4 * (n - 4) + 4 * n), 0.0);
    PetscCall(add_blocks(dofs(m, win_lo_, win_hi_ + 1), zero.data(), sink));
    PetscFunctionReturn(0);
  }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    if (frame_) PetscFunctionReturn(frame_residual(ctx, r));
    const Terms t = terms(ctx);
    const Eigen::Vector3d& mu = t.mu;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int A = t.lo; A <= t.hi; ++A) {
      Eigen::Map<Eigen::Vector3d>(block(r, ctx.map, ctx.model, A)) += t.Wq.at(A) * mu;
      g += t.N1.at(A) * position(ctx.x, ctx.map, ctx.model, A);
    }
    subtract_slider_point(g, ctx.x, ctx.map, ctx.model);
    if (stencil_.n > 0) scatter_stencil(r, ctx.map, ctx.model.beam(slider_), stencil_, -mu);
    r.at(s_index()) += t.Gs.dot(mu);
    for (int k = 0; k < 3; ++k) r.at(extra_offset() + k) += g(k);
    PetscFunctionReturn(0);
  }

  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    if (frame_) PetscFunctionReturn(frame_jacobian(ctx, J));
    const Terms t = terms(ctx);
    const Eigen::Vector3d& mu = t.mu;
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
      const Eigen::Vector3d x1 = position(ctx.x, ctx.map, ctx.model, a);
      const Eigen::Vector3d xh = t.blend_old * position(ctx.x_old, ctx.map, ctx.model, a) + (1.0 - t.blend_old) * x1;
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

  /// The force on the slider: the multipliers (spatial form), or sum_i lambda_i e_i at the
  /// force state (frame form; mid-step under energy-momentum).
  bool joint_force(const EvalContext& ctx, std::array<double, 3>& f) const override {
    if (!owned_) return false;
    Eigen::Vector3d force = multipliers(ctx.x);
    if (frame_) {
      Eigen::Matrix3d e;
      Eigen::Vector3d p;
      slider_frame(ctx.xf, ctx.map, ctx.model.beam(slider_), e, p);
      force = e * force;
    }
    for (int k = 0; k < 3; ++k) f[static_cast<size_t>(k)] = force(k);
    return true;
  }

  /// Outputs (history columns <slider>_on_<carrier>.<name>, a guide's <rope>_at_<name>): s;
  /// ds_dt, its mean rate over the step (0 outside a step); the force of the carrier on the
  /// slider (joint_force: over the step, at its force state); the gap, the distance of the slider
  /// point from the carrier's centre line at the end state (the norm of the constraint rows:
  /// c(s) - p, or its components on the slider's directors in the frame form); a guide's point.
  std::vector<std::string> output_names() const override {
    if (is_guide()) return {"s", "ds_dt", "reaction.x", "reaction.y", "reaction.z", "gap", "point.x", "point.y", "point.z"};
    return {"s", "ds_dt", "reaction.x", "reaction.y", "reaction.z", "gap"};
  }
  std::string output_prefix() const override { return prefix_; }
  void outputs(const EvalContext& ctx, double* v) const override {
    if (!owned_) return;
    const double s1 = ctx.x.at(s_index());
    v[0] += s1;
    if (ctx.h > 0) v[1] += (s1 - ctx.x_old.at(s_index())) / ctx.h;
    std::array<double, 3> f{};
    joint_force(ctx, f);
    for (int k = 0; k < 3; ++k) v[2 + k] += f[static_cast<size_t>(k)];
    v[5] += end_gap(ctx).norm();
    if (is_guide()) {  // where the guide is at the end state (it moves with its body)
      Eigen::Vector3d minus_point = Eigen::Vector3d::Zero();
      subtract_slider_point(minus_point, ctx.x, ctx.map, ctx.model);
      for (int k = 0; k < 3; ++k) v[6 + k] -= minus_point(k);
    }
  }

  /// N = |Lambda - (t . Lambda) t|: Lambda the force on the slider (joint_force), t = c'/|c'| the
  /// carrier's unit tangent at the force state (x_f, s_f). Both are read at the force state, so
  /// d/dx = theta d/dx_f; the multipliers come from x. Every column lies in the joint's own s row
  /// pattern (s, multipliers, slider directors, carrier blocks around s_f within the window).
  bool normal_force(const EvalContext& ctx, double& N, std::vector<PetscInt>& dofs, std::vector<double>& dN) const override {
    if (!owned_) return false;
    const DofMap& map = ctx.map;
    const double th = ctx.theta, sf = ctx.xf.at(s_index());
    const auto range = track_.touched_blocks(sf, sf);
    sliding::Weights d1, d2;
    d1.reset(range[0], range[1] - range[0] + 1);
    d2.reset(range[0], range[1] - range[0] + 1);
    const int e = track_.span_of(sf);
    track_.add_basis(e, sf, 1, 1.0, d1);
    track_.add_basis(e, sf, 2, 1.0, d2);
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), dc_ds = Eigen::Vector3d::Zero();
    for (int a = range[0]; a <= range[1]; ++a) {
      const Eigen::Vector3d xa = position(ctx.xf, map, ctx.model, a);
      c += d1.at(a) * xa;
      dc_ds += d2.at(a) * xa;
    }
    const double len = c.norm();
    const Eigen::Vector3d t = c / len;
    const Eigen::Vector3d lam = multipliers(ctx.x);
    Eigen::Matrix3d E = Eigen::Matrix3d::Identity();
    if (frame_) {
      Eigen::Vector3d p;
      slider_frame(ctx.xf, map, ctx.model.beam(slider_), E, p);
    }
    const Eigen::Vector3d Lambda = E * lam, Nvec = Lambda - t.dot(Lambda) * t;
    N = Nvec.norm();
    // dN = (Nvec . dLambda - (t . Lambda) Nvec . dc' / |c'|) / N   (Nvec is normal to t);
    // at N = 0 (no transverse force) N is not differentiable: its derivative is taken as 0
    const double inv = N > 0.0 ? 1.0 / N : 0.0;
    const Eigen::Vector3d gL = inv * Nvec, gc = -(t.dot(Lambda) * inv / len) * Nvec;
    dofs.clear();
    dN.clear();
    for (int i = 0; i < 3; ++i) {
      dofs.push_back(extra_offset() + i);
      dN.push_back(gL.dot(E.col(i)));
    }
    dofs.push_back(s_index());
    dN.push_back(th * gc.dot(dc_ds));
    for (int a = range[0]; a <= range[1]; ++a)
      for (int k = 0; k < 3; ++k) {
        dofs.push_back(map.q(carrier_cp(ctx.model, a), track_.offset_of_block(a) + k));
        dN.push_back(th * d1.at(a) * gc(k));
      }
    if (frame_)  // Lambda = sum_i lam_i e_i(x_f), e_i = sum_j w_j d_i,j
      for (int j = 0; j < frame_st_.n; ++j)
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) {
            dofs.push_back(map.q(ctx.model.beam(slider_).first_cp() + frame_st_.cp[j], 3 + 3 * i + k));
            dN.push_back(th * frame_st_.w[j] * lam(i) * gL(k));
          }
    return true;
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
    Eigen::Vector3d mu = Eigen::Vector3d::Zero();  // the multipliers
  };

  Terms terms(const EvalContext& ctx) const {
    const sliding::Track& cv = track_;
    const double s1 = ctx.x.at(s_index()), s0 = ctx.x_old.at(s_index());
    Terms t;
    t.mu = multipliers(ctx.x);
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
      const Eigen::Vector3d xh = t.blend_old * position(ctx.x_old, ctx.map, ctx.model, a) + (1.0 - t.blend_old) * position(ctx.x, ctx.map, ctx.model, a);
      t.Gs += t.Ds.at(a) * xh;
    }
    return t;
  }

  /// Unknowns of the frame form: P = the slider point's blocks (3 per stencil entry), then the
  /// carrier curve blocks of the window (3 each); D = the directors d1, d2, d3 of the slider's
  /// stencil control points (9 per entry); E = s, lambda. The joint couples P with D and E, D
  /// with P and E, and E with all; never positions with positions or directors with directors.
  struct FrameDofs {
    std::vector<PetscInt> P, D, E, PE, DE, all;
    size_t value_count() const { return P.size() * DE.size() + D.size() * PE.size() + E.size() * all.size(); }
    /// values: rows P x cols DE, then rows D x cols PE, then rows E x cols all (row-major each).
    PetscErrorCode add(const double* v, const MatSink& J) const {
      PetscFunctionBeginUser;
      const auto n = [](const std::vector<PetscInt>& x) { return static_cast<PetscInt>(x.size()); };
      PetscCall(J.add(n(P), P.data(), n(DE), DE.data(), v));
      v += P.size() * DE.size();
      PetscCall(J.add(n(D), D.data(), n(PE), PE.data(), v));
      v += D.size() * PE.size();
      PetscCall(J.add(n(E), E.data(), n(all), all.data(), v));
      PetscFunctionReturn(0);
    }
  };
  FrameDofs frame_dofs(const Model& m, int c0, int c1) const {
    const DofMap& map = m.dof_map();
    const Beam& S = m.beam(slider_);
    FrameDofs d;
    d.P = stencil_dofs(map, S, frame_st_);
    for (int a = c0; a < c1; ++a)
      for (int k = 0; k < 3; ++k) d.P.push_back(map.q(carrier_cp(m, a), track_.offset_of_block(a) + k));
    for (int j = 0; j < frame_st_.n; ++j)
      for (int k = 0; k < 9; ++k) d.D.push_back(map.q(S.first_cp() + frame_st_.cp[j], 3 + k));
    d.E.push_back(s_index());
    for (int k = 0; k < 3; ++k) d.E.push_back(extra_offset() + k);
    d.PE = d.P;
    d.PE.insert(d.PE.end(), d.E.begin(), d.E.end());
    d.DE = d.D;
    d.DE.insert(d.DE.end(), d.E.begin(), d.E.end());
    d.all = d.P;
    d.all.insert(d.all.end(), d.D.begin(), d.D.end());
    d.all.insert(d.all.end(), d.E.begin(), d.E.end());
    return d;
  }

  /// Coefficients of one evaluation of the frame form, over carrier curve blocks lo..hi.
  struct FrameTerms {
    int lo = 0, hi = 0;
    sliding::Weights W, dW;    // force weights on carrier blocks and d W / d s_n+1
    sliding::Weights D, dD;    // s row: sum_A D_A pi_iA, and d D / d s_n+1
    sliding::Weights N1, dN1;  // the constraint at the end of the step: N(s1), N'(s1)
    double b = 1.0;            // d (force state) / d (end state)
    Eigen::Matrix3d E, E1, Epi;  // columns: directors of the force state, the end state, and of pi's x-derivative
    Eigen::Vector3d v, dv_ds;    // moment arm sum_A W_A xbar_A - pbar and its d / d s_n+1
    Eigen::Vector3d gap, dc_ds;  // c(s1) - p at the end of the step, and c'(s1)
    Eigen::Vector3d Gs, dGs_ds;  // s row: coefficient of lambda_i, and its d / d s_n+1
    Eigen::Vector3d Xpi;         // sum_A D_A (x_A of pi's e-derivative)
  };

  /// Interpolated directors (columns) and point of the slider at a state.
  void slider_frame(const LocalValues& x, const DofMap& map, const Beam& S, Eigen::Matrix3d& e, Eigen::Vector3d& p) const {
    e.setZero();
    p.setZero();
    for (int j = 0; j < frame_st_.n; ++j) {
      const double* c = x.cp(map, S.first_cp() + frame_st_.cp[j]);
      p += frame_st_.w[j] * Eigen::Map<const Eigen::Vector3d>(c);
      for (int i = 0; i < 3; ++i) e.col(i) += frame_st_.w[j] * Eigen::Map<const Eigen::Vector3d>(c + 3 + 3 * i);
    }
  }

  FrameTerms frame_terms(const EvalContext& ctx) const {
    const Beam& S = ctx.model.beam(slider_);
    const sliding::Track& cv = track_;
    const double s1 = ctx.x.at(s_index()), s0 = ctx.x_old.at(s_index());
    FrameTerms t;
    const auto range = cv.touched_blocks(s0, s1);
    t.lo = range[0];
    t.hi = range[1];
    const int nr = t.hi - t.lo + 1;
    for (auto* w : {&t.W, &t.dW, &t.D, &t.dD, &t.N1, &t.dN1}) w->reset(t.lo, nr);
    const int e1 = cv.span_of(s1);
    cv.add_basis(e1, s1, 0, 1.0, t.N1);
    cv.add_basis(e1, s1, 1, 1.0, t.dN1);
    // the force state x_f: mid-step under energy-momentum (theta = 1/2), the end for Endpoint
    t.b = ctx.theta;
    const bool em = ctx.rule == StepRule::EnergyMomentum && exact_;
    Eigen::Matrix3d E0;
    Eigen::Vector3d p0, p1, pf;
    slider_frame(ctx.x, ctx.map, S, t.E1, p1);
    slider_frame(ctx.x_old, ctx.map, S, E0, p0);
    slider_frame(ctx.xf, ctx.map, S, t.E, pf);
    if (em) {
      const int e0 = cv.span_of(s0);
      cv.add_basis(e0, s0, 0, 0.5, t.W);
      cv.add_basis(e1, s1, 0, 0.5, t.W);
      cv.add_basis(e1, s1, 1, 0.5, t.dW);
      cv.difference_quotient(s0, s1, t.D, t.dD);
      t.Epi = t.E1;
    } else {
      const double th = ctx.theta, sf = ctx.xf.at(s_index());
      const int ef = cv.span_of(sf);
      cv.add_basis(ef, sf, 0, 1.0, t.W);
      cv.add_basis(ef, sf, 1, th, t.dW);
      cv.add_basis(ef, sf, 1, 1.0, t.D);
      cv.add_basis(ef, sf, 2, th, t.dD);
      t.Epi = t.E;
    }
    t.v = -pf;
    t.dv_ds.setZero();
    t.gap = -p1;
    t.dc_ds.setZero();
    t.Gs.setZero();
    t.dGs_ds.setZero();
    t.Xpi.setZero();
    for (int a = t.lo; a <= t.hi; ++a) {
      const Eigen::Vector3d x1 = position(ctx.x, ctx.map, ctx.model, a), xf = position(ctx.xf, ctx.map, ctx.model, a);
      t.v += t.W.at(a) * xf;
      t.dv_ds += t.dW.at(a) * xf;
      t.gap += t.N1.at(a) * x1;
      t.dc_ds += t.dN1.at(a) * x1;
      Eigen::Vector3d pi;  // pi_iA, i = 1..3
      if (em) {
        const Eigen::Vector3d x0 = position(ctx.x_old, ctx.map, ctx.model, a);
        pi = 0.5 * (E0.transpose() * x0 + t.E1.transpose() * x1);
        t.Xpi += t.D.at(a) * x1;
      } else {
        pi = t.E.transpose() * xf;
        t.Xpi += t.D.at(a) * xf;
      }
      t.Gs += t.D.at(a) * pi;
      t.dGs_ds += t.dD.at(a) * pi;
    }
    return t;
  }

  PetscErrorCode frame_residual(const EvalContext& ctx, const LocalValues& r) const {
    PetscFunctionBeginUser;
    const FrameTerms t = frame_terms(ctx);
    const Eigen::Vector3d lam = multipliers(ctx.x);
    const Eigen::Vector3d Lambda = t.E * lam;
    const Beam& S = ctx.model.beam(slider_);
    for (int A = t.lo; A <= t.hi; ++A) Eigen::Map<Eigen::Vector3d>(block(r, ctx.map, ctx.model, A)) += t.W.at(A) * Lambda;
    for (int j = 0; j < frame_st_.n; ++j) {
      double* c = r.cp(ctx.map, S.first_cp() + frame_st_.cp[j]);
      Eigen::Map<Eigen::Vector3d>(c) -= frame_st_.w[j] * Lambda;
      for (int i = 0; i < 3; ++i) Eigen::Map<Eigen::Vector3d>(c + 3 + 3 * i) += frame_st_.w[j] * lam(i) * t.v;
    }
    r.at(s_index()) += t.Gs.dot(lam);
    const Eigen::Vector3d phi = t.E1.transpose() * t.gap;
    for (int k = 0; k < 3; ++k) r.at(extra_offset() + k) += phi(k);
    PetscFunctionReturn(0);
  }

  PetscErrorCode frame_jacobian(const EvalContext& ctx, const MatSink& J) const {
    PetscFunctionBeginUser;
    const FrameTerms t = frame_terms(ctx);
    move_window(t.lo, t.hi);
    const Eigen::Vector3d lam = multipliers(ctx.x);
    const Eigen::Vector3d Lambda = t.E * lam, Lambda_pi = t.Epi * lam;
    const FrameDofs d = frame_dofs(ctx.model, win_lo_, win_hi_ + 1);
    const int ny = 3 * frame_st_.n, np = static_cast<int>(d.P.size()), nd = static_cast<int>(d.D.size());
    const int nde = nd + 4, npe = np + 4, nall = np + nd + 4;
    std::vector<double> v(d.value_count(), 0.0);
    double* vP = v.data();                               // rows P x cols (D, s, lambda)
    double* vD = vP + static_cast<size_t>(np * nde);     // rows D x cols (P, s, lambda)
    double* vE = vD + static_cast<size_t>(nd * npe);     // rows (s, lambda) x cols (P, D, s, lambda)
    auto P_ = [&](int row, int col) -> double& { return vP[static_cast<size_t>(row * nde + col)]; };
    auto D_ = [&](int row, int col) -> double& { return vD[static_cast<size_t>(row * npe + col)]; };
    auto E_ = [&](int row, int col) -> double& { return vE[static_cast<size_t>(row * nall + col)]; };
    // column offsets: within DE, s at nd, lambda_i at nd + 1 + i; within PE, s at np; within all,
    // directors from np, s at np + nd
    const double b = t.b;
    // carrier rows (P index ny + 3 (A - win_lo) + k)
    for (int a = t.lo; a <= t.hi; ++a) {
      const int ia = ny + 3 * (a - win_lo_);
      for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3; ++i) {
          P_(ia + k, nd + 1 + i) = t.W.at(a) * t.E(k, i);
          for (int j = 0; j < frame_st_.n; ++j) P_(ia + k, 9 * j + 3 * i + k) = t.W.at(a) * lam(i) * b * frame_st_.w[j];
        }
        P_(ia + k, nd) = t.dW.at(a) * Lambda(k);
        // director rows: d (w_j lambda_i v) / d x_A
        for (int j = 0; j < frame_st_.n; ++j)
          for (int i = 0; i < 3; ++i) D_(9 * j + 3 * i + k, ia + k) = frame_st_.w[j] * lam(i) * t.W.at(a) * b;
        E_(0, ia + k) = b * t.D.at(a) * Lambda_pi(k);
        for (int i = 0; i < 3; ++i) E_(1 + i, ia + k) = t.N1.at(a) * t.E1(k, i);
      }
    }
    // slider point rows and columns
    for (int j = 0; j < frame_st_.n; ++j) {
      const double wj = frame_st_.w[j];
      for (int k = 0; k < 3; ++k) {
        const int iy = 3 * j + k;
        for (int i = 0; i < 3; ++i) {
          P_(iy, nd + 1 + i) = -wj * t.E(k, i);
          for (int l = 0; l < frame_st_.n; ++l) P_(iy, 9 * l + 3 * i + k) = -wj * lam(i) * b * frame_st_.w[l];
          for (int l = 0; l < frame_st_.n; ++l) D_(9 * l + 3 * i + k, iy) = -frame_st_.w[l] * lam(i) * b * wj;
          E_(1 + i, iy) = -wj * t.E1(k, i);
        }
      }
    }
    // director rows' (s, lambda) columns; s and constraint rows' director columns
    for (int j = 0; j < frame_st_.n; ++j) {
      const double wj = frame_st_.w[j];
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
          const int row = 9 * j + 3 * i + k;
          D_(row, np) = wj * lam(i) * t.dv_ds(k);
          D_(row, np + 1 + i) = wj * t.v(k);
          E_(0, np + row) = b * lam(i) * wj * t.Xpi(k);
          E_(1 + i, np + row) = wj * t.gap(k);
        }
    }
    // (s, lambda) x (s, lambda)
    const int is = np + nd;
    E_(0, is) = t.dGs_ds.dot(lam);
    for (int i = 0; i < 3; ++i) {
      E_(0, is + 1 + i) = t.Gs(i);
      E_(1 + i, is) = t.E1.col(i).dot(t.dc_ds);
    }
    PetscCall(d.add(v.data(), J));
    PetscFunctionReturn(0);
  }

  /// The constraint rows at the end state x, summed in the order residual() sums them.
  Eigen::Vector3d end_gap(const EvalContext& ctx) const {
    const double s1 = ctx.x.at(s_index());
    const auto range = track_.touched_blocks(s1, s1);
    sliding::Weights N1;
    N1.reset(range[0], range[1] - range[0] + 1);
    track_.add_basis(track_.span_of(s1), s1, 0, 1.0, N1);
    if (frame_) {
      Eigen::Matrix3d E1;
      Eigen::Vector3d p1;
      slider_frame(ctx.x, ctx.map, ctx.model.beam(slider_), E1, p1);
      Eigen::Vector3d gap = -p1;
      for (int a = range[0]; a <= range[1]; ++a) gap += N1.at(a) * position(ctx.x, ctx.map, ctx.model, a);
      return E1.transpose() * gap;
    }
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int a = range[0]; a <= range[1]; ++a) g += N1.at(a) * position(ctx.x, ctx.map, ctx.model, a);
    subtract_slider_point(g, ctx.x, ctx.map, ctx.model);
    return g;
  }

  /// g -= the slider point p at the state x (spatial form): the stencil over the slider's
  /// coordinates, one block at a time, or a fixed guide's point.
  void subtract_slider_point(Eigen::Vector3d& g, const LocalValues& x, const DofMap& map, const Model& m) const {
    if (stencil_.n == 0) {
      g -= offset_;
      return;
    }
    const PetscInt first = m.beam(slider_).first_cp();
    for (int j = 0; j < stencil_.n; ++j)
      g -= stencil_.w[j] * Eigen::Map<const Eigen::Vector3d>(x.cp(map, first + stencil_.cp[j]) + stencil_.comp[j]);
  }
  bool is_guide() const { return !name_.empty(); }
  static sliding::Curve curve_of(const Beam& C) {
    return {C.is_ancf() ? sliding::Curve::Kind::Hermite : sliding::Curve::Kind::BSpline, C.n_spans(), C.length()};
  }
  /// The carrier, or the track of carriers `carrier_track` (beam indices along s): each one's end
  /// meets the next one's start or end as drawn, which decides the way each is run through.
  void build_track(const Model& m, const EffectParams& p) {
    carriers_ = {carrier_};
    if (p.vec.count("carrier_track")) {
      carriers_.clear();
      for (double b : p.vec.at("carrier_track")) carriers_.push_back(static_cast<int>(b));
    }
    const int nb = static_cast<int>(m.beams().size());
    for (size_t k = 0; k < carriers_.size(); ++k) {
      const int c = carriers_[k];
      if (c < 0 || c >= nb) throw std::invalid_argument("sliding_joint: no beam with index " + std::to_string(c));
      if (c == slider_) throw ParamError("carrier", "a beam cannot slide on itself ('" + m.beam(c).name() + "')");
      if (m.beam(c).is_rigid())
        throw ParamError("carrier", "'" + m.beam(c).name() + "' is a [[body]]: a slider runs on beams");
      for (size_t j = 0; j < k; ++j)
        if (carriers_[j] == c) throw ParamError("carrier", "beam '" + m.beam(c).name() + "' is twice on the track");
    }
    carrier_ = carriers_[0];
    if (carriers_.size() == 1) {
      track_.append(curve_of(m.beam(carrier_)), false);
      return;
    }
    // the ends of consecutive carriers that meet decide each one's way along the track
    auto ends = [&](int c) {
      const Beam& B = m.beam(c);
      return std::array<Eigen::Vector3d, 2>{drawn_point(B, B.position_at(0.0)), drawn_point(B, B.position_at(B.length()))};
    };
    std::vector<bool> reversed(carriers_.size(), false);
    for (size_t k = 0; k + 1 < carriers_.size(); ++k) {
      const Beam &A = m.beam(carriers_[k]), &B = m.beam(carriers_[k + 1]);
      const auto ea = ends(carriers_[k]), eb = ends(carriers_[k + 1]);
      const double tol = 1e-6 * std::max(A.length(), B.length());
      int best_a = -1, best_b = -1;
      double best = std::numeric_limits<double>::infinity();
      for (int ia = 0; ia < 2; ++ia) {
        if (k > 0 && ia == (reversed[k] ? 1 : 0)) continue;  // its entry end is taken
        for (int ib = 0; ib < 2; ++ib)
          if ((ea[ia] - eb[ib]).norm() < best) best = (ea[ia] - eb[ib]).norm(), best_a = ia, best_b = ib;
      }
      if (best > tol) {
        std::ostringstream msg;
        msg << "carrier '" << B.name() << "' does not begin where '" << A.name() << "' ends: the nearest of their ends are "
            << best << " apart as drawn (tolerance " << tol << "); a track's carriers follow each other end to end";
        throw ParamError("carrier", msg.str());
      }
      if (k == 0) reversed[0] = best_a == 0;
      reversed[k + 1] = best_b == 1;
    }
    for (size_t k = 0; k < carriers_.size(); ++k) track_.append(curve_of(m.beam(carriers_[k])), reversed[k]);
  }
  /// The carrier control point (global index) nearest the slider point as drawn (a scan of the
  /// track's carriers' points).
  PetscInt nearest_carrier_cp(const Model& m) const {
    PetscInt nearest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (int carrier : carriers_) {
      const Beam& C = m.beam(carrier);
      const int nq = C.coordinates_per_cp();
      for (int c = 0; c < C.n_cp(); ++c) {
        const double* x = C.q_ref().data() + static_cast<size_t>(nq) * static_cast<size_t>(c);
        const double d = (x[0] - point_[0]) * (x[0] - point_[0]) + (x[1] - point_[1]) * (x[1] - point_[1]) +
                         (x[2] - point_[2]) * (x[2] - point_[2]);
        if (d < best) best = d, nearest = C.first_cp() + c;
      }
    }
    return nearest;
  }

  /// The global control point of track block A (on whichever carrier holds it).
  PetscInt carrier_cp(const Model& m, int A) const {
    return m.beam(carriers_[static_cast<size_t>(track_.piece_of_block(A))]).first_cp() + track_.cp_of_block(A);
  }
  /// Track block A in the state x, and a pointer to its 3 entries in r.
  Eigen::Vector3d position(const LocalValues& x, const DofMap& map, const Model& m, int A) const {
    return Eigen::Map<const Eigen::Vector3d>(x.cp(map, carrier_cp(m, A)) + track_.offset_of_block(A));
  }
  double* block(const LocalValues& r, const DofMap& map, const Model& m, int A) const {
    return r.cp(map, carrier_cp(m, A)) + track_.offset_of_block(A);
  }
  Eigen::Vector3d multipliers(const LocalValues& x) const {
    return {x.at(extra_offset()), x.at(extra_offset() + 1), x.at(extra_offset() + 2)};
  }
  PetscInt s_index() const { return extra_offset() + 3; }

  /// Events: the slider passes the carrier's start (g = s) or its end (g = L - s), L the
  /// carrier's reference length.
  int n_events() const override { return 2; }
  void event_values(const Model&, const PetscScalar* x, PetscInt lo, PetscInt hi, double* g) const override {
    const PetscInt row = s_index();
    if (row < lo || row >= hi) return;
    g[0] = x[row - lo];
    g[1] = track_.length() - x[row - lo];
  }
  double event_scale(const Model&, int) const override { return track_.length(); }
  Action event_action(int) const override { return fail_at_end_ ? Action::Fail : Action::Stop; }
  std::string event_message(const Model& m, int i, double g, const std::string& when) const override {
    const double s = i == 0 ? g : track_.length() - g;
    char value[32];
    std::snprintf(value, sizeof value, "%.9g", s);
    if (is_guide())
      return "the " + std::string(i == 0 ? "start" : "end") + " of rope '" + m.beam(carrier_).name() +
             "' reached guide '" + name_ + "' (s = " + value + ") " + when + "; run stopped (at_rope_end = '" +
             (fail_at_end_ ? "fail" : "stop") + "')";
    // the carrier at that end of the track, and the end of it there
    const size_t k = i == 0 ? 0 : carriers_.size() - 1;
    const bool carriers_start = (i == 0) != track_.pieces[k].reversed;
    return "the slider of beam '" + m.beam(slider_).name() + "' reached the " + (carriers_start ? "start" : "end") +
           " of carrier '" + m.beam(carriers_[k]).name() + "'" + (track_.single() ? "" : ", the " + std::string(i == 0 ? "start" : "end") + " of its track") +
           " (s = " + value + ") " + when +
           "; run stopped (at_carrier_end = '" + (fail_at_end_ ? "fail" : "stop") + "')";
  }

  /// Global index of the slider stencil's control point (node) j.
  PetscInt slider_cp(const Model& m, int j) const { return m.beam(slider_).first_cp() + stencil_.cp[j]; }
  /// Slider stencil blocks (3 each), carrier curve blocks [c0, c1) (3 each), s, mu.
  std::vector<PetscInt> dofs(const Model& m, int c0, int c1) const {
    const DofMap& map = m.dof_map();
    std::vector<PetscInt> d = stencil_.n > 0 ? stencil_dofs(map, m.beam(slider_), stencil_) : std::vector<PetscInt>{};
    d.reserve(static_cast<size_t>(3 * stencil_.n + 3 * (c1 - c0) + 4));
    for (int a = c0; a < c1; ++a)
      for (int k = 0; k < 3; ++k) d.push_back(map.q(carrier_cp(m, a), track_.offset_of_block(a) + k));
    d.push_back(s_index());  // the local block's order: s, then mu
    for (int k = 0; k < 3; ++k) d.push_back(extra_offset() + k);
    return d;
  }

  /// Keep carrier curve blocks [lo, hi] inside the window; re-centre it (with margin) when they
  /// leave. Touched ranges of a Hermite curve start at an r block and end at an r' block, and the
  /// margin is whole nodes, so the window holds whole nodes.
  void move_window(int lo, int hi) const {
    if (lo >= win_lo_ && hi <= win_hi_) return;
    int per_cp = 1;
    for (const auto& piece : track_.pieces) per_cp = std::max(per_cp, piece.curve.blocks_per_cp());
    const int margin = kWindowMargin * per_cp;
    win_lo_ = std::max(0, lo - margin);
    win_hi_ = std::min(track_.n_blocks() - 1, hi + margin);
  }
  /// Ghost the carrier points touched by [s0, s1] plus kGhostMargin on either side.
  void set_ghost_window(double s0, double s1) const {
    const auto r = track_.touched_cps(s0, s1);
    ghost_lo_ = std::max(0, r[0] - kGhostMargin);
    ghost_hi_ = std::min(track_.n_cp() - 1, r[1] + kGhostMargin);
  }
  static constexpr int kWindowMargin = 2;  ///< carrier points (nodes) beyond the touched ones
  /// Ghosted carrier points beyond the touched ones: wider than the Jacobian's window, which
  /// must lie within them (its values are read), so ghosts move less often than the pattern.
  static constexpr int kGhostMargin = 4;

  int slider_, carrier_;
  mutable int win_lo_ = 0, win_hi_ = -1;  ///< carrier curve blocks in the Jacobian pattern
  mutable int ghost_lo_ = 0, ghost_hi_ = -1;  ///< carrier points ghosted
  std::vector<int> carriers_;   ///< the track's carriers, along s (carrier_ the first)
  sliding::Track track_;        ///< their centre lines joined: the basis over s
  PositionStencil stencil_;     ///< the slider point on the slider beam
  PositionStencil frame_st_;    ///< its entries of nonzero weight (the frame form)
  bool exact_ = true;
  bool frame_ = false;  ///< the frame-projected form (director sliders)
  double s0_ = 0.0;
  double point_[3] = {0, 0, 0};  ///< the slider point, reference configuration
  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();  ///< a fixed guide's point (no slider unknowns)
  std::string name_;             ///< a guide's name ("": a sliding joint)
  double tolerance_ = 0.0;       ///< largest distance from the carrier at the start
  bool fail_at_end_ = false;     ///< at_carrier_end = "fail": the slider leaving ends the run as failed
  bool held_at_start_ = true;    ///< static = "held": the equilibrium start keeps s
  std::string label_;
  std::string prefix_;  ///< of the history columns: <slider>_on_<carrier>
  bool owned_ = false;
};

void register_sliding_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  ParamSpec at{"at", K::Point, "m", "the slider's point: \"start\", \"end\" or an arc length", "\"start\""};
  at.on = "slider";
  r.add(table_effect_spec(
            "sliding_joint", "sliding_joint", "", EnergyRole::Constraint,
            "a point of one beam (the slider) kept on another beam's centre line (the carrier), free to slide along "
            "it and to turn",
            {{"slider", K::Beam, "", "the beam whose point slides", ""},
             at,
             {"carrier", K::Track, "",
              "the beam it slides on, or a track: a list of beams each beginning where the one before ends (a "
              "carriage passing from one track rope onto the next; join them with a [[joint]] or [[rigid_joint]] "
              "there); s runs along the list",
              ""},
             {"discrete_gradient", K::Choice, "",
              "\"exact\": energy conserved across knots; \"midpoint\": the seed paper's form", "\"exact\"", -kInf,
              kInf, false, 0, {"exact", "midpoint"}},
             optional_param({"form", K::Choice, "",
                             "\"frame\": the constraint in the slider's director frame (energy, linear and angular "
                             "momentum exact under energy-momentum); \"spatial\": c(s) - p = 0. Default: frame for "
                             "director sliders with the exact gradient, spatial otherwise",
                             "", -kInf, kInf, false, 0, {"frame", "spatial"}}),
             {"at_carrier_end", K::Choice, "",
              "when the slider reaches an end of its carrier: \"stop\" the run (exit 0) or \"fail\" (exit 1)",
              "\"stop\"", -kInf, kInf, false, 0, {"stop", "fail"}},
             optional_param({"tolerance", K::Number, "m",
                             "largest slider-carrier distance allowed at the start (default: 1e-6 of the carrier's "
                             "length, or the track's)",
                             "", 0.0, kInf, true}),
             {"static", K::Choice, "",
              "in the equilibrium start: \"held\" keeps s, \"free\" lets the slider slide to equilibrium",
              "\"held\"", -kInf, kInf, false, 0, {"held", "free"}}}),
        [](const Model& m, const EffectParams& p) { return std::make_unique<SlidingJoint>(m, p); });
  r.add(table_effect_spec(
            "guide", "guide", "", EnergyRole::Constraint,
            "a point the rope runs through (a ring, fairlead, saddle or small sheave), fixed in space or on a rigid "
            "body: the rope's arc length there is free, the rope turns freely",
            {{"rope", K::Beam, "", "the rope (a director beam or an ANCF cable)", ""},
             {"point", K::Vector, "m", "where the rope passes, as drawn (a point of the rope)", "", -kInf, kInf, false, 3},
             optional_param({"body", K::Beam, "", "the [[body]] that carries the guide (fixed in space without it)", ""}),
             {"name", K::Name, "", "the guide's name: history columns <rope>_at_<name>.*, and how [[friction]] and "
                                   "[[slider_drive]] name it", "guide<k>, k its place among the [[guide]] entries"},
             {"at_rope_end", K::Choice, "",
              "when an end of the rope reaches the guide: \"stop\" the run (exit 0) or \"fail\" (exit 1)", "\"stop\"",
              -kInf, kInf, false, 0, {"stop", "fail"}},
             optional_param({"tolerance", K::Number, "m",
                             "largest guide-rope distance allowed at the start (default: half a span of the rope: a corner drawn at "
                             "the guide is cut by about a quarter span; the equilibrium start closes the gap, a start "
                             "from the drawing steps onto it)", "",
                             0.0, kInf, true}),
             {"static", K::Choice, "",
              "in the equilibrium start: \"free\" lets the rope run through to equilibrium, \"held\" keeps it",
              "\"free\"", -kInf, kInf, false, 0, {"free", "held"}}}),
        [](const Model& m, const EffectParams& p) { return std::make_unique<SlidingJoint>(m, p, SlidingJoint::GuideTag{}); });
}

}  // namespace slidebeam::effects
