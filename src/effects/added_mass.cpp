// SPDX-License-Identifier: MIT
/// @file The added mass of a line in a fluid (`ca_normal` or `ca_tangential` > 0 on a [[drag]]
/// entry adds this effect beside the drag, in dynamic runs): the water a rope or chain
/// accelerates with it, C_n rho pi D^2 / 4 per unit length across the line and C_t rho pi D^2 / 4
/// along it (kernels/added_mass.hpp). Its kinetic energy 1/2 v^T A(x') v follows the line's
/// direction, so it is an effect with Lagrange's forces of that energy (role Stored, "kinetic";
/// ConfigurationKinetic: the integrator counts A v in the kinetic energy and momenta), at the
/// mass quadrature points and per unit reference length (as MoorDyn's, on the unstretched
/// length). The fluid is still: a current's own acceleration (Froude-Krylov) is not modelled.
///
/// Under energy-momentum (and midpoint) the step's forces conserve the added kinetic energy
/// exactly (a discrete gradient); under Newmark and HHT they are the equations of motion at the
/// step's end. Their tangent is differentiated by hand under energy-momentum and midpoint and by
/// automatic differentiation of the point kernel under Newmark and HHT. The initial
/// acceleration of Newmark and HHT is solved with the added mass at the start (mass_at), from the
/// forces alone: the velocity's terms of Lagrange's equations are left out there (exact for a
/// start at rest).

#include "effects/common.hpp"
#include "kernels/added_mass.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

#include <cmath>
#include <memory>
#include <string>

namespace slidebeam::effects {

namespace {
namespace am = kernels::added_mass;
using Vec3 = Eigen::Vector3d;

template <int W>
class AddedMass final : public CentreLineEffect<W>, public ConfigurationKinetic {
  using Base = CentreLineEffect<W>;
  using typename Base::MatY;
  using typename Base::VecY;
  using Base::gather;
  using Base::n_points;
  using Base::point;
  using Base::position;
  using Base::tangent;
  using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, 6, 1>>;
  using Vec3AD = Eigen::Matrix<AD, 3, 1>;

 public:
  AddedMass(int beam, const Model& m, const EffectParams& p) : Base(beam, m) {
    const double rho = p.number("density"), D = p.number("diameter");
    const double displaced = rho * M_PI * D * D / 4.0;
    c_.m_n = p.number("ca_normal", 0.0) * displaced;
    c_.m_t = p.number("ca_tangential", 0.0) * displaced;
  }
  std::string type() const override { return "added_mass"; }

  void momentum(const EvalContext& ctx, const LocalValues& v, const LocalValues& p) const override {
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      const VecY y = gather(ctx, ctx.x, b, e), vy = gather(ctx, v, b, e);
      VecY pe = VecY::Zero();
      for (int g = 0; g < n_points(b); ++g) {
        const CentreLinePoint<W> q = point(b, e, g);
        const Vec3 pv = am::apply(c_, tangent(q, y), position(q, vy));
        for (int i = 0; i < W; ++i) pe.template segment<3>(3 * i) += q.w * q.N[static_cast<size_t>(i)] * pv;
      }
      this->scatter(ctx, p, b, e, pe);
    }
  }
  PetscErrorCode mass_at(const EvalContext& ctx, const MatSink& M) const override {
    PetscFunctionBeginUser;
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      const VecY y = gather(ctx, ctx.x, b, e);
      MatY K = MatY::Zero();
      for (int g = 0; g < n_points(b); ++g) {
        const CentreLinePoint<W> q = point(b, e, g);
        const Eigen::Matrix3d A = am::matrix(c_, tangent(q, y));
        for (int i = 0; i < W; ++i)
          for (int j = 0; j < W; ++j)
            K.template block<3, 3>(3 * i, 3 * j) += (q.w * q.N[static_cast<size_t>(i)] * q.N[static_cast<size_t>(j)]) * A;
      }
      const auto d = this->element_dofs(ctx.map, b, e);
      PetscCall(M.add(Base::kDofs, d.data(), Base::kDofs, d.data(), K.data()));
    }
    PetscFunctionReturn(0);
  }

 private:
  bool acts(const EvalContext& ctx) const override { return ctx.h > 0.0 && ctx.v_old != nullptr; }

  void element(const EvalContext& ctx, const Beam& b, int e, VecY& r, MatY* K) const override {
    const VecY y0 = gather(ctx, ctx.x_old, b, e), y1 = gather(ctx, ctx.x, b, e), v0 = gather(ctx, *ctx.v_old, b, e);
    const bool midpoint = ctx.scheme == StepScheme::EnergyMomentum || ctx.scheme == StepScheme::Midpoint;
    const VecY a0 = midpoint ? VecY::Zero() : gather(ctx, *ctx.a_old, b, e);
    for (int g = 0; g < n_points(b); ++g) {
      const CentreLinePoint<W> q = point(b, e, g);
      const Vec3 r1d = position(q, y1), b1d = tangent(q, y1);
      const auto forces = [&](const auto& r1, const auto& b1, auto& f_r, auto& f_b) {
        if (midpoint) {
          am::midpoint_forces(c_, ctx.h, position(q, y0), tangent(q, y0), position(q, v0), r1, b1, f_r, f_b);
        } else {
          const am::NewmarkStart s{position(q, y0), position(q, v0), position(q, a0),
                                   tangent(q, y0),  tangent(q, v0),  tangent(q, a0)};
          am::endpoint_forces(c_, ctx.h, ctx.beta, ctx.gamma, s, r1, b1, f_r, f_b);
        }
      };
      Vec3 fr, fb;
      Eigen::Matrix<double, 3, 6> dfr, dfb;
      if (!K) {  // the residual alone: plain doubles
        forces(r1d, b1d, fr, fb);
      } else if (midpoint) {  // and its derivatives with respect to the point's end position and tangent
        const am::PointTangent d =
            am::midpoint_tangent(c_, ctx.h, position(q, y0), tangent(q, y0), position(q, v0), r1d, b1d, fr, fb);
        dfr << d.fr_r, d.fr_b;
        dfb << d.fb_r, d.fb_b;
      } else {  // Newmark, HHT: by automatic differentiation
        Vec3AD r1, b1, f_r, f_b;
        for (int k = 0; k < 3; ++k) {
          r1(k) = AD(r1d(k), 6, k);
          b1(k) = AD(b1d(k), 6, 3 + k);
        }
        forces(r1, b1, f_r, f_b);
        for (int k = 0; k < 3; ++k) {
          fr(k) = f_r(k).value();
          fb(k) = f_b(k).value();
          dfr.row(k) = f_r(k).derivatives().transpose();
          dfb.row(k) = f_b(k).derivatives().transpose();
        }
      }
      for (int i = 0; i < W; ++i)
        r.template segment<3>(3 * i) += q.w * (q.N[static_cast<size_t>(i)] * fr + q.dN[static_cast<size_t>(i)] * fb);
      if (!K) continue;
      for (int j = 0; j < W; ++j) {
        const double Nj = q.N[static_cast<size_t>(j)], dNj = q.dN[static_cast<size_t>(j)];
        const Eigen::Matrix3d dr = Nj * dfr.leftCols<3>() + dNj * dfr.rightCols<3>();
        const Eigen::Matrix3d db = Nj * dfb.leftCols<3>() + dNj * dfb.rightCols<3>();
        for (int i = 0; i < W; ++i)
          K->template block<3, 3>(3 * i, 3 * j) +=
              q.w * (q.N[static_cast<size_t>(i)] * dr + q.dN[static_cast<size_t>(i)] * db);
      }
    }
  }

  am::Coefficients c_;
};

}  // namespace

void register_added_mass_effects(EffectRegistry& r) {
  EffectSpec s = model_effect_spec("added_mass", EnergyRole::Stored,
                                   "the added mass of a line in a fluid (a [[drag]] entry's ca_normal or ca_tangential "
                                   "> 0): the kinetic energy of the water it moves, 1/2 v^T A v per unit length, "
                                   "A = rho pi D^2 / 4 (C_n across the line, C_t along it)",
                                   "kinetic");
  s.rate_force = true;
  r.add(s, make_centre_line_effect<AddedMass>);
}

}  // namespace slidebeam::effects
