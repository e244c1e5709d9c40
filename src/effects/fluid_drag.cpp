// SPDX-License-Identifier: MIT
/// @file Fluid drag on a beam's centre line (scene table [[drag]]): ropes in wind or water.
///
/// Per unit (current) length, with v the centre line's velocity relative to the flow u (flow
/// times an optional time function f(t), and times a profile p(z) by height where one is given: a
/// current that falls off with depth, a wind's boundary layer) and t = x'/|x'| the centre line's
/// unit tangent
/// (director beams: phi'/|phi'|, not d1, so that shear does not tilt it; ANCF cables: r'/|r'|):
///   f = -1/2 rho D (C_n |v_n| v_n + C_t |v_t| v_t),   v_t = (t . v) t,  v_n = v - v_t,
/// rho the fluid's density, D the diameter (the projected width), C_n and C_t the normal and
/// tangential drag coefficients (C_t on the diameter: pi times a skin-friction coefficient on the
/// wetted perimeter). The integral over the current length, int f |x'| dS, is taken with the
/// mass's quadrature (3 points per span, 5 per ANCF element).
///
/// |w| is regularised to sqrt(w . w + eps^2) (eps: `regularization`, a velocity), so that the
/// force is smooth at w = 0 and the step has a Jacobian there; for |w| >> eps the relative error
/// of the force is eps^2 / (2 |w|^2).
///
/// Over a step the velocity is the mean rate (x_n+1 - x_n) / h, the tangent is the one at the
/// step's force state x_f (the midpoint for energy-momentum and midpoint, the end for Newmark and
/// HHT), the flow the one at the load time and at the height of x_f: as for beam_damping. The
/// profile is piecewise linear through (profile_z[k], profile[k]), constant beyond its ends. Outside steps (h = 0: statics,
/// Newmark's and HHT's initial acceleration, HHT's history term) there is no rate and no force.
///
/// Energy: the force is external (role External): its work -r . (q_n+1 - q_n) over each step is
/// in W. Relative to still fluid (u = 0) that work is h sum w |x'| f . v <= 0 point by point
/// (v_n . v = |v_n|^2, v_t . v = |v_t|^2), so drag then only takes energy out, exactly at the
/// discrete level; a flow can put energy in (wind driving a rope).

#include "effects/common.hpp"
#include "model/time_function.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace slidebeam::effects {

namespace {
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

struct DragLaw {
  double k = 0.0;   ///< 1/2 rho D
  double cn = 0.0;  ///< normal drag coefficient
  double ct = 0.0;  ///< tangential drag coefficient
  double eps = 0.0; ///< regularisation velocity
};

/// Drag per unit current length F(a, v) at a point of tangent vector a = x' (not normalised;
/// |a| is the stretch) and relative velocity v; with dF/dv and dF/da if wanted.
struct DragPoint {
  Vec3 F;
  Mat3 dFdv, dFda;
};

DragPoint drag_point(const DragLaw& law, const Vec3& a, const Vec3& v, bool derivatives) {
  const double aa = a.squaredNorm(), L = std::sqrt(aa), av = a.dot(v);
  const Vec3 vt = (av / aa) * a, vn = v - vt;
  const double e2 = law.eps * law.eps;
  const double gn = std::sqrt(vn.squaredNorm() + e2), gt = std::sqrt(vt.squaredNorm() + e2);
  const Vec3 phi = law.cn * gn * vn + law.ct * gt * vt;
  DragPoint p;
  p.F = -law.k * L * phi;
  if (!derivatives) return p;
  const Mat3 I = Mat3::Identity();
  const Mat3 Pt = a * a.transpose() / aa, Pn = I - Pt;
  // d(g(w) w)/dw = g I + w w^T / g, with g = sqrt(w . w + eps^2)
  const Mat3 Phin = gn * I + vn * vn.transpose() / gn, Phit = gt * I + vt * vt.transpose() / gt;
  p.dFdv = -law.k * L * (law.cn * Phin * Pn + law.ct * Phit * Pt);
  // d v_t / d a of v_t = (a . v) a / (a . a); d v_n / d a = -d v_t / d a; d|a|/da = a^T / |a|
  const Mat3 dvt = (a * v.transpose() + av * I) / aa - (2.0 * av / (aa * aa)) * a * a.transpose();
  p.dFda = -law.k * (phi * a.transpose() / L + L * (law.ct * Phit - law.cn * Phin) * dvt);
  return p;
}

/// A flow's profile by height: piecewise linear through (z[k], p[k]), constant beyond the ends;
/// none: 1 everywhere.
struct FlowProfile {
  std::vector<double> z, p;
  /// p(height) and dp/dheight.
  std::pair<double, double> at(double height) const {
    if (z.empty()) return {1.0, 0.0};
    if (height <= z.front()) return {p.front(), 0.0};
    if (height >= z.back()) return {p.back(), 0.0};
    const size_t k = static_cast<size_t>(std::upper_bound(z.begin(), z.end(), height) - z.begin());
    const double slope = (p[k] - p[k - 1]) / (z[k] - z[k - 1]);
    return {p[k - 1] + slope * (height - z[k - 1]), slope};
  }
};

FlowProfile flow_profile(const EffectParams& p) {
  FlowProfile f;
  const bool has_z = p.vec.count("profile_z") > 0, has_p = p.vec.count("profile") > 0;
  if (!has_z && !has_p) return f;
  if (has_z != has_p)
    throw ParamError(has_z ? "profile" : "profile_z", "a profile needs both `profile_z` (heights) and `profile` (factors)");
  f.z = p.vec.at("profile_z");
  f.p = p.vec.at("profile");
  if (f.z.size() != f.p.size() || f.z.size() < 2)
    throw ParamError("profile", "must have as many factors as `profile_z` has heights, at least 2 (got " +
                                    std::to_string(f.p.size()) + " and " + std::to_string(f.z.size()) + ")");
  for (size_t k = 0; k + 1 < f.z.size(); ++k)
    if (!(f.z[k + 1] > f.z[k])) throw ParamError("profile_z", "the heights must increase");
  return f;
}

}  // namespace

/// Drag on one beam: W = 3 a director beam, W = 4 an ANCF cable (CentreLineEffect).
template <int W>
class FluidDrag final : public CentreLineEffect<W> {
  using Base = CentreLineEffect<W>;
  using typename Base::MatY;
  using typename Base::VecY;
  using Base::beam_;
  using Base::gather;
  using Base::n_points;
  using Base::point;

 public:
  FluidDrag(int beam, const Model& m, const EffectParams& p)
      : Base(beam, m), f_(TimeFunction::from(p)), profile_(flow_profile(p)) {
    const double rho = p.number("density"), D = p.number("diameter");
    law_.cn = p.number("cd_normal", 1.2);
    law_.ct = p.number("cd_tangential", 0.0);
    law_.eps = p.number("regularization", 1e-3);
    law_.k = 0.5 * rho * D;
    flow_ = vector3_param(p, "flow");
    if (!(rho > 0.0) || !(D > 0.0) || !(law_.cn >= 0.0) || !(law_.ct >= 0.0) || !(law_.eps > 0.0) || !flow_.allFinite())
      throw std::invalid_argument("drag: density, diameter and regularization must be > 0, the coefficients >= 0");
  }
  std::string type() const override { return "fluid_drag"; }

  bool acts(const EvalContext& ctx) const override { return ctx.h > 0.0; }  // no step, no rate

 private:
  /// r += the element's generalised drag force (with the sign of a residual: -int N^T f), and
  /// K += its derivative with respect to the step's end state.
  void element(const EvalContext& ctx, const Beam& b, int e, VecY& r, MatY* K) const override {
    const VecY y0 = gather(ctx, ctx.x_old, b, e), y1 = gather(ctx, ctx.x, b, e), yf = gather(ctx, ctx.xf, b, e);
    const Vec3 u0 = f_(ctx.t) * flow_;
    const double h = ctx.h, theta = ctx.theta;
    for (int g = 0; g < n_points(b); ++g) {
      const CentreLinePoint<W> q = point(b, e, g);
      Vec3 a = Vec3::Zero(), x = Vec3::Zero(), v = Vec3::Zero();
      for (int i = 0; i < W; ++i) {
        a += q.dN[static_cast<size_t>(i)] * yf.template segment<3>(3 * i);
        x += q.N[static_cast<size_t>(i)] * yf.template segment<3>(3 * i);
        v += q.N[static_cast<size_t>(i)] / h * (y1 - y0).template segment<3>(3 * i);
      }
      const auto [factor, slope] = profile_.at(x.z());
      v -= factor * u0;
      const DragPoint p = drag_point(law_, a, v, K != nullptr);
      for (int i = 0; i < W; ++i) r.template segment<3>(3 * i) -= q.w * q.N[static_cast<size_t>(i)] * p.F;
      if (!K) continue;
      // the flow at the force state's height: dv/dx_f = -u0 p'(z) e_z^T
      Mat3 dFdx = Mat3::Zero();
      if (slope != 0.0) dFdx.col(2) = -slope * (p.dFdv * u0);
      for (int j = 0; j < W; ++j) {
        const Mat3 dF = (q.N[static_cast<size_t>(j)] / h) * p.dFdv + (theta * q.dN[static_cast<size_t>(j)]) * p.dFda +
                        (theta * q.N[static_cast<size_t>(j)]) * dFdx;
        for (int i = 0; i < W; ++i) K->template block<3, 3>(3 * i, 3 * j) -= q.w * q.N[static_cast<size_t>(i)] * dF;
      }
    }
  }

  TimeFunction f_;
  FlowProfile profile_;
  DragLaw law_;
  Vec3 flow_;
};

void register_drag_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const double inf = std::numeric_limits<double>::infinity();
  EffectSpec s = table_effect_spec(
      "fluid_drag", "drag", "", EnergyRole::External,
      "fluid drag on a beam's centre line (wind, current): per length -1/2 rho D (C_n |v_n| v_n + C_t |v_t| v_t), v "
      "the velocity relative to the flow (uniform, or by a profile over height)",
      {});
  s.rate_force = true;
  s.params = {
      {"beam", K::Beam, "", "the beam in the flow (director beam or ANCF cable)", ""},
      {"diameter", K::Number, "m", "D, the width the flow sees (a rope's diameter)", "", 0.0, inf, true},
      {"density", K::Number, "kg/m^3", "rho of the fluid (air 1.225, fresh water 1000, seawater 1025)", "", 0.0, inf,
       true},
      {"cd_normal", K::Number, "", "C_n, drag coefficient across the centre line (circular cylinder: about 1.2)",
       "1.2", 0.0},
      {"cd_tangential", K::Number, "",
       "C_t, drag coefficient along the centre line, on the diameter (pi times a skin-friction coefficient; "
       "ropes about 0.01 to 0.03; 0: none)",
       "0.0", 0.0},
      {"ca_normal", K::Number, "",
       "C_n, added-mass coefficient across the centre line: the line carries C_n rho pi D^2 / 4 of fluid per "
       "unit length with it (a circular cylinder: 1; 0: none; dynamic runs)",
       "0.0", 0.0},
      {"ca_tangential", K::Number, "", "C_t, added-mass coefficient along the centre line (0: none)", "0.0", 0.0},
      {"flow", K::Vector, "m/s", "velocity of the fluid (uniform): wind or current", "[0.0, 0.0, 0.0]", -inf, inf,
       false, 3},
      {"time_function", K::TimeFunction, "", "scales the flow over time (a gust, a tide)", "{ type = \"constant\" }"},
      optional_param({"profile_z", K::Vector, "m",
                      "heights (global z, increasing) of the flow's profile: a current by depth, a wind's boundary "
                      "layer",
                      "", -inf, inf, false, 0}),
      optional_param({"profile", K::Vector, "",
                      "the flow's factor at each of `profile_z` (piecewise linear between, constant beyond)", "", -inf,
                      inf, false, 0}),
      {"regularization", K::Number, "m/s",
       "eps of |w| ~ sqrt(w . w + eps^2): the force is smooth at rest (relative error eps^2 / (2 |w|^2))", "1e-3", 0.0,
       inf, true},
  };
  r.add(s, make_centre_line_effect<FluidDrag>);
}

}  // namespace slidebeam::effects
