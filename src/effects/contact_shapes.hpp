// SPDX-License-Identifier: MIT
#pragma once
/// @file The rigid shapes of [[contact]] and the bed's penalty law, built from an entry's
/// parameters: read by the contact (contact.cpp) and by its friction (contact_friction.cpp).

#include "effects/gap_potential.hpp"

#include <array>
#include <memory>
#include <stdexcept>
#include <string>

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
