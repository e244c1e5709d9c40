// SPDX-License-Identifier: MIT
/// @file Contact of a beam with a rigid plane (scene table [[contact]], type = "plane"): the
/// ground, a seabed, a slope.
///
/// A penalty potential per unit length of the beam, checked at the mass quadrature points (3 per
/// span, 5 per ANCF element):
///   V = 1/2 k <-g>^2,   g = n . (x - p),   <-g> = max(-g, 0),
/// n the plane's unit normal (pointing to the free side), p a point of it, k the bed's stiffness
/// (force per unit length of beam per unit of penetration). The beam sinks w / k into the bed
/// under a line weight w: the stiffer, the closer to a rigid bed, at the price of a stiffer step.
///
/// Energy: V is part of H (potential). Under energy-momentum each point's force is the discrete
/// gradient of V along its gap (gap_potential.hpp), so the contact's work over a step is exactly
/// V(g1) - V(g0): energy is conserved through touch-down and lift-off without locating them.
/// The plane is fixed: the contact takes linear momentum along n (and the angular momentum about
/// axes not parallel to n), as a support does.

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

Eigen::Vector3d vector_param(const EffectParams& p, const char* key) {
  const auto& v = p.vector(key, 3);
  return {v[0], v[1], v[2]};
}

Eigen::Vector3d plane_normal(const EffectParams& p) {
  const Eigen::Vector3d n = vector_param(p, "normal");
  if (!(n.norm() > 0.0) || !n.allFinite()) throw ParamError("normal", "the plane's normal must be a nonzero vector");
  return n;
}
}  // namespace

/// The plane's contact on one beam.
template <int W>
class PlaneContact final : public GapPotential<W, Penalty> {
 public:
  PlaneContact(int beam, const Model& m, const EffectParams& p)
      : GapPotential<W, Penalty>(beam, m, plane_normal(p), vector_param(p, "point"), bed(p)) {}
  std::string type() const override { return "plane_contact"; }
};

void register_contact_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const double inf = std::numeric_limits<double>::infinity();
  EffectSpec s;
  s.type = "plane_contact";
  s.table = "contact";
  s.variant = "plane";
  s.meaning = "contact of a beam with a rigid plane (the ground, a seabed, a slope): a penalty 1/2 k <-g>^2 per "
              "unit length, g the distance of the centre line from the plane, checked at the mass quadrature points";
  s.role = EnergyRole::Stored;
  s.stored = "potential";
  s.params = {
      {"beam", K::Beam, "", "the beam that touches the plane (director beam or ANCF cable)", ""},
      {"point", K::Vector, "m", "a point of the plane", "", -inf, inf, false, 3},
      {"normal", K::Vector, "", "the plane's normal, towards the side the beam is on (e.g. [0, 0, 1] for the ground)",
       "", -inf, inf, false, 3},
      {"stiffness", K::Number, "N/m^2",
       "k, the bed's stiffness: force per unit length of beam per unit of penetration (a line weight w sinks w / k "
       "into it)",
       "", 0.0, inf, true},
  };
  r.add(s, [](const Model& m, const EffectParams& p) -> std::unique_ptr<Effect> {
    const int beam = beam_param(m, p);
    if (m.beam(beam).is_ancf()) return std::make_unique<PlaneContact<4>>(beam, m, p);
    return std::make_unique<PlaneContact<3>>(beam, m, p);
  });
}

}  // namespace slidebeam::effects
