// SPDX-License-Identifier: MIT
/// @file Buoyancy of a beam in still water (scene table [[buoyancy]]): ropes, chains and
/// mooring lines under a free surface.
///
/// Per unit length of the beam, the weight of the water its section displaces, upward (against
/// g), times the part of the section below the surface:
///   f = rho_w |g| A chi(h) n,   h = n . (x - p),   n = -g / |g|,
/// rho_w the water's density, A = pi D^2 / 4 the displaced area of a section of diameter D, p a
/// point of the surface and h the centre line's height above it. chi is 1 at depth (h <= -D/2), 0
/// above the water (h >= D/2) and a smoothstep between, 1 - (3 u^2 - 2 u^3) with u = (h + D/2) / D:
/// a line floats where its weight balances the submerged part, and the force is smooth through the
/// surface. It is the gradient of a potential (gap_potential.hpp), V(h) = -rho_w |g| A Psi(h) with
/// Psi' = chi, part of H: energy-momentum keeps the balance exact as the line enters and leaves
/// the water.

#include "effects/gap_potential.hpp"

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

namespace slidebeam::effects {

namespace {
/// V(h) = -c Psi(h), c = rho_w |g| A, Psi' = chi.
struct Submersion {
  static constexpr int kBreakpoints = 2;
  double c = 0.0;     ///< rho_w |g| A: the buoyancy per unit length at full depth
  double D = 0.0;     ///< the section's diameter: the band of partial submersion
  std::array<double, 2> breakpoints() const { return {-0.5 * D, 0.5 * D}; }
  double u(double h) const { return (h + 0.5 * D) / D; }
  double V(double h) const {
    if (h <= -0.5 * D) return -c * h;
    if (h >= 0.5 * D) return 0.0;
    const double s = u(h);
    return -c * (-0.5 * D + D * (s - s * s * s + 0.5 * s * s * s * s));
  }
  double dV(double h) const {  // -c chi(h)
    if (h <= -0.5 * D) return -c;
    if (h >= 0.5 * D) return 0.0;
    const double s = u(h);
    return -c * (1.0 - s * s * (3.0 - 2.0 * s));
  }
  double ddV(double h) const {  // -c chi'(h)
    if (h <= -0.5 * D || h >= 0.5 * D) return 0.0;
    const double s = u(h);
    return c * 6.0 * s * (1.0 - s) / D;
  }
};

/// The surface: a plane normal to g, its normal up.
PlaneGap surface(const EffectParams& p) {
  const Eigen::Vector3d g = vector3_param(p, "g");
  if (!(g.norm() > 0.0) || !g.allFinite()) throw ParamError("g", "buoyancy needs gravity: a nonzero g");
  return {-g.normalized(), vector3_param(p, "surface")};
}

Submersion submersion(const EffectParams& p) {
  Submersion law;
  const double rho = p.number("density");
  law.D = p.number("diameter");
  if (!(rho > 0.0)) throw ParamError("density", "the water's density must be > 0");
  if (!(law.D > 0.0)) throw ParamError("diameter", "the diameter must be > 0");
  law.c = rho * vector3_param(p, "g").norm() * M_PI * 0.25 * law.D * law.D;
  return law;
}
}  // namespace

/// Buoyancy on one beam.
template <int W>
class Buoyancy final : public GapPotential<W, Submersion> {
 public:
  Buoyancy(int beam, const Model& m, const EffectParams& p)
      : GapPotential<W, Submersion>(beam, m, surface(p), submersion(p)) {}
  std::string type() const override { return "buoyancy"; }
};

void register_buoyancy_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const double inf = std::numeric_limits<double>::infinity();
  const EffectSpec s = table_effect_spec(
      "buoyancy", "buoyancy", "", EnergyRole::Stored,
      "buoyancy of a beam in still water: per unit length rho_w |g| A (A = pi D^2 / 4) against g, times the part "
      "of the section below the surface (smooth over the diameter)",
      {{"beam", K::Beam, "", "the beam in the water (director beam or ANCF cable)", ""},
       {"density", K::Number, "kg/m^3", "rho_w of the water (fresh 1000, sea 1025)", "", 0.0, inf, true},
       {"diameter", K::Number, "m",
        "D: the section displaces pi D^2 / 4 per unit length (a chain: its volume's equivalent diameter)", "", 0.0, inf,
        true},
       {"surface", K::Vector, "m", "a point of the water's surface (the surface is normal to g)", "", -inf, inf, false,
        3},
       {"g", K::Vector, "m/s^2", "the gravity the water weighs under; [0, 0, 0]: [gravity]'s", "[0.0, 0.0, 0.0]", -inf,
        inf, false, 3}},
      "potential");
  r.add(s, make_centre_line_effect<Buoyancy>);
}

}  // namespace slidebeam::effects
