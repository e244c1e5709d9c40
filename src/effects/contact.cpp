// SPDX-License-Identifier: MIT
/// @file Contact of a beam with a fixed rigid shape (scene table [[contact]]): a plane (the ground,
/// a seabed, a slope; type = "plane"), a cylinder (a drum, a sheave, a pipe, a bollard) or a
/// sphere (a boulder, a ball), touched from outside, frictionless.
///
/// A penalty potential per unit length of the beam, checked at the mass quadrature points (3 per
/// span, 5 per ANCF element):
///   V = 1/2 k <-g>^2,   <-g> = max(-g, 0),
/// g the centre line's distance from the shape's surface (gap_potential.hpp): n . (x - p) for the
/// plane of unit normal n (pointing to the free side) through p, |P (x - c)| - R for the cylinder
/// and the sphere (R: where the centre line touches, the shape's radius plus the rope's), k the
/// bed's stiffness (force per unit length of beam per unit of penetration). The beam sinks w / k
/// into the bed under a line weight w, a rope of tension T wrapped on a drum T / (R k): the
/// stiffer, the closer to a rigid body, at the price of a stiffer step.
///
/// Energy: V is part of H (potential). Under energy-momentum each point's force is the discrete
/// gradient of V along its gap (gap_potential.hpp), so the contact's work over a step is exactly
/// V(g1) - V(g0): energy is conserved through touch-down and lift-off without locating them.
/// A fixed shape takes momentum from the beam, as a support does. A sphere may instead be carried
/// by a rigid body (a boulder, a ball: centred on the body's centre of mass): the gap is then that
/// of x - phi, the force on the beam's point goes back onto the body, and since its discrete
/// gradient is parallel to the mid-step x - phi, energy-momentum keeps the linear and angular
/// momentum of beam and body exactly too.

#include "effects/gap_potential.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <string>

namespace slidebeam::effects {

namespace {
/// The bed: V = 1/2 k <-g>^2.
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

Penalty bed(const EffectParams& p) {
  Penalty law;
  law.k = p.number("stiffness");
  if (!(law.k > 0.0)) throw ParamError("stiffness", "the bed's stiffness must be > 0");
  return law;
}

Eigen::Vector3d unit(const EffectParams& p, const char* key, const std::string& what) {
  const Eigen::Vector3d n = vector3_param(p, key);
  if (!(n.norm() > 0.0) || !n.allFinite()) throw ParamError(key, what + " must be a nonzero vector");
  return n.normalized();
}

double radius(const EffectParams& p) {
  const double R = p.number("radius");
  if (!(R > 0.0)) throw ParamError("radius", "the radius must be > 0");
  return R;
}

PlaneGap plane(const EffectParams& p) { return {unit(p, "normal", "the plane's normal"), vector3_param(p, "point")}; }

RoundGap cylinder(const EffectParams& p) {
  const Eigen::Vector3d a = unit(p, "axis", "the cylinder's axis");
  return {vector3_param(p, "point"), Eigen::Matrix3d::Identity() - a * a.transpose(), radius(p)};
}

RoundGap sphere(const EffectParams& p) { return {vector3_param(p, "center"), Eigen::Matrix3d::Identity(), radius(p)}; }

/// Contact of one beam with a shape.
template <int W, class Shape>
class Contact final : public GapPotential<W, Penalty, Shape> {
 public:
  Contact(int beam, const Model& m, const EffectParams& p, const char* type, const Shape& shape)
      : GapPotential<W, Penalty, Shape>(beam, m, shape, bed(p)), type_(type) {}
  std::string type() const override { return type_; }

 private:
  std::string type_;
};

template <class Shape>
std::unique_ptr<Effect> make_contact(const Model& m, const EffectParams& p, const char* type,
                                     Shape (*shape)(const EffectParams&)) {
  const int beam = beam_param(m, p);
  if (m.beam(beam).is_ancf()) return std::make_unique<Contact<4, Shape>>(beam, m, p, type, shape(p));
  return std::make_unique<Contact<3, Shape>>(beam, m, p, type, shape(p));
}

/// Contact of one beam with a sphere of radius R centred on a body's centre of mass phi: the
/// penalty of the gap |x - phi| - R at the beam's mass quadrature points, each element coupled
/// with the body's phi.
template <int W>
class BodySphereContact final : public Effect {
  static constexpr int kDofs = 3 * W + 3;  // the element's position blocks, then the body's phi
  using Point = CentreLinePoint<W>;
  using VecY = Eigen::Matrix<double, kDofs, 1>;
  using MatY = Eigen::Matrix<double, kDofs, kDofs, Eigen::RowMajor>;

 public:
  BodySphereContact(int beam, int body, const Model& m, const EffectParams& p)
      : beam_(beam), body_(body), law_(bed(p)), sphere_{Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), radius(p)} {
    if (!m.beam(body_).is_rigid())
      throw ParamError("body", "'" + m.beam(body_).name() + "' is a beam: a sphere is carried by a [[body]]");
    label_ = "sphere_contact[" + m.beam(beam_).name() + "-" + m.beam(body_).name() + "]";
  }
  std::string type() const override { return "sphere_contact"; }
  std::string label() const override { return label_; }

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
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    for (int e : elements_) {
      VecY re = VecY::Zero();
      element(ctx, e, re, nullptr);
      const auto d = dofs(ctx.map, ctx.model, e);
      for (int k = 0; k < kDofs; ++k) r.at(d[static_cast<size_t>(k)]) += re(k);
    }
    PetscFunctionReturn(0);
  }
  /// Only the spans near the sphere: the others' blocks are zero, and adding them would couple
  /// the body's centre with every span of the beam, a dense row in every factorisation (on
  /// runs/multibody/rockfall_net.toml's first 0.3 s the linear solves took 3.9 s with it, 2.9 s
  /// without). The assembled pattern then follows the contact (the solvers set their
  /// factorisation up anew when it changes); the preallocated one (pattern()) holds them all.
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    for (int e : elements_) {
      if (!near(ctx, e)) continue;
      VecY re = VecY::Zero();
      MatY K = MatY::Zero();
      element(ctx, e, re, &K);
      const auto d = dofs(ctx.map, ctx.model, e);
      PetscCall(J.add(kDofs, d.data(), kDofs, d.data(), K.data()));
    }
    PetscFunctionReturn(0);
  }
  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(beam_);
    double U = 0.0;
    for (int e : elements_) {
      const VecY y = gather(ctx, ctx.x, e);
      for (int g = 0; g < n_points(b); ++g) {
        const Point q = point(b, e, g);
        U += q.w * law_.V(sphere_.gap(relative(q, y)));
      }
    }
    return U;
  }

 private:
  /// re += the element's generalised force (residual sign) on its blocks and on phi, K += its
  /// derivative with respect to the step's end state: each point's force f on x is -f on phi.
  void element(const EvalContext& ctx, int e, VecY& re, MatY* K) const {
    const Beam& b = ctx.model.beam(beam_);
    const bool em = ctx.rule == StepRule::EnergyMomentum;
    const VecY y1 = gather(ctx, ctx.x, e), yf = gather(ctx, em ? ctx.x_old : ctx.xf, e);
    for (int g = 0; g < n_points(b); ++g) {
      const Point q = point(b, e, g);
      Eigen::Vector3d force;
      Eigen::Matrix3d stiffness;
      if (!gap_force(law_, sphere_, ctx, relative(q, yf), relative(q, y1), K != nullptr, force, stiffness)) continue;
      // z = sum_i N_i x_i - phi: the weights of the blocks, the body's last
      std::array<double, W + 1> c{};
      for (int i = 0; i < W; ++i) c[static_cast<size_t>(i)] = q.N[static_cast<size_t>(i)];
      c[W] = -1.0;
      for (int i = 0; i <= W; ++i) re.template segment<3>(3 * i) += q.w * c[static_cast<size_t>(i)] * force;
      if (!K) continue;
      for (int i = 0; i <= W; ++i)
        for (int j = 0; j <= W; ++j)
          K->template block<3, 3>(3 * i, 3 * j) += q.w * c[static_cast<size_t>(i)] * c[static_cast<size_t>(j)] * stiffness;
    }
  }
  /// Whether a point of span e is within half the radius of the sphere's surface at the step's
  /// end or force state (a margin, so that the pattern changes less often than the contact).
  bool near(const EvalContext& ctx, int e) const {
    const Beam& b = ctx.model.beam(beam_);
    const VecY y1 = gather(ctx, ctx.x, e), yf = gather(ctx, ctx.rule == StepRule::EnergyMomentum ? ctx.x_old : ctx.xf, e);
    for (int g = 0; g < n_points(b); ++g) {
      const Point q = point(b, e, g);
      if (std::min(sphere_.gap(relative(q, y1)), sphere_.gap(relative(q, yf))) < 0.5 * sphere_.R) return true;
    }
    return false;
  }
  static int n_points(const Beam& b) { return centre_line_points(b); }
  static Point point(const Beam& b, int e, int g) { return centre_line_point<W>(b, e, g); }
  // block i < W of the element: director, the phi of control point i; ANCF, r (even i) or r'
  // (odd i) of node i / 2; block W: the body's phi
  static int node(int i) { return W == 3 ? i : i / 2; }
  static int offset(int i) { return W == 3 ? 0 : 3 * (i % 2); }
  std::array<PetscInt, kDofs> dofs(const DofMap& map, const Model& m, int e) const {
    std::array<PetscInt, kDofs> d{};
    const PetscInt first = m.beam(beam_).first_cp(), body = m.beam(body_).first_cp();
    for (int i = 0; i < W; ++i)
      for (int k = 0; k < 3; ++k) d[static_cast<size_t>(3 * i + k)] = map.q(first + e + node(i), offset(i) + k);
    for (int k = 0; k < 3; ++k) d[static_cast<size_t>(3 * W + k)] = map.q(body, k);
    return d;
  }
  VecY gather(const EvalContext& ctx, const LocalValues& x, int e) const {
    VecY y;
    const PetscInt first = ctx.model.beam(beam_).first_cp();
    for (int i = 0; i < W; ++i)
      y.template segment<3>(3 * i) = Eigen::Map<const Eigen::Vector3d>(x.cp(ctx.map, first + e + node(i)) + offset(i));
    y.template segment<3>(3 * W) = Eigen::Map<const Eigen::Vector3d>(x.cp(ctx.map, ctx.model.beam(body_).first_cp()));
    return y;
  }
  /// The point's position relative to the sphere's centre.
  static Eigen::Vector3d relative(const Point& q, const VecY& y) {
    Eigen::Vector3d z = -y.template segment<3>(3 * W);
    for (int i = 0; i < W; ++i) z += q.N[static_cast<size_t>(i)] * y.template segment<3>(3 * i);
    return z;
  }

  int beam_, body_;
  Penalty law_;
  RoundGap sphere_;  ///< centred at 0: its gap is taken of x - phi
  std::string label_;
  std::vector<int> elements_;
};

std::unique_ptr<Effect> make_sphere_contact(const Model& m, const EffectParams& p) {
  const bool on_body = p.num.count("body") > 0, fixed = p.vec.count("center") > 0;
  if (on_body == fixed)
    throw ParamError(on_body ? "center" : "body",
                     "a sphere has either a fixed `center` or a `body` that carries it (centred on its centre of "
                     "mass), not both");
  if (!on_body) return make_contact(m, p, "sphere_contact", &sphere);
  const int beam = beam_param(m, p), body = static_cast<int>(p.number("body"));
  if (body < 0 || body >= static_cast<int>(m.beams().size()))
    throw std::invalid_argument("sphere_contact: no body with index " + std::to_string(body));
  if (m.beam(beam).is_ancf()) return std::make_unique<BodySphereContact<4>>(beam, body, m, p);
  return std::make_unique<BodySphereContact<3>>(beam, body, m, p);
}

}  // namespace

void register_contact_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const double inf = std::numeric_limits<double>::infinity();
  const ParamSpec beam{"beam", K::Beam, "", "the beam that touches it (director beam or ANCF cable)", ""};
  const ParamSpec stiffness{"stiffness", K::Number, "N/m^2",
                            "k, the bed's stiffness: force per unit length of beam per unit of penetration (a line "
                            "weight w sinks w / k into it, a rope of tension T on a radius R sinks T / (R k))",
                            "", 0.0, inf, true};
  const ParamSpec radius{"radius", K::Number, "m",
                         "R, where the centre line touches: the shape's radius plus the rope's", "", 0.0, inf, true};
  const auto spec = [](const char* type, const char* variant, const char* meaning, std::vector<ParamSpec> params) {
    return table_effect_spec(type, "contact", variant, EnergyRole::Stored, meaning, std::move(params), "potential");
  };
  r.add(spec("plane_contact", "plane",
                     "contact of a beam with a rigid plane (the ground, a seabed, a slope): a penalty 1/2 k <-g>^2 "
                     "per unit length, g the distance of the centre line from the plane, checked at the mass "
                     "quadrature points",
                     {beam,
                      {"point", K::Vector, "m", "a point of the plane", "", -inf, inf, false, 3},
                      {"normal", K::Vector, "",
                       "the plane's normal, towards the side the beam is on (e.g. [0, 0, 1] for the ground)", "",
                       -inf, inf, false, 3},
                      stiffness}),
        [](const Model& m, const EffectParams& p) { return make_contact(m, p, "plane_contact", &plane); });
  r.add(spec("cylinder_contact", "cylinder",
                     "contact of a beam with a fixed rigid cylinder from outside (a drum, a sheave, a pipe, a "
                     "bollard; frictionless): a penalty as for the plane",
                     {beam,
                      {"point", K::Vector, "m", "a point of the cylinder's axis", "", -inf, inf, false, 3},
                      {"axis", K::Vector, "", "the axis' direction (the cylinder is endless)", "", -inf, inf, false, 3},
                      radius, stiffness}),
        [](const Model& m, const EffectParams& p) { return make_contact(m, p, "cylinder_contact", &cylinder); });
  r.add(spec("sphere_contact", "sphere",
                     "contact of a beam with a rigid sphere from outside (frictionless), fixed or carried by a body: "
                     "a penalty as for the plane",
                     {beam,
                      optional_param({"center", K::Vector, "m", "the sphere's centre, fixed (or give `body`)", "",
                                      -inf, inf, false, 3}),
                      optional_param({"body", K::Beam, "",
                                      "the [[body]] that carries the sphere, centred on its centre of mass (or give "
                                      "`center`)",
                                      ""}),
                      radius, stiffness}),
        [](const Model& m, const EffectParams& p) { return make_sphere_contact(m, p); });
}

}  // namespace slidebeam::effects
