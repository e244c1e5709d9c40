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
/// The shapes are fixed: the contact takes momentum from the beam, as a support does.

#include "effects/gap_potential.hpp"

#include <Eigen/Dense>

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
                     "contact of a beam with a fixed rigid sphere from outside (frictionless): a penalty as for the "
                     "plane",
                     {beam, {"center", K::Vector, "m", "the sphere's centre", "", -inf, inf, false, 3}, radius,
                      stiffness}),
        [](const Model& m, const EffectParams& p) { return make_contact(m, p, "sphere_contact", &sphere); });
}

}  // namespace slidebeam::effects
