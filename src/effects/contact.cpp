// SPDX-License-Identifier: MIT
/// @file Contact of a beam with a fixed rigid shape (scene table [[contact]]): a plane (the ground,
/// a seabed, a slope; type = "plane"), a cylinder (a drum, a sheave, a pipe, a bollard) or a
/// sphere (a boulder, a ball), touched from outside. Its friction (`mu` > 0) is an effect of its
/// own beside it (contact_friction.cpp).
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
/// A fixed shape takes momentum from the beam, as a support does. A sphere or a cylinder may
/// instead be carried by a rigid body (a boulder; a drum, a sheave: SphereOnBody, CylinderOnBody):
/// the force on the beam's point then goes back onto the body, and energy-momentum keeps the
/// linear and angular momentum of beam and body exactly too.

#include "effects/contact_shapes.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <string>

namespace slidebeam::effects {

namespace {

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

/// A sphere of radius R centred on the body's centre of mass phi: the gap of z = x - phi. The
/// body coordinates it reads: phi.
struct SphereOnBody {
  static constexpr int kBody = 3;
  static constexpr const char* kType = "sphere_contact";
  using Body = Eigen::Matrix<double, kBody, 1>;
  using Force = Eigen::Matrix<double, 3 + kBody, 1>;
  using Stiffness = Eigen::Matrix<double, 3 + kBody, 3 + kBody>;
  RoundGap sphere;  ///< centred at 0

  double radius() const { return sphere.R; }
  double gap(const Eigen::Vector3d& x, const Body& b) const { return sphere.gap(x - b); }
  /// The point's force (d energy / d (x, phi)) and its derivative with respect to the step's end,
  /// from the force state (xf, bf) and the end (x1, b1), as gap_force.
  bool force(const Penalty& law, const EvalContext& ctx, const Eigen::Vector3d& xf, const Body& bf,
             const Eigen::Vector3d& x1, const Body& b1, bool with_K, Force& f, Stiffness& K) const {
    Eigen::Vector3d F;
    Eigen::Matrix3d S;
    if (!gap_force(law, sphere, ctx, xf - bf, x1 - b1, with_K, F, S)) return false;
    f << F, -F;
    if (with_K) K << S, -S, -S, S;
    return true;
  }
};

/// A cylinder of radius R about an axis through the body's centre of mass, fixed in the body (a
/// drum, a sheave: it turns with the body). With D = (d1, d2, d3) the body's axes and u_1, u_2 the
/// body components of two directions perpendicular to the axis, the point's coordinates across
/// the axis are xi_k = (D u_k) . (x - phi), bilinear in the unknowns, and the gap is |xi| - R.
/// Under energy-momentum the force is the discrete gradient of V(|xi| - R): DG_V times
/// c . (Delta xi), c = (xi0 + xi1) / (|xi0| + |xi1|) (the norm's), and the bilinear xi's exact
/// increments (the product rule at the step's middle). The point's force and its moment on the
/// body cancel: energy and both momenta of rope and drum are exact. The body coordinates it reads:
/// phi, d1, d2, d3. Its derivatives come by forward-mode automatic differentiation.
struct CylinderOnBody {
  static constexpr int kBody = 12;
  static constexpr int kVars = 3 + kBody;  // x, phi, d1, d2, d3
  static constexpr const char* kType = "cylinder_contact";
  using Body = Eigen::Matrix<double, kBody, 1>;
  using Force = Eigen::Matrix<double, kVars, 1>;
  using Stiffness = Eigen::Matrix<double, kVars, kVars>;
  using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, kVars, 1>>;
  std::array<Eigen::Vector3d, 2> u;  ///< body components of two directions across the axis
  double R = 0.0;

  double radius() const { return R; }
  template <class T>
  std::array<T, 2> xi(const Eigen::Matrix<T, kVars, 1>& s) const {
    const Eigen::Matrix<T, 3, 1> z = s.template segment<3>(0) - s.template segment<3>(3);
    std::array<T, 2> out;
    for (size_t k = 0; k < 2; ++k) {
      const Eigen::Matrix<T, 3, 1> a = T(u[k](0)) * s.template segment<3>(6) + T(u[k](1)) * s.template segment<3>(9) +
                                       T(u[k](2)) * s.template segment<3>(12);
      out[k] = a.dot(z);
    }
    return out;
  }
  static Eigen::Matrix<double, kVars, 1> stack(const Eigen::Vector3d& x, const Body& b) {
    Eigen::Matrix<double, kVars, 1> s;
    s << x, b;
    return s;
  }
  static Eigen::Matrix<AD, kVars, 1> active(const Eigen::Matrix<double, kVars, 1>& s) {
    Eigen::Matrix<AD, kVars, 1> a;
    for (int i = 0; i < kVars; ++i) a(i) = AD(s(i), kVars, i);
    return a;
  }
  double gap(const Eigen::Vector3d& x, const Body& b) const {
    const auto e = xi(stack(x, b));
    return std::hypot(e[0], e[1]) - R;
  }
  /// d g / d s at a state (AD): the gradient of |xi| - R.
  Eigen::Matrix<AD, kVars, 1> gradient(const Eigen::Matrix<AD, kVars, 1>& s, const std::array<AD, 2>& c) const {
    // d xi_k / d x = D u_k = -d xi_k / d phi; d xi_k / d d_i = u_k(i) z
    Eigen::Matrix<AD, kVars, 1> w;
    const Eigen::Matrix<AD, 3, 1> z = s.template segment<3>(0) - s.template segment<3>(3);
    Eigen::Matrix<AD, 3, 1> wz = Eigen::Matrix<AD, 3, 1>::Zero();
    for (size_t k = 0; k < 2; ++k)
      wz += c[k] * (AD(u[k](0)) * s.template segment<3>(6) + AD(u[k](1)) * s.template segment<3>(9) +
                    AD(u[k](2)) * s.template segment<3>(12));
    w.template segment<3>(0) = wz;
    w.template segment<3>(3) = -wz;
    for (int i = 0; i < 3; ++i)
      w.template segment<3>(6 + 3 * i) = (c[0] * AD(u[0](i)) + c[1] * AD(u[1](i))) * z;
    return w;
  }
  bool force(const Penalty& law, const EvalContext& ctx, const Eigen::Vector3d& xf, const Body& bf,
             const Eigen::Vector3d& x1, const Body& b1, bool with_K, Force& f, Stiffness& K) const {
    Eigen::Matrix<AD, kVars, 1> w;
    AD scale;
    if (ctx.rule == StepRule::EnergyMomentum) {  // xf: the step's start; active: the end
      const auto s0 = stack(xf, bf);
      const Eigen::Matrix<AD, kVars, 1> s1 = active(stack(x1, b1));
      const auto xi0 = xi(s0);
      const auto xi1 = xi(s1);
      const double r0 = std::hypot(xi0[0], xi0[1]);
      const AD r1 = sqrt(xi1[0] * xi1[0] + xi1[1] * xi1[1]);
      const auto [dg, ddg] = gap_discrete_gradient(law, r0 - R, r1.value() - R);
      if (dg == 0.0 && ddg == 0.0) return false;
      scale = AD(dg, ddg * r1.derivatives());
      const std::array<AD, 2> c = {(AD(xi0[0]) + xi1[0]) / (AD(r0) + r1), (AD(xi0[1]) + xi1[1]) / (AD(r0) + r1)};
      Eigen::Matrix<AD, kVars, 1> mid;
      for (int i = 0; i < kVars; ++i) mid(i) = 0.5 * (AD(s0(i)) + s1(i));
      w = gradient(mid, c);  // the bilinear xi's exact increment: its gradient at the middle
    } else {  // the force state is active; d/d(end) = theta d/d(force state)
      const Eigen::Matrix<AD, kVars, 1> s = active(stack(xf, bf));
      const auto e = xi(s);
      const AD r = sqrt(e[0] * e[0] + e[1] * e[1]);
      const double g = r.value() - R, dv = law.dV(g), ddv = law.ddV(g);
      if (dv == 0.0 && ddv == 0.0) return false;
      scale = AD(dv, ddv * r.derivatives());
      w = gradient(s, {e[0] / r, e[1] / r});
    }
    for (int i = 0; i < kVars; ++i) {
      const AD fi = scale * w(i);
      f(i) = fi.value();
      if (with_K) K.row(i) = (ctx.rule == StepRule::EnergyMomentum ? 1.0 : ctx.theta) * fi.derivatives().transpose();
    }
    return true;
  }
};

/// Contact of one beam with a shape carried by a rigid body (Kernel: SphereOnBody,
/// CylinderOnBody): a penalty of the point's gap at the beam's mass quadrature points, each
/// element coupled with the body coordinates the shape reads.
template <int W, class Kernel>
class BodyContact final : public BeamOnBodyElements<W, Kernel::kBody> {
  using Base = BeamOnBodyElements<W, Kernel::kBody>;
  static constexpr int kBody = Kernel::kBody;
  static constexpr int kDofs = Base::kDofs;
  using typename Base::Point;
  using typename Base::VecY;
  using typename Base::MatY;
  using Body = typename Kernel::Body;

 public:
  BodyContact(int beam, int body, const Model& m, const EffectParams& p, const Kernel& kernel)
      : Base(beam, body), law_(bed(p)), kernel_(kernel) {
    label_ = std::string(Kernel::kType) + "[" + m.beam(beam).name() + "-" + m.beam(body).name() + "]";
  }
  std::string type() const override { return Kernel::kType; }
  std::string label() const override { return label_; }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    for (int e : this->elements_) {
      VecY re = VecY::Zero();
      const auto [y1, yf] = states(ctx, e);
      element(ctx, e, y1, yf, re, nullptr);
      this->scatter(ctx, e, re, r);
    }
    PetscFunctionReturn(0);
  }
  /// Only the spans near the shape: the others' blocks are zero, and adding them would couple
  /// the body with every span of the beam, a dense row in every factorisation (on
  /// runs/multibody/rockfall_net.toml's first 0.3 s the linear solves took 3.9 s with it, 2.9 s
  /// without). The assembled pattern then follows the contact (the solvers set their
  /// factorisation up anew when it changes); the preallocated one (pattern()) holds them all.
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    for (int e : this->elements_) {
      const auto [y1, yf] = states(ctx, e);
      if (!near(ctx, e, y1, yf)) continue;
      VecY re = VecY::Zero();
      MatY K = MatY::Zero();
      element(ctx, e, y1, yf, re, &K);
      const auto d = this->dofs(ctx.map, ctx.model, e);
      PetscCall(J.add(kDofs, d.data(), kDofs, d.data(), K.data()));
    }
    PetscFunctionReturn(0);
  }
  double energy(const EvalContext& ctx) const override {
    const Beam& b = ctx.model.beam(this->beam_);
    double U = 0.0;
    for (int e : this->elements_) {
      const VecY y = this->gather(ctx, ctx.x, e);
      for (int g = 0; g < Base::n_points(b); ++g) {
        const Point q = Base::point(b, e, g);
        U += q.w * law_.V(kernel_.gap(Base::position(q, y), y.template tail<kBody>()));
      }
    }
    return U;
  }

 private:
  /// Span e's unknowns (its blocks, then the body's) at the step's end and at its force state
  /// (the step's start under energy-momentum).
  std::pair<VecY, VecY> states(const EvalContext& ctx, int e) const {
    return {this->gather(ctx, ctx.x, e), this->gather(ctx, ctx.rule == StepRule::EnergyMomentum ? ctx.x_old : ctx.xf, e)};
  }
  /// re += span e's generalised force (residual sign) on its blocks and on the body's
  /// coordinates, K += its derivative with respect to the step's end state.
  void element(const EvalContext& ctx, int e, const VecY& y1, const VecY& yf, VecY& re, MatY* K) const {
    const Beam& b = ctx.model.beam(this->beam_);
    const Body b1 = y1.template tail<kBody>(), bf = yf.template tail<kBody>();
    for (int g = 0; g < Base::n_points(b); ++g) {
      const Point q = Base::point(b, e, g);
      typename Kernel::Force f;
      typename Kernel::Stiffness S;
      if (!kernel_.force(law_, ctx, Base::position(q, yf), bf, Base::position(q, y1), b1, K != nullptr, f, S)) continue;
      Base::spread(q, f, S, re, K);
    }
  }
  /// Whether a point of span e is within half the shape's radius of its surface at the step's
  /// end or force state (a margin, so that the pattern changes less often than the contact).
  bool near(const EvalContext& ctx, int e, const VecY& y1, const VecY& yf) const {
    const Beam& b = ctx.model.beam(this->beam_);
    for (int g = 0; g < Base::n_points(b); ++g) {
      const Point q = Base::point(b, e, g);
      const double gap = std::min(kernel_.gap(Base::position(q, y1), y1.template tail<kBody>()),
                                  kernel_.gap(Base::position(q, yf), yf.template tail<kBody>()));
      if (gap < 0.5 * kernel_.radius()) return true;
    }
    return false;
  }

  Penalty law_;
  Kernel kernel_;
  std::string label_;
};

template <class Kernel>
std::unique_ptr<Effect> make_body_contact(const Model& m, const EffectParams& p, int body, const Kernel& kernel) {
  const int beam = beam_param(m, p);
  if (m.beam(beam).is_ancf()) return std::make_unique<BodyContact<4, Kernel>>(beam, body, m, p, kernel);
  return std::make_unique<BodyContact<3, Kernel>>(beam, body, m, p, kernel);
}

/// Fixed (`center`, `point`) or carried by a body (`body`): which one the entry says.
bool on_body(const EffectParams& p, const char* fixed_key) {
  const bool carried = p.num.count("body") > 0, fixed = p.vec.count(fixed_key) > 0;
  if (carried == fixed)
    throw ParamError(carried ? fixed_key : "body",
                     std::string("give either a fixed `") + fixed_key + "` or the `body` that carries the shape "
                     "(through its centre of mass), not both");
  return carried;
}

std::unique_ptr<Effect> make_sphere_contact(const Model& m, const EffectParams& p) {
  if (!on_body(p, "center")) return make_contact(m, p, "sphere_contact", &sphere_shape);
  SphereOnBody k{{Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), contact_radius(p)}};
  return make_body_contact(m, p, carrier_body(m, p, "sphere"), k);
}

std::unique_ptr<Effect> make_cylinder_contact(const Model& m, const EffectParams& p) {
  if (!on_body(p, "point")) return make_contact(m, p, "cylinder_contact", &cylinder_shape);
  const int body = carrier_body(m, p, "cylinder");
  // the axis drawn in space, in the body's components
  const Beam& B = m.beam(body);
  Eigen::Matrix3d D;
  for (int i = 0; i < 3; ++i) D.col(i) = Eigen::Map<const Eigen::Vector3d>(B.q_ref().data() + 3 + 3 * i);
  const Eigen::Vector3d axis = D.transpose() * unit_vector_param(p, "axis", "the cylinder's axis");
  const auto [across, across_too] = perpendicular_pair(axis);
  CylinderOnBody k;
  k.u = {across, across_too};
  k.R = contact_radius(p);
  return make_body_contact(m, p, body, k);
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
  const ParamSpec mu{"mu", K::Number, "",
                     "Coulomb friction coefficient between beam and shape (0: frictionless; a fixed shape, or a "
                     "cylinder carried by a body): a point sticks while its tangential load is below mu N",
                     "0", 0.0, inf};
  const ParamSpec mu_axial = optional_param(
      {"mu_axial", K::Number, "",
       "friction coefficient along the beam, if it differs from across it (a chain on the seabed: MoorDyn's "
       "axial seabed friction); default mu",
       "", 0.0, inf, true});
  const ParamSpec mu_transverse = optional_param(
      {"mu_transverse", K::Number, "", "friction coefficient across the beam (default mu)", "", 0.0, inf, true});
  const ParamSpec damping{"damping", K::Number, "N s/m^2",
                          "c, the bed's damping of the beam's normal motion in contact, per unit length (0: none; a "
                          "fixed shape only): c = 2 zeta sqrt(k rho A) damps the beam's bounce on the bed by the ratio "
                          "zeta",
                          "0", 0.0, inf};
  const ParamSpec damping_depth = optional_param(
      {"damping_depth", K::Number, "m",
       "d, the penetration over which the bed's damping grows from nothing to c, so that the damping force is "
       "continuous at touch-down (default: the sinkage of the beam's own weight in standard gravity, rho A g0 / k)",
       "", 0.0, inf, true});
  const ParamSpec tangential_stiffness = optional_param(
      {"tangential_stiffness", K::Number, "N/m^2",
       "k_t, the stiffness that holds a sticking point to its anchor, per unit length (default: the bed's "
       "stiffness): a point sticks within mu N / k_t of where it stuck",
       "", 0.0, inf, true});
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
                      stiffness, mu, mu_axial, mu_transverse, tangential_stiffness, damping, damping_depth}),
        [](const Model& m, const EffectParams& p) { return make_contact(m, p, "plane_contact", &plane_shape); });
  r.add(spec("cylinder_contact", "cylinder",
                     "contact of a beam with a fixed rigid cylinder from outside (a drum, a sheave, a pipe, a "
                     "bollard): a penalty as for the plane",
                     {beam,
                      optional_param({"point", K::Vector, "m", "a point of the cylinder's axis, fixed (or give `body`)",
                                      "", -inf, inf, false, 3}),
                      optional_param({"body", K::Beam, "",
                                      "the [[body]] that carries the cylinder, its axis through the body's centre of "
                                      "mass, turning with it (a drum, a sheave; or give `point`)",
                                      ""}),
                      {"axis", K::Vector, "", "the axis' direction as drawn (the cylinder is endless)", "", -inf, inf,
                       false, 3},
                      radius, stiffness, mu, mu_axial, mu_transverse, tangential_stiffness, damping, damping_depth}),
        [](const Model& m, const EffectParams& p) { return make_cylinder_contact(m, p); });
  r.add(spec("sphere_contact", "sphere",
                     "contact of a beam with a rigid sphere from outside, fixed or carried by a body: "
                     "a penalty as for the plane",
                     {beam,
                      optional_param({"center", K::Vector, "m", "the sphere's centre, fixed (or give `body`)", "",
                                      -inf, inf, false, 3}),
                      optional_param({"body", K::Beam, "",
                                      "the [[body]] that carries the sphere, centred on its centre of mass (or give "
                                      "`center`)",
                                      ""}),
                      radius, stiffness, mu, mu_axial, mu_transverse, tangential_stiffness, damping, damping_depth}),
        [](const Model& m, const EffectParams& p) { return make_sphere_contact(m, p); });
}

}  // namespace slidebeam::effects
