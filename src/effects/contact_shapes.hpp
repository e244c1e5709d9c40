// SPDX-License-Identifier: MIT
#pragma once
/// @file The rigid shapes of [[contact]] and the bed's penalty law, built from an entry's
/// parameters: read by the contact (contact.cpp) and by its friction (contact_friction.cpp).

#include "effects/gap_potential.hpp"

#include <Eigen/Dense>

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace slidebeam::effects {

/// The bed: V = 1/2 k <-g>^2 per unit length of beam.
struct Penalty {
  static constexpr int kBreakpoints = 1;
  double k = 0.0;
  std::array<double, 1> breakpoints() const { return {0.0}; }
  double V(double g) const { return g < 0.0 ? 0.5 * k * g * g : 0.0; }
  double dV(double g) const { return g < 0.0 ? k * g : 0.0; }
  // at g = 0 the contact branch: a beam drawn on the bed starts with the bed's stiffness in its
  // tangent (else the first Newton step lets it fall through as if nothing held it)
  double ddV(double g) const { return g <= 0.0 ? k : 0.0; }
};

inline Penalty bed(const EffectParams& p) {
  Penalty law;
  law.k = p.number("stiffness");
  if (!(law.k > 0.0)) throw ParamError("stiffness", "the bed's stiffness must be > 0");
  return law;
}

inline double contact_radius(const EffectParams& p) {
  const double R = p.number("radius");
  if (!(R > 0.0)) throw ParamError("radius", "the radius must be > 0");
  return R;
}

inline PlaneGap plane_shape(const EffectParams& p) {
  return {unit_vector_param(p, "normal", "the plane's normal"), vector3_param(p, "point")};
}

inline RoundGap cylinder_shape(const EffectParams& p) {
  const Eigen::Vector3d a = unit_vector_param(p, "axis", "the cylinder's axis");
  return {vector3_param(p, "point"), Eigen::Matrix3d::Identity() - a * a.transpose(), contact_radius(p)};
}

inline RoundGap sphere_shape(const EffectParams& p) {
  return {vector3_param(p, "center"), Eigen::Matrix3d::Identity(), contact_radius(p)};
}

/// The spans of one beam coupled with the first kBody coordinates of a rigid body that carries a
/// contact shape (W = 3 a director beam's spans, W = 4 an ANCF cable's elements): the unknowns each
/// element reads (its position blocks, then the body's phi, d1, d2, d3), its pattern and its states.
template <int W, int kBody>
class BeamOnBodyElements : public Effect {
 protected:
  static constexpr int kDofs = 3 * W + kBody;  // the element's position blocks, then the body's
  using Point = CentreLinePoint<W>;
  using VecY = Eigen::Matrix<double, kDofs, 1>;
  using MatY = Eigen::Matrix<double, kDofs, kDofs, Eigen::RowMajor>;
  using Body = Eigen::Matrix<double, kBody, 1>;

  BeamOnBodyElements(int beam, int body) : beam_(beam), body_(body) {}

 public:
  void distribute(const Model& m) override {
    const Beam& b = m.beam(beam_);
    elements_.clear();
    for (int e = 0; e < b.n_spans(); ++e)
      if (owns_span(m, b, e)) elements_.push_back(e);
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    if (elements_.empty()) return;
    const Beam& b = m.beam(beam_);
    for (int e : elements_) add_cp_blocks(m.dof_map(), b.first_cp() + e, W == 3 ? 3 : 2, dofs);
    add_cp_blocks(m.dof_map(), m.beam(body_).first_cp(), 1, dofs);
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    for (int e : elements_) PetscCall(add_block_pattern(sink, dofs(m.dof_map(), m, e)));
    PetscFunctionReturn(0);
  }

 protected:
  static int n_points(const Beam& b) { return centre_line_points(b); }
  static Point point(const Beam& b, int e, int g) { return centre_line_point<W>(b, e, g); }
  static Eigen::Vector3d position(const Point& q, const VecY& y) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int i = 0; i < W; ++i) x += q.N[static_cast<size_t>(i)] * y.template segment<3>(3 * i);
    return x;
  }
  std::array<PetscInt, kDofs> dofs(const DofMap& map, const Model& m, int e) const {
    std::array<PetscInt, kDofs> d{};
    const PetscInt first = m.beam(beam_).first_cp(), body = m.beam(body_).first_cp();
    for (int i = 0; i < W; ++i)
      for (int k = 0; k < 3; ++k) d[static_cast<size_t>(3 * i + k)] = map.q(first + e + node(i), offset(i) + k);
    for (int k = 0; k < kBody; ++k) d[static_cast<size_t>(3 * W + k)] = map.q(body, k);
    return d;
  }
  VecY gather(const EvalContext& ctx, const LocalValues& x, int e) const {
    VecY y;
    const PetscInt first = ctx.model.beam(beam_).first_cp();
    for (int i = 0; i < W; ++i)
      y.template segment<3>(3 * i) = Eigen::Map<const Eigen::Vector3d>(x.cp(ctx.map, first + e + node(i)) + offset(i));
    y.template tail<kBody>() = Eigen::Map<const Body>(x.cp(ctx.map, ctx.model.beam(body_).first_cp()));
    return y;
  }
  /// A point's force on (x, the body's coordinates) and its derivative S (if K): into the
  /// element's re and K, the point's part spread by the shape functions (x = sum_i N_i y_i).
  template <class Force, class Stiffness>
  static void spread(const Point& q, const Force& f, const Stiffness& S, VecY& re, MatY* K) {
    for (int i = 0; i < W; ++i) re.template segment<3>(3 * i) += q.w * q.N[static_cast<size_t>(i)] * f.template head<3>();
    re.template tail<kBody>() += q.w * f.template tail<kBody>();
    if (!K) return;
    for (int i = 0; i < W; ++i) {
      const double Ni = q.w * q.N[static_cast<size_t>(i)];
      for (int j = 0; j < W; ++j)
        K->template block<3, 3>(3 * i, 3 * j) += Ni * q.N[static_cast<size_t>(j)] * S.template topLeftCorner<3, 3>();
      K->template block<3, kBody>(3 * i, 3 * W) += Ni * S.template topRightCorner<3, kBody>();
      K->template block<kBody, 3>(3 * W, 3 * i) += Ni * S.template bottomLeftCorner<kBody, 3>();
    }
    K->template block<kBody, kBody>(3 * W, 3 * W) += q.w * S.template bottomRightCorner<kBody, kBody>();
  }
  /// re (kDofs values, residual sign) into r at element e's unknowns.
  void scatter(const EvalContext& ctx, int e, const VecY& re, const LocalValues& r) const {
    const auto d = dofs(ctx.map, ctx.model, e);
    for (int k = 0; k < kDofs; ++k) r.at(d[static_cast<size_t>(k)]) += re(k);
  }

  int beam_, body_;
  std::vector<int> elements_;

 private:
  // block i < W of the element: director, the phi of control point i; ANCF, r (even i) or r'
  // (odd i) of node i / 2
  static int node(int i) { return W == 3 ? i : i / 2; }
  static int offset(int i) { return W == 3 ? 0 : 3 * (i % 2); }
};

/// A StepHistory of kPerPoint values at every mass quadrature point of a beam (all its spans, on
/// every rank), this rank's own those of the spans it owns: what friction keeps of each point.
template <int kPerPoint>
class PointHistory : public StepHistory {
 public:
  const std::vector<double>& history() const override { return history_; }
  bool owns_history(size_t i) const override { return owned_[i / static_cast<size_t>(points_ * kPerPoint)] != 0; }
  void set_history(const std::vector<double>& values) override { history_ = values; }

 protected:
  /// All 0: nothing kept yet.
  void size_history(int spans, int points) {
    points_ = points;
    history_.assign(static_cast<size_t>(spans * points * kPerPoint), 0.0);
  }
  /// The spans this rank owns (after distribute).
  void own_spans(int spans, const std::vector<int>& elements) {
    owned_.assign(static_cast<size_t>(spans), 0);
    for (int e : elements) owned_[static_cast<size_t>(e)] = 1;
  }
  double* slot(int e, int g) { return history_.data() + static_cast<size_t>((e * points_ + g) * kPerPoint); }
  const double* slot(int e, int g) const {
    return history_.data() + static_cast<size_t>((e * points_ + g) * kPerPoint);
  }
  int points_ = 0;

 private:
  std::vector<double> history_;
  std::vector<char> owned_;  // by span
};

/// The body a contact shape is carried by (its "body" parameter), checked to be a [[body]].
inline int carrier_body(const Model& m, const EffectParams& p, const char* shape) {
  const int body = static_cast<int>(p.number("body"));
  if (body < 0 || body >= static_cast<int>(m.beams().size()))
    throw std::invalid_argument(std::string(shape) + "_contact: no body with index " + std::to_string(body));
  if (!m.beam(body).is_rigid())
    throw ParamError("body", "'" + m.beam(body).name() + "' is a beam: a " + shape + " is carried by a [[body]]");
  return body;
}

/// Effect E<W, Shape> (W = 3 a director beam, 4 an ANCF cable) of the beam of a [[contact]] entry
/// on its fixed shape (the entry's `type`, passed as "shape"), labelled by the entry's "label". A
/// shape carried by a body is refused, naming `key` (what the entry asked of it).
template <template <int, class> class E>
std::unique_ptr<Effect> make_on_fixed_shape(const Model& m, const EffectParams& p, const char* key) {
  if (p.num.count("body"))
    throw ParamError(key, std::string("`") + key + "` on a shape carried by a body is not supported yet: leave it out");
  const int beam = beam_param(m, p);
  const bool ancf = m.beam(beam).is_ancf();
  const std::string shape = p.string("shape"), label = p.string("label");
  auto make = [&](auto build) -> std::unique_ptr<Effect> {
    using Shape = decltype(build(p));
    if (ancf) return std::make_unique<E<4, Shape>>(beam, m, p, label, build(p));
    return std::make_unique<E<3, Shape>>(beam, m, p, label, build(p));
  };
  if (shape == "plane") return make(&plane_shape);
  if (shape == "cylinder") return make(&cylinder_shape);
  if (shape == "sphere") return make(&sphere_shape);
  throw std::invalid_argument("contact: unknown shape '" + shape + "'");
}

}  // namespace slidebeam::effects
