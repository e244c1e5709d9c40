// SPDX-License-Identifier: MIT
#pragma once
/// @file The rigid shapes of [[contact]] and the bed's penalty law, built from an entry's
/// parameters: read by the contact (contact.cpp) and by its friction (contact_friction.cpp).

#include "effects/gap_potential.hpp"

#include <array>

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

}  // namespace slidebeam::effects
