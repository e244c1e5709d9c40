// SPDX-License-Identifier: MIT
/// @file External loads: gravity, point masses (their weight; inertia comes with dynamics),
/// point forces and point moments with a time function.

#include "effects/common.hpp"
#include "model/time_function.hpp"

#include <Eigen/Dense>

#include <map>
#include <stdexcept>

namespace slidebeam::effects {

namespace {
Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
  return S;
}

/// A point of a beam given by arc length: its position stencil (both formulations) and, on a
/// director beam, the basis of the span that holds it (directors at the point); on a body, the
/// body's one control point (its directors are the body's axes).
struct BeamPoint {
  int beam = 0;
  double s = 0.0;
  PositionStencil stencil;
  PointBasis basis;
  int n_basis = 3;  ///< control points the directors interpolate from (a body: 1)

  BeamPoint(const Model& m, const EffectParams& p, const std::string& who) : beam(beam_param(m, p)) {
    const Beam& b = m.beam(beam);
    s = p.number("s");
    if (s < -1e-12 * b.length() || s > b.length() * (1 + 1e-12))
      throw std::invalid_argument(who + ": point s = " + std::to_string(s) + " is outside beam '" + b.name() +
                                  "' (length " + std::to_string(b.length()) + ")");
    if (b.is_rigid()) {  // a body's point, given where it is drawn
      if (who == "point_mass")
        throw ParamError("beam", "body '" + b.name() + "' takes no point mass: a mass on a body is part of its mass and "
                                 "inertia");
      const Eigen::Vector3d at = vector3_param(p, "point");
      stencil = b.body_point_drawn({at(0), at(1), at(2)});
      basis.N = {1.0, 0.0, 0.0};
      n_basis = 1;
      return;
    }
    stencil = b.position_at(s);
    if (!b.is_ancf()) basis = b.basis_at(s);
  }
  PetscInt cp(const Model& m, int a) const { return m.beam(beam).first_cp() + basis.span + a; }
  bool owned(const Model& m) const { return owns_span(m, m.beam(beam), stencil.span); }
  /// All unknowns of the control points the stencil reads.
  void add_stencil_blocks(const Model& m, std::vector<PetscInt>& dofs) const {
    const Beam& b = m.beam(beam);
    for (int j = 0; j < stencil.n; ++j) add_cp_blocks(m.dof_map(), b.first_cp() + stencil.cp[j], 1, dofs);
  }
  Eigen::Vector3d position(const EvalContext& ctx, const LocalValues& x) const {
    return stencil_point(x, ctx.map, ctx.model.beam(beam), stencil);
  }
  /// r += the generalised force of a point force f at the point.
  void add_force(const EvalContext& ctx, const LocalValues& r, const Eigen::Vector3d& f) const {
    scatter_stencil(r, ctx.map, ctx.model.beam(beam), stencil, f);
  }
  /// Interpolated block (0 = phi, 1..3 = d1..d3) at the point in the state x.
  Eigen::Vector3d field(const EvalContext& ctx, const LocalValues& x, int block) const {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (int a = 0; a < n_basis; ++a)
      v += basis.N[a] * Eigen::Map<const Eigen::Vector3d>(x.cp(ctx.map, cp(ctx.model, a)) + 3 * block);
    return v;
  }
};
}  // namespace

/// A lumped mass at a beam point: m w_a(s) w_b(s) on the position stencil's blocks of the mass
/// matrix (director: N^A N^B on the phi blocks; ANCF: the Hermite weights on r and r'). Its
/// weight comes through the gravity effect.
class PointMass final : public Effect, public MassSource {
 public:
  PointMass(const Model& m, const EffectParams& p) : point(m, p, "point_mass"), kg(p.number("mass")) {
    if (!(kg > 0)) throw std::invalid_argument("point_mass: mass must be > 0");
  }
  std::string type() const override { return "point_mass"; }
  std::string label() const override { return "point_mass[" + std::to_string(kg) + " kg]"; }
  void distribute(const Model& m) override { owned_ = point.owned(m); }
  void needed_dofs(const Model&, std::vector<PetscInt>&) const override {}
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (owned_) PetscCall(add_block_pattern(sink, stencil_dofs(m.dof_map(), m.beam(point.beam), point.stencil)));
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext&, const LocalValues&) const override { return 0; }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override { return 0; }
  PetscErrorCode mass(const Model& m, const MatSink& M) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const PositionStencil& st = point.stencil;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMajor A = RowMajor::Zero(3 * st.n, 3 * st.n);
    for (int a = 0; a < st.n; ++a)
      for (int b = 0; b < st.n; ++b)
        A.block<3, 3>(3 * a, 3 * b) = kg * st.w[a] * st.w[b] * Eigen::Matrix3d::Identity();
    const auto d = stencil_dofs(m.dof_map(), m.beam(point.beam), st);
    PetscCall(M.add(3 * st.n, d.data(), 3 * st.n, d.data(), A.data()));
    PetscFunctionReturn(0);
  }

  BeamPoint point;
  double kg;  ///< the mass

 private:
  bool owned_ = false;
};

/// Uniform gravity on every beam (rho A) and on every point mass of the model. On an ANCF
/// cable the consistent load int rhoA S^T g dx of each element (kernels/ancf_kernels.hpp).
class Gravity final : public Effect {
 public:
  Gravity(const Model&, const EffectParams& p) : f_(TimeFunction::from(p)), g_(vector3_param(p, "g")) {}
  bool time_dependent() const override { return f_.kind != TimeFunction::Kind::Constant; }
  std::string type() const override { return "gravity"; }
  std::string label() const override { return "gravity"; }

  void distribute(const Model& m) override {
    // The load is constant in q: sum it per control point once (unit time function), so that
    // a residual costs one lookup per control point instead of one per basis function and
    // quadrature point.
    std::map<PetscInt, Load6> loads;
    for (const auto& b : m.beams()) {
      if (b.is_rigid()) {  // its weight at its centre of mass
        if (m.dof_map().owns_cp(b.first_cp())) entry(loads, b.first_cp()).head<3>() += b.body_mass() * g_;
        continue;
      }
      if (b.section().rhoA == 0.0) continue;
      for (int e = 0; e < b.n_spans(); ++e) {
        if (!owns_span(m, b, e)) continue;
        if (b.is_ancf()) {
          const kernels::ancf::ElVec f = kernels::ancf::gravity_load(b.ancf_section(), b.ancf_element(e), g_);
          for (int a = 0; a < 2; ++a) entry(loads, b.first_cp() + e + a) += f.segment<6>(6 * a);
          continue;
        }
        for (int q = 0; q < 3; ++q) {
          const auto& gp = b.gp_full(e, q);
          for (int a = 0; a < 3; ++a) entry(loads, b.first_cp() + e + a).head<3>() += gp.w * gp.N[a] * b.section().rhoA * g_;
        }
      }
    }
    nodal_.assign(loads.begin(), loads.end());
    for (const auto& eff : m.effects())
      if (const auto* pm = dynamic_cast<const PointMass*>(eff.get()); pm && pm->point.owned(m)) masses_.push_back(pm);
  }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    for (const auto& [cp, f] : nodal_) add_cp_blocks(m.dof_map(), cp, 1, dofs);
    for (const auto* pm : masses_) pm->point.add_stencil_blocks(m, dofs);
  }
  PetscErrorCode pattern(const Model&, const MatSink&) const override { return 0; }  // constant force

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    const double s = f_(ctx.t);
    for (const auto& [cp, f] : nodal_) {
      PetscScalar* rc = r.cp(ctx.map, cp);
      // director control points take phi (3), ANCF nodes r and r' (6)
      const int n = ctx.map.n_coordinates(cp) == kernels::kNq ? 3 : 6;
      for (int k = 0; k < n; ++k) rc[k] -= s * f(k);
    }
    const Eigen::Vector3d g = s * g_;
    for (const auto* pm : masses_) pm->point.add_force(ctx, r, -pm->kg * g);
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override { return 0; }
  double energy(const EvalContext& ctx) const override {
    const double s = f_(ctx.t);
    double V = 0.0;  // the load is constant, so V = -q . load
    for (const auto& [cp, f] : nodal_) {
      const PetscScalar* xc = ctx.x.cp(ctx.map, cp);
      const int n = ctx.map.n_coordinates(cp) == kernels::kNq ? 3 : 6;
      for (int k = 0; k < n; ++k) V -= s * f(k) * xc[k];
    }
    const Eigen::Vector3d g = s * g_;
    for (const auto* pm : masses_) V -= pm->kg * g.dot(pm->point.position(ctx, ctx.x));
    return V;
  }

 private:
  using Load6 = Eigen::Matrix<double, 6, 1>;
  static Load6& entry(std::map<PetscInt, Load6>& loads, PetscInt cp) {
    return loads.try_emplace(cp, Load6::Zero()).first->second;
  }
  TimeFunction f_;
  Eigen::Vector3d g_;
  std::vector<std::pair<PetscInt, Load6>> nodal_;  // load per control point of g_ (unit time function)
  std::vector<const PointMass*> masses_;
};

/// Force (fixed direction) or moment at a beam point, times a time function.
/// A moment M acts through director forces F_i = 1/2 M x d_i, whose virtual work is M . dtheta
/// (docs/theory.md, "Loads: moments as director forces"). In the material frame M = sum_j m_j d_j
/// follows the section.
class PointLoad final : public Effect {
 public:
  PointLoad(const Model& m, const EffectParams& p, bool moment)
      : point_(m, p, moment ? "moment" : "force"), moment_(moment), f_(TimeFunction::from(p)) {
    value_ = vector3_param(p, "value");
    const std::string frame = p.string("frame", "spatial");
    if (frame != "spatial" && frame != "material") throw std::invalid_argument("load frame must be spatial or material");
    material_ = frame == "material";
    if (material_ && !moment) throw std::invalid_argument("force: only moments can be given in the material frame");
    if (moment && m.beam(point_.beam).is_ancf())  // the cable has no rotational unknowns to do work on
      throw std::invalid_argument("moment: beam '" + m.beam(point_.beam).name() + "' is an ANCF cable (forces only)");
  }
  bool time_dependent() const override { return f_.kind != TimeFunction::Kind::Constant; }
  std::string type() const override { return moment_ ? "moment" : "force"; }
  std::string label() const override { return type() + "[" + std::to_string(point_.beam) + "@" + std::to_string(point_.s) + "]"; }

  void distribute(const Model& m) override { owned_ = point_.owned(m); }
  void needed_dofs(const Model& m, std::vector<PetscInt>& dofs) const override {
    if (owned_) point_.add_stencil_blocks(m, dofs);
  }
  PetscErrorCode pattern(const Model& m, const MatSink& sink) const override {
    PetscFunctionBeginUser;
    if (owned_ && moment_) PetscCall(add_block_pattern(sink, director_dofs(m.dof_map(), m)));
    PetscFunctionReturn(0);
  }
  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!owned_) PetscFunctionReturn(0);
    const double amp = f_(ctx.t);
    if (!moment_) {
      point_.add_force(ctx, r, -amp * value_);
      PetscFunctionReturn(0);
    }
    const Eigen::Vector3d M = amp * moment_vector(ctx);
    for (int i = 1; i <= 3; ++i) {
      const Eigen::Vector3d Fi = 0.5 * M.cross(point_.field(ctx, ctx.xf, i));
      for (int a = 0; a < point_.n_basis; ++a)
        Eigen::Map<Eigen::Vector3d>(r.cp(ctx.map, point_.cp(ctx.model, a)) + 3 * i) -= point_.basis.N[a] * Fi;
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!owned_ || !moment_) PetscFunctionReturn(0);
    const double amp = f_(ctx.t);
    const Eigen::Vector3d M = amp * moment_vector(ctx);
    // dF_i/dd_k = 1/2 (delta_ik [M]x - m_k [d_i]x), the second term only in the material frame.
    const int nb = point_.n_basis;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMajor K = RowMajor::Zero(9 * nb, 9 * nb);
    for (int i = 1; i <= 3; ++i) {
      const Eigen::Vector3d di = point_.field(ctx, ctx.xf, i);
      for (int k = 1; k <= 3; ++k) {
        Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
        if (i == k) D += 0.5 * ctx.theta * skew(M);
        if (material_) D -= 0.5 * ctx.theta * amp * value_(k - 1) * skew(di);
        for (int a = 0; a < nb; ++a)
          for (int b = 0; b < nb; ++b)
            K.block<3, 3>(9 * a + 3 * (i - 1), 9 * b + 3 * (k - 1)) -= point_.basis.N[a] * point_.basis.N[b] * D;
      }
    }
    const auto d = director_dofs(ctx.map, ctx.model);
    const auto n = static_cast<PetscInt>(d.size());
    PetscCall(J.add(n, d.data(), n, d.data(), K.data()));
    PetscFunctionReturn(0);
  }
  double energy(const EvalContext& ctx) const override {
    // A force of fixed direction is conservative; a moment in 3D is not, so it has no potential.
    if (!owned_ || moment_) return 0.0;
    return -f_(ctx.t) * value_.dot(point_.position(ctx, ctx.x));
  }

 private:
  Eigen::Vector3d moment_vector(const EvalContext& ctx) const {
    if (!material_) return value_;
    return value_(0) * point_.field(ctx, ctx.xf, 1) + value_(1) * point_.field(ctx, ctx.xf, 2) +
           value_(2) * point_.field(ctx, ctx.xf, 3);
  }
  std::vector<PetscInt> director_dofs(const DofMap& map, const Model& m) const {
    std::vector<PetscInt> d;
    for (int a = 0; a < point_.n_basis; ++a)
      for (int k = 0; k < 9; ++k) d.push_back(map.q(point_.cp(m, a), 3 + k));
    return d;
  }
  BeamPoint point_;
  bool moment_;
  bool material_ = false;
  TimeFunction f_;
  Eigen::Vector3d value_;
  bool owned_ = false;
};

void register_load_effects(EffectRegistry& r) {
  using K = ParamSpec::Kind;
  const ParamSpec beam{"beam", K::Beam, "", "the beam it acts on", ""};
  const ParamSpec at{"at", K::Point, "m", "the point: \"start\", \"end\" or an arc length in [0, L]", ""};
  const ParamSpec load_tf{"time_function", K::TimeFunction, "",
                          "scales the value over time (default: a ramp over the load steps in statics, constant "
                          "in dynamics)",
                          "load"};
  r.add(table_effect_spec("force", "load", "force", EnergyRole::Stored,
                          "a point force with a time function (potential energy)",
                          {beam, at, {"value", K::Vector, "N", "the force", "", -kInf, kInf, false, 3},
                           {"frame", K::Choice, "", "a force keeps its direction in space", "\"spatial\"", -kInf,
                            kInf, false, 0, {"spatial"}},
                           load_tf},
                          "potential"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<PointLoad>(m, p, false); });
  ParamSpec director_beam = beam;
  director_beam.choices = {"director"};
  director_beam.meaning = "the beam it acts on (an ANCF cable has no rotational unknowns: only forces act on it)";
  r.add(table_effect_spec("moment", "load", "moment", EnergyRole::External,
                          "a point moment with a time function (its work is counted, it has no potential)",
                          {director_beam, at, {"value", K::Vector, "N m", "the moment", "", -kInf, kInf, false, 3},
                           {"frame", K::Choice, "",
                            "\"spatial\": fixed in space; \"material\": components along the section's directors "
                            "d1, d2, d3, turning with it",
                            "\"spatial\"", -kInf, kInf, false, 0, {"spatial", "material"}},
                           load_tf}),
        [](const Model& m, const EffectParams& p) { return std::make_unique<PointLoad>(m, p, true); });
  r.add(table_effect_spec("point_mass", "point_mass", "", EnergyRole::Stored,
                          "a lumped mass at a beam point (kinetic energy; its weight comes with [gravity])",
                          {beam, at, {"mass", K::Number, "kg", "the mass", "", 0.0, kInf, true}}, "kinetic"),
        [](const Model& m, const EffectParams& p) { return std::make_unique<PointMass>(m, p); });
  EffectSpec gravity = table_effect_spec(
      "gravity", "gravity", "", EnergyRole::Stored,
      "weight of every beam and point mass (potential energy)",
      {{"g", K::Vector, "m/s^2", "the acceleration of gravity, e.g. [0, 0, -9.81]", "", -kInf, kInf, false, 3},
       load_tf},
      "potential");
  gravity.single = true;
  r.add(gravity, [](const Model& m, const EffectParams& p) { return std::make_unique<Gravity>(m, p); });
}

}  // namespace slidebeam::effects
