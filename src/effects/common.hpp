// SPDX-License-Identifier: MIT
#pragma once
/// @file Helpers shared by effects: which items a rank owns, gathering a span's coordinates,
/// and the global indices of its unknowns.

#include "kernels/ancf_kernels.hpp"
#include "kernels/beam_kernels.hpp"
#include "model/model.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace slidebeam::effects {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A number as %g writes it, and a point as (x, y, z): for messages a user reads.
std::string format_number(double x);
std::string format_point(const Eigen::Vector3d& p);

/// The spec of an effect the model creates itself (one per [[beam]]): no table of its own,
/// its role in the energy balance.
inline EffectSpec model_effect_spec(const std::string& type, EnergyRole role, const std::string& meaning,
                                    const std::string& stored = "") {
  EffectSpec s;
  s.type = type;
  s.role = role;
  s.meaning = meaning;
  s.stored = stored;
  return s;
}

/// The spec of an effect a scene creates with the entries of [[table]] (variant: the value of
/// the entry's `type` key that picks this effect when several share the table).
inline EffectSpec table_effect_spec(const std::string& type, const std::string& table, const std::string& variant,
                                    EnergyRole role, const std::string& meaning, std::vector<ParamSpec> params,
                                    const std::string& stored = "") {
  EffectSpec s = model_effect_spec(type, role, meaning, stored);
  s.table = table;
  s.variant = variant;
  s.params = std::move(params);
  return s;
}

/// A parameter that may be left out (the effect then decides).
inline ParamSpec optional_param(ParamSpec p) {
  p.optional = true;
  return p;
}

/// Beam index from parameters, checked against the model.
int beam_param(const Model& model, const EffectParams& p);
/// Beam index of an effect that exists for one formulation only ("who" names the effect in the
/// error message).
int director_beam_param(const Model& model, const EffectParams& p, const std::string& who);
int ancf_beam_param(const Model& model, const EffectParams& p, const std::string& who);

/// Rank that evaluates span (element) e of a beam: the owner of Beam::span_owner_cp(e), so that
/// every span has exactly one owner and neighbouring spans mostly stay on one rank.
inline bool owns_span(const Model& m, const Beam& b, int e) {
  return m.dof_map().owns_cp(b.first_cp() + b.span_owner_cp(e));
}

/// Global indices of the coordinate 3-blocks of a position stencil (3 per stencil entry).
std::vector<PetscInt> stencil_dofs(const DofMap& map, const Beam& b, const PositionStencil& st);
/// r(s) = sum_j w_j y_j of a stencil in the state x.
Eigen::Vector3d stencil_point(const LocalValues& x, const DofMap& map, const Beam& b, const PositionStencil& st);
/// r(stencil's nodes) += w_j f for every entry j: the generalised force of a point force f.
void scatter_stencil(const LocalValues& r, const DofMap& map, const Beam& b, const PositionStencil& st,
                     const Eigen::Vector3d& f);

/// The nonzero pattern of a dense block on the unknowns d (a std::vector or std::array of
/// global indices): d x d zeros.
template <class Dofs>
PetscErrorCode add_block_pattern(const MatSink& sink, const Dofs& d) {
  const auto n = static_cast<PetscInt>(d.size());
  const std::vector<double> zero(d.size() * d.size(), 0.0);
  return sink.add(n, d.data(), n, d.data(), zero.data());
}

/// Index (within the beam) of the end control point at arc length s (0 or L), or -1 if s is
/// inside the beam. Open knot vectors make end control points interpolate; ANCF end nodes are
/// the end points.
int end_cp(const Beam& b, double s);

/// An element effect whose only term is a constant mass matrix (inertia): it reads no state and
/// has no residual or tangent of its own (the time integrator applies the mass).
template <class Base>
class MassOnlyEffect : public Base, public MassSource {
 public:
  using Base::Base;
  void needed_dofs(const Model&, std::vector<PetscInt>&) const override {}
  PetscErrorCode residual(const EvalContext&, const LocalValues&) const override { return 0; }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override { return 0; }
};

/// The JointLink of an effect acting on a sliding joint's or a guide's s (friction, a slider
/// drive): linked to the joint made before it on the same slider beam (params `beam`), or to the
/// guide named (`guide`).
class SlidingJointLink : public JointLink, public NumberingHints {
 public:
  /// type: the effect's type, for the error when the beam is no slider.
  SlidingJointLink(const Model& m, const EffectParams& p, const char* type);
  int linked_slider() const override { return slider_; }
  std::string linked_name() const override { return guide_; }
  void link(const Model& m, const JointTarget* joint) override;
  /// Extras anchored with the joint's are eliminated after them wherever those go (a fixed
  /// guide's: after its rope, NumberingHints::pivots_along).
  void pivots_along(std::vector<int>& beams) const override {
    if (const auto* h = dynamic_cast<const NumberingHints*>(joint_)) h->pivots_along(beams);
  }

 protected:
  /// The joint's s: its fourth extra (after the three multipliers).
  PetscInt s_index() const { return joint_->joint_unknowns().extra_offset() + 3; }
  /// The anchor of the joint's own extras: the linked effect's extras go right after them.
  PetscInt joint_anchor(const Model& m) const { return joint_ ? joint_->joint_unknowns().elimination_anchor(m) : -1; }
  /// "<type>[<slider beam>]"
  std::string link_label(const Model& m) const;

  int slider_ = -1;
  std::string guide_;  ///< the guide's name ("": a sliding joint's slider beam)
  const JointTarget* joint_ = nullptr;

 private:
  const char* type_;
};

/// A clamp inside a beam or on a body (params beam, s, point): a rigid joint to the ground
/// (joints.cpp); a clamp at a beam end prescribes the end control point instead (supports.cpp).
std::unique_ptr<Effect> make_clamp_inside(const Model& m, const EffectParams& p);

/// The spans on both sides of knot i of a director beam (-1: none).
inline void knot_spans(const Beam& b, int i, int& left, int& right) {
  left = i >= 1 ? i - 1 : -1;
  right = i < b.n_spans() ? i : -1;
}
/// The point of beam b that the stencil interpolates, in the beam's reference (drawn) state.
inline Eigen::Vector3d drawn_point(const Beam& b, const PositionStencil& st) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int j = 0; j < st.n; ++j)
    for (int k = 0; k < 3; ++k)
      x[k] += st.w[j] * b.q_ref()[static_cast<size_t>(b.coordinates_per_cp() * st.cp[j] + st.comp[j] + k)];
  return x;
}
/// A 3-vector parameter of an effect.
inline Eigen::Vector3d vector3_param(const EffectParams& p, const char* key) {
  const auto& v = p.vector(key, 3);
  return {v[0], v[1], v[2]};
}

/// A direction parameter (an axis, a normal), normalised; `what` names it in the error.
inline Eigen::Vector3d unit_vector_param(const EffectParams& p, const char* key, const std::string& what) {
  const Eigen::Vector3d n = vector3_param(p, key);
  if (!(n.norm() > 0.0) || !n.allFinite())
    throw ParamError(key, what + " must be a nonzero vector, got " + format_point(n));
  return n.normalized();
}

/// An orthonormal pair perpendicular to the unit vector a (a, p, q right-handed).
inline std::pair<Eigen::Vector3d, Eigen::Vector3d> perpendicular_pair(const Eigen::Vector3d& a) {
  const Eigen::Vector3d helper = std::abs(a.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d p = a.cross(helper).normalized();
  return {p, a.cross(p)};
}

/// The first control point (beam-local) of knot i's patch.
inline int knot_first_cp(const Beam& b, int i) {
  int l, r;
  knot_spans(b, i, l, r);
  return l >= 0 ? l : r;
}
/// The last control point (beam-local) of knot i's patch.
inline int knot_last_cp(const Beam& b, int i) {
  int l, r;
  knot_spans(b, i, l, r);
  return (r >= 0 ? r : l) + 2;
}

/// Add all unknowns (coordinates and multipliers) of control points cp0 .. cp0+n-1 to a dof list.
void add_cp_blocks(const DofMap& map, PetscInt cp0, int n, std::vector<PetscInt>& dofs);

/// A knot's moment gradient: 3 x the coordinates of its 3 (end knot) or 4 control points.
using KnotGradient = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 4 * kernels::kNq>;
/// The gradients of the spans' Gamma moments toward their left and right knots in one state,
/// by span (filled for the spans a rank's knots read: KnotPatches::moment_spans).
struct SpanMomentGradients {
  std::vector<kernels::Mat3El> left, right;
  template <class SpanCoordinates>
  void compute(const Beam& b, const std::vector<int>& spans, SpanCoordinates&& span_q) {
    left.resize(static_cast<size_t>(b.n_spans()));
    right.resize(static_cast<size_t>(b.n_spans()));
    for (int f : spans)
      kernels::span_gamma_moment_gradients(b.strain_table(), &b.gp(f, 0), b.n_gp(), span_q(f),
                                           left[static_cast<size_t>(f)], right[static_cast<size_t>(f)]);
  }
  /// Knot i's: its spans' moments toward it, 3 x the coordinates of its control points (knot_first_cp on).
  KnotGradient knot(const Beam& b, int i) const {
    int l, r;
    knot_spans(b, i, l, r);
    const int cp0 = knot_first_cp(b, i);
    KnotGradient G = KnotGradient::Zero(3, kernels::kNq * (knot_last_cp(b, i) + 1 - cp0));
    if (l >= 0) G.middleCols(kernels::kNq * (l - cp0), kernels::kNqEl) += right[static_cast<size_t>(l)];
    if (r >= 0) G.middleCols(kernels::kNq * (r - cp0), kernels::kNqEl) += left[static_cast<size_t>(r)];
    return G;
  }
};

/// A director beam's Jacobian blocks summed on this rank by control point before they go to the
/// global matrix: one add per control point's 12 coordinate rows over the control points up to
/// `reach` away. Spans and knot patches overlap, and added one by one their blocks repeat each
/// entry up to seven times, all summed again by PETSc's COO assembly.
class ControlPointBand {
 public:
  /// The control points (beam-local) that the spans and the knot patches given touch; they couple
  /// up to 2 apart (spans), 3 with knots.
  void layout(const Beam& b, const std::vector<int>& spans, const std::vector<int>& knots);
  void zero() { std::fill(v_.begin(), v_.end(), 0.0); }
  /// += the row-major (12 n) x (12 n) block K over control points cp0 .. cp0 + n - 1 (beam-local).
  void add(int cp0, int n, const double* K) {
    const int m = kernels::kNq * n;
    for (int r = 0; r < m; ++r) {
      double* dst = segment(cp0, r);
      const double* src = K + static_cast<size_t>(r) * static_cast<size_t>(m);
      for (int j = 0; j < m; ++j) dst[j] += src[j];
    }
  }
  /// += Ga^T diag(w) Gb over control points cp0 .. cp0 + n - 1 (beam-local), Ga and Gb 3 x 12 n.
  template <class Gradient>
  void add_outer(int cp0, int n, const Gradient& Ga, const Eigen::Vector3d& w, const Gradient& Gb) {
    constexpr int kMax = kernels::kNq * (2 * 3 + 1);
    const int m = kernels::kNq * n;
    double b[3][kMax];
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < m; ++j) b[k][j] = Gb(k, j);
    for (int r = 0; r < m; ++r) {
      double* dst = segment(cp0, r);
      const double a0 = w(0) * Ga(0, r), a1 = w(1) * Ga(1, r), a2 = w(2) * Ga(2, r);
      for (int j = 0; j < m; ++j) dst[j] += a0 * b[0][j] + a1 * b[1][j] + a2 * b[2][j];
    }
  }
  /// J += the band, control point by control point (collective only as J.add is).
  PetscErrorCode flush(const DofMap& map, const Beam& b, const MatSink& J) const;

 private:
  // row r of a block over control points cp0 on: its columns are contiguous in the band, from cp0
  double* segment(int cp0, int r) {
    const int a = r / kernels::kNq;
    return &v_[row_offset(cp0 + a, r % kernels::kNq)] + kernels::kNq * (reach_ - a);
  }
  size_t row_offset(int cp, int i) const {
    return (static_cast<size_t>(cp - lo_) * kernels::kNq + static_cast<size_t>(i)) * static_cast<size_t>(width());
  }
  int width() const { return kernels::kNq * (2 * reach_ + 1); }
  int lo_ = 0, hi_ = -1, reach_ = 2;
  std::vector<double> v_;  // row (cp - lo, i), column (cp' - cp + reach, j)
};

/// Which knots of a director beam's assumed-strain patches a rank assembles and which spans' moments
/// it needs: knot i is assembled by the owner of span min(i, n - 1), and a knot's value takes the
/// moments of both its spans (so a rank reads one span beyond its own on either side).
struct KnotPatches {
  std::vector<int> knots, moment_spans;
  void distribute(const Beam& b, const std::vector<int>& elements) {
    const int n = b.n_spans();
    std::vector<char> need(static_cast<size_t>(n), 0);
    for (int e : elements) {
      for (int f = std::max(e - 1, 0); f <= std::min(e + 1, n - 1); ++f) need[static_cast<size_t>(f)] = 1;
      knots.push_back(e);
      if (e == n - 1) knots.push_back(n);
    }
    for (int f = 0; f < n; ++f)
      if (need[static_cast<size_t>(f)]) moment_spans.push_back(f);
  }
  void needed_dofs(const DofMap& map, const Beam& b, std::vector<PetscInt>& dofs) const {
    for (int f : moment_spans) add_cp_blocks(map, b.first_cp() + f, 3, dofs);
  }
};

/// The 36 coordinates of span e (control points e, e+1, e+2) in the state x.
kernels::VecEl gather_span(const LocalValues& x, const DofMap& map, const Beam& b, int e);

/// Global indices of the 36 coordinates of span e.
std::array<PetscInt, kernels::kNqEl> span_q_dofs(const DofMap& map, const Beam& b, int e);

/// r(span coordinates) += v.
void scatter_span(const DofMap& map, const LocalValues& r, const Beam& b, int e, const kernels::VecEl& v);

/// An effect integrated element by element over one beam (a director beam's knot spans, an
/// ANCF cable's elements): each rank takes the elements it owns (owns_span), reads their
/// kPoints control points and may touch the kElDofs x kElDofs block of their coordinates, whose
/// global indices element_dofs gives.
template <int kPoints, int kElDofs>
class ElementEffect : public Effect {
 public:
  using Dofs = std::array<PetscInt, kElDofs>;
  ElementEffect(int beam, const Model& m) : beam_(beam), name_(m.beam(beam).name()) {}
  std::string label() const override { return type() + "[" + name_ + "]"; }

  void distribute(const Model& m) override {
    const Beam& b = m.beam(beam_);
    for (int e = 0; e < b.n_spans(); ++e)
      if (owns_span(m, b, e)) elements_.push_back(e);
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    const Beam& b = m.beam(beam_);
    for (int e : elements_) add_cp_blocks(m.dof_map(), b.first_cp() + e, kPoints, dofs);
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    const Beam& b = m.beam(beam_);
    for (int e : elements_) PetscCall(add_block_pattern(sink, element_dofs(m.dof_map(), b, e)));
    PetscFunctionReturn(0);
  }

 protected:
  virtual Dofs element_dofs(const DofMap& map, const Beam& b, int e) const = 0;
  int beam_;
  std::string name_;
  std::vector<int> elements_;
};

/// An effect integrated span by span over a director beam (strain energy, damping, inertia).
class SpanEffect : public ElementEffect<3, kernels::kNqEl> {
 public:
  SpanEffect(const Model& m, const EffectParams& p, const std::string& who)
      : ElementEffect(director_beam_param(m, p, who), m) {}

 protected:
  Dofs element_dofs(const DofMap& map, const Beam& b, int e) const override { return span_q_dofs(map, b, e); }
};

/// A span-wise term whose membrane and shear strains may be the knots' (assumed strains): where
/// knots_used, a rank also reads the spans whose moments its knots take (patches_), and its
/// Jacobian couples a knot's two spans (band_, by control point).
class KnotBandSpanEffect : public SpanEffect {
 public:
  using SpanEffect::SpanEffect;
  void distribute(const Model& m) override {
    SpanEffect::distribute(m);
    if (knots_used(m.beam(beam_))) patches_.distribute(m.beam(beam_), elements_);
    band_.layout(m.beam(beam_), elements_, patches_.knots);
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    SpanEffect::needed_dofs(m, dofs);
    patches_.needed_dofs(m.dof_map(), m.beam(beam_), dofs);
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    ControlPointBand zero = band_;
    zero.zero();
    return zero.flush(m.dof_map(), m.beam(beam_), sink);
  }

 protected:
  virtual bool knots_used(const Beam& b) const { return b.gamma_at_knots(); }
  /// r += span e's residual (the spans' part: the knots' comes apart), K (if given) += its tangent.
  virtual void element(const EvalContext& ctx, const Beam& b, int e, kernels::VecEl& r, kernels::MatEl* K) const = 0;
  /// r += every owned span's residual.
  void add_span_residuals(const EvalContext& ctx, const Beam& b, const LocalValues& r) const {
    for (int e : elements_) {
      kernels::VecEl re = kernels::VecEl::Zero();
      element(ctx, b, e, re, nullptr);
      scatter_span(ctx.map, r, b, e, re);
    }
  }
  /// band_ = every owned span's tangent (the knots' tangents are added to it before it is flushed).
  void span_tangents_into_band(const EvalContext& ctx, const Beam& b) const {
    band_.zero();
    for (int e : elements_) {
      kernels::VecEl re = kernels::VecEl::Zero();
      kernels::MatEl K = kernels::MatEl::Zero();
      element(ctx, b, e, re, &K);
      band_.add(e, 3, K.data());
    }
  }
  KnotPatches patches_;
  mutable ControlPointBand band_;
};

/// An effect integrated element by element over one ANCF cable: two nodes, the 12 x 12 block
/// of their coordinates.
class AncfElementEffect : public ElementEffect<2, kernels::ancf::kElDofs> {
 public:
  AncfElementEffect(const Model& m, const EffectParams& p, const std::string& who)
      : ElementEffect(ancf_beam_param(m, p, who), m) {}

 protected:
  /// Global indices of element e's 12 coordinates: the 6 of node e, then the 6 of node e+1 (not
  /// contiguous when extras are anchored at node e: DofMap slots).
  Dofs element_dofs(const DofMap& map, const Beam& b, int e) const override {
    Dofs d{};
    for (int a = 0; a < 2; ++a)
      for (int k = 0; k < kernels::ancf::kNodeDofs; ++k)
        d[static_cast<size_t>(kernels::ancf::kNodeDofs * a + k)] = map.q(b.first_cp() + e + a, k);
    return d;
  }
  static kernels::ancf::ElVec gather(const LocalValues& x, const DofMap& map, const Beam& b, int e) {
    kernels::ancf::ElVec q;
    for (int a = 0; a < 2; ++a)
      q.segment<kernels::ancf::kNodeDofs>(kernels::ancf::kNodeDofs * a) =
          Eigen::Map<const Eigen::Matrix<double, kernels::ancf::kNodeDofs, 1>>(x.cp(map, b.first_cp() + e + a));
    return q;
  }
  static void scatter(const LocalValues& r, const DofMap& map, const Beam& b, int e, const kernels::ancf::ElVec& v) {
    for (int a = 0; a < 2; ++a)
      Eigen::Map<Eigen::Matrix<double, kernels::ancf::kNodeDofs, 1>>(r.cp(map, b.first_cp() + e + a)) +=
          v.segment<kernels::ancf::kNodeDofs>(kernels::ancf::kNodeDofs * a);
  }
};

/// A quadrature point on a beam's centre line: weight (reference arc length) and the W basis
/// weights of the position x = sum_i N_i y_i and its derivative x' = sum_i dN_i y_i (y_i: 3-blocks).
template <int W>
struct CentreLinePoint {
  double w = 0.0;
  std::array<double, W> N{}, dN{};
};

/// The mass quadrature points of a beam's span (3) or ANCF element (5) ...
inline int centre_line_points(const Beam& b) { return b.is_ancf() ? kernels::ancf::kAxialPoints : 3; }

/// ... and point g of span or element e: its weight and the W shape functions of its position
/// blocks (W = 3 a director span's phi, W = 4 an ANCF element's r and r').
template <int W>
CentreLinePoint<W> centre_line_point(const Beam& b, int e, int g) {
  CentreLinePoint<W> p;
  if constexpr (W == 3) {
    const kernels::GaussPoint& gp = b.gp_full(e, g);
    p.w = gp.w;
    p.N = gp.N;
    p.dN = gp.dN;
  } else {
    const kernels::ancf::AxialPoint& ap = b.ancf_element(e).axial[static_cast<size_t>(g)];
    p.w = ap.w;
    p.N = ap.S;
    p.dN = ap.dS;
  }
  return p;
}

/// An effect on the centre line of one beam, element by element, at the mass quadrature points
/// (3 per span, 5 per ANCF element): drag, contact. W = 3: a director beam's quadratic span (the
/// phi blocks of its 3 control points); W = 4: an ANCF element (r and r' of its 2 nodes, cubic
/// Hermite).
template <int W>
class CentreLineEffect : public ElementEffect<W == 3 ? 3 : 2, 3 * W> {
 protected:
  static constexpr int kDofs = 3 * W;
  using Base = ElementEffect<W == 3 ? 3 : 2, 3 * W>;
  using VecY = Eigen::Matrix<double, kDofs, 1>;
  using MatY = Eigen::Matrix<double, kDofs, kDofs, Eigen::RowMajor>;
  using Base::Base;

 public:
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!acts(ctx)) PetscFunctionReturn(0);
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      VecY re = VecY::Zero();
      element(ctx, b, e, re, nullptr);
      scatter(ctx, r, b, e, re);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!acts(ctx)) PetscFunctionReturn(0);
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      VecY re = VecY::Zero();
      MatY K = MatY::Zero();
      element(ctx, b, e, re, &K);
      const auto d = element_dofs(ctx.map, b, e);
      PetscCall(J.add(kDofs, d.data(), kDofs, d.data(), K.data()));
    }
    PetscFunctionReturn(0);
  }

 protected:
  /// Whether the term acts in this evaluation at all (drag: only within a step, where there is a rate).
  virtual bool acts(const EvalContext&) const { return true; }
  /// r += element e's generalised force with the sign of a residual (-int N^T f), and K (if
  /// given) += its derivative with respect to the step's end state.
  virtual void element(const EvalContext& ctx, const Beam& b, int e, VecY& r, MatY* K) const = 0;

  typename Base::Dofs element_dofs(const DofMap& map, const Beam& b, int e) const override {
    typename Base::Dofs d{};
    for (int i = 0; i < W; ++i)
      for (int k = 0; k < 3; ++k) d[static_cast<size_t>(3 * i + k)] = map.q(b.first_cp() + e + node(i), offset(i) + k);
    return d;
  }
  /// The element's W position blocks of x.
  VecY gather(const EvalContext& ctx, const LocalValues& x, const Beam& b, int e) const {
    VecY y;
    for (int i = 0; i < W; ++i)
      y.template segment<3>(3 * i) = Eigen::Map<const Eigen::Vector3d>(x.cp(ctx.map, b.first_cp() + e + node(i)) + offset(i));
    return y;
  }
  void scatter(const EvalContext& ctx, const LocalValues& r, const Beam& b, int e, const VecY& v) const {
    for (int i = 0; i < W; ++i)
      Eigen::Map<Eigen::Vector3d>(r.cp(ctx.map, b.first_cp() + e + node(i)) + offset(i)) += v.template segment<3>(3 * i);
  }
  static int n_points(const Beam& b) { return centre_line_points(b); }
  static CentreLinePoint<W> point(const Beam& b, int e, int g) { return centre_line_point<W>(b, e, g); }
  /// The centre line's position and tangent x' at point q of an element in state y (gather).
  static Eigen::Vector3d position(const CentreLinePoint<W>& q, const VecY& y) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int i = 0; i < W; ++i) x += q.N[static_cast<size_t>(i)] * y.template segment<3>(3 * i);
    return x;
  }
  static Eigen::Vector3d tangent(const CentreLinePoint<W>& q, const VecY& y) {
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    for (int i = 0; i < W; ++i) t += q.dN[static_cast<size_t>(i)] * y.template segment<3>(3 * i);
    return t;
  }

 private:
  // block i of the element: director, the phi of control point i; ANCF, r (even i) or r' (odd i)
  // of node i / 2
  static int node(int i) { return W == 3 ? i : i / 2; }
  static int offset(int i) { return W == 3 ? 0 : 3 * (i % 2); }
};

/// The factory of a CentreLineEffect E<W>(beam, model, params) on the entry's beam: E<4> on an
/// ANCF cable, E<3> on a director beam.
template <template <int> class E>
std::unique_ptr<Effect> make_centre_line_effect(const Model& m, const EffectParams& p) {
  const int beam = beam_param(m, p);
  if (m.beam(beam).is_ancf()) return std::make_unique<E<4>>(beam, m, p);
  return std::make_unique<E<3>>(beam, m, p);
}

}  // namespace slidebeam::effects
