// SPDX-License-Identifier: MIT
/// @file Coulomb friction between a beam and the fixed shape of its [[contact]] (`mu` > 0 on the
/// entry adds this effect beside the contact; docs/theory.md, "Friction and damping on contact").
///
/// Each mass quadrature point of the beam in contact is held at an anchor a on the shape by a
/// tangential spring of stiffness k_t per unit length (by default the bed's k), whose force is
/// capped at mu N, N = k <-g> the bed's normal force per unit length. Over a time step, from the
/// anchor a_n of the step's start, with the point's end position x1 and the shape's unit normal n
/// at x1 (P = I - n n^T):
///
///   e_trial = P (x1 - a_n),   e1 = e_trial                               if k_t |e_trial| <= mu N1,
///                             e1 = (mu N1 / k_t) e_trial / |e_trial|     otherwise (slip),
///
/// and the point's tangential force is k_t e1 (opposing e1), at the step's end under every
/// scheme (backward Euler on the friction law: the return map of elasto-plasticity). A step that
/// is accepted moves the anchor to a_n+1 = x1 - e1: a sticking point keeps its anchor, a slipping
/// one drags it along. So a point sticks for good below the limit (it stays within mu N / k_t of
/// its anchor, the bed's own scale: a line weight w sinks w / k), with no creep however long the
/// load lasts, and slips at the limit force. A point that touches down anchors where the step
/// started; one that lifts off forgets its anchor.
///
/// Energy: the springs' energy sum 1/2 k_t |e|^2 is part of H (potential), and what the step
/// dissipates is their force's work minus that energy's change (EnergyRole::Dissipative with a
/// stored part): on a plane, per point, k_t e1 . (e_trial - e1) + 1/2 k_t |e1 - e_n|^2 >= 0, slip
/// and the backward-Euler spring's small loss while it sticks. On a round shape P moves with the
/// point, which adds terms of the order of the shape's curvature times the elastic slip.
///
/// With `mu_axial` and `mu_transverse` (MoorDyn's seabed friction along and across the line) the
/// limit is an ellipse in the surface, the beam's direction at the step's start as its axis:
/// (f_a / mu_a)^2 + (f_t / mu_t)^2 <= N^2 (friction_point).
///
/// Friction acts within time steps only: the equilibrium start and static runs are frictionless.
/// Shapes carried by a body are refused for now (their anchors would turn with the body).

#include "effects/contact_shapes.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

namespace slidebeam::effects {

namespace {

/// One point's friction over a step: the force on it (residual sign: +k_t e1, the beam is pulled
/// by -k_t e1), its derivative with respect to the point's end position, the elastic slip e1 and
/// whether it slipped.
struct FrictionPoint {
  Eigen::Vector3d force, e1;
  Eigen::Matrix3d stiffness;
  bool slipped = false;
};

/// A load within this share of mu N above the limit still sticks (as on a sliding joint).
constexpr double kTie = 1e-6;

/// k_t: the entry's `tangential_stiffness`, by default the bed's stiffness k.
double tangential_stiffness(const EffectParams& p, double k) {
  const double kt = p.num.count("tangential_stiffness") ? p.number("tangential_stiffness") : k;
  if (!(kt > 0.0)) throw ParamError("tangential_stiffness", "the tangential stiffness must be > 0");
  return kt;
}

/// Coulomb's coefficients along the beam and across it (MoorDyn's axial and transverse seabed
/// friction): the limit of the tangential force f is the ellipse (f_a / mu_a)^2 + (f_t / mu_t)^2
/// <= N^2, f_a its part along the beam's direction t on the surface, f_t the rest.
struct Coefficients {
  double axial = 0.0, transverse = 0.0;
  bool isotropic() const { return axial == transverse; }
};

/// The return map of one point at end position x1 held at anchor a (Shape: PlaneGap, RoundGap),
/// with t the beam's unit direction in the surface at the step's start (fixed over the step, so
/// that the step's Jacobian has no term from it; zero with equal coefficients). Stick while
/// phi(e) = k_t |e|_M <= N, |e|_M^2 = e . M e, M = t t^T / mu_a^2 + (I - t t^T) / mu_t^2 (with equal
/// coefficients k_t |e| <= mu N); in slip the trial is scaled back onto the limit, e1 = (N / phi)
/// e_trial, so the force keeps the trial's direction and the slip's work is never negative.
/// false: the point is not in contact at x1 (no force, no anchor).
template <class Shape>
bool friction_point(const Penalty& law, const Shape& shape, const Coefficients& mu, double kt,
                    const Eigen::Vector3d& x1, const Eigen::Vector3d& a, const Eigen::Vector3d& t, bool with_K,
                    FrictionPoint& out) {
  const double g = shape.gap(x1);
  if (!(g < 0.0)) return false;
  const double N = -law.dV(g);
  const Eigen::Vector3d n = shape.gradient(x1);
  const Eigen::Vector3d d = x1 - a;
  const double nd = n.dot(d);
  const Eigen::Vector3d e = d - nd * n;
  // M e, M the limit's metric
  Eigen::Vector3d Me = e / (mu.transverse * mu.transverse);
  if (!mu.isotropic()) Me += (1.0 / (mu.axial * mu.axial) - 1.0 / (mu.transverse * mu.transverse)) * t.dot(e) * t;
  const double norm_M = std::sqrt(std::max(e.dot(Me), 0.0)), phi = kt * norm_M;
  out.slipped = phi > N * (1.0 + kTie);
  Eigen::Matrix3d De;  // d e / d x1
  if (with_K) {
    const Eigen::Matrix3d H = shape.hessian(x1);
    De = Eigen::Matrix3d::Identity() - n * n.transpose() - nd * H - n * (H * d).transpose();
  }
  if (!out.slipped) {
    out.e1 = e;
    out.force = kt * e;
    if (with_K) out.stiffness = kt * De;
    return true;
  }
  const double r = N / phi;  // < 1
  out.e1 = r * e;
  out.force = kt * out.e1;
  if (with_K) {
    // r = N / (kt |e|_M): dr = dN / phi - r (Me . de) / |e|_M^2
    const Eigen::Vector3d dN = -law.ddV(g) * n;
    const Eigen::RowVector3d dr = dN.transpose() / phi - (r / (norm_M * norm_M)) * (Me.transpose() * De);
    out.stiffness = kt * (r * De + e * dr);
  }
  return true;
}

/// Friction of one beam (W = 3: director, 4: ANCF) on a fixed Shape.
template <int W, class Shape>
class ContactFriction final : public CentreLineEffect<W>, public PointHistory<4>, public OutputSource {
  using Base = CentreLineEffect<W>;
  using Base::position;
  using VecY = typename Base::VecY;
  using MatY = typename Base::MatY;
  // per point: the anchor's 3 coordinates, then its state (kFree, kStuck, kSlipped)
  static constexpr int kPerPoint = 4;
  static constexpr double kFree = 0.0, kStuck = 1.0, kSlipped = 2.0;

 public:
  ContactFriction(int beam, const Model& m, const EffectParams& p, const std::string& label, const Shape& shape)
      : Base(beam, m), shape_(shape), law_(bed(p)), label_(label) {
    const double mu = p.number("mu");
    mu_ = {p.num.count("mu_axial") ? p.number("mu_axial") : mu, p.num.count("mu_transverse") ? p.number("mu_transverse") : mu};
    for (const auto& [key, value] : {std::pair<const char*, double>{"mu_axial", mu_.axial}, {"mu_transverse", mu_.transverse}})
      if (!(value > 0.0))
        throw ParamError(p.num.count(key) ? key : "mu", std::string("friction on a contact needs ") + key +
                                                            " > 0 (it is mu unless given)");
    kt_ = tangential_stiffness(p, law_.k);
    size_history(m.beam(beam).n_spans(), Base::n_points(m.beam(beam)));
  }
  std::string type() const override { return "contact_friction"; }
  std::string label() const override { return label_; }

  void distribute(const Model& m) override {
    Base::distribute(m);
    own_spans(m.beam(this->beam_).n_spans(), this->elements_);
  }

  void commit(const EvalContext& ctx) override {
    if (!acts(ctx)) return;
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      const VecY y1 = this->gather(ctx, ctx.x, b, e), y0 = this->gather(ctx, ctx.x_old, b, e);
      for (int g = 0; g < points_; ++g) {
        const CentreLinePoint<W> q = Base::point(b, e, g);
        const Eigen::Vector3d x1 = position(q, y1);
        double* h = slot(e, g);
        FrictionPoint f;
        if (!friction_point(law_, shape_, mu_, kt_, x1, anchor(h, position(q, y0)), direction(q, y0), false, f)) {
          for (int k = 0; k < kPerPoint; ++k) h[k] = 0.0;
          continue;
        }
        const Eigen::Vector3d held = x1 - f.e1;
        for (int k = 0; k < 3; ++k) h[k] = held(k);
        h[3] = f.slipped ? kSlipped : kStuck;
      }
    }
  }

  /// The tangential springs' energy at x (anchors as committed).
  double energy(const EvalContext& ctx) const override {
    double U = 0.0;
    at_anchored(ctx, [&](double w, const Eigen::Vector3d& e, double) { U += 0.5 * w * kt_ * e.squaredNorm(); });
    return U;
  }

  std::vector<std::string> output_names() const override {
    return {"force.x", "force.y", "force.z", "sticking", "slipping"};
  }
  /// The friction force on the beam and the lengths that stuck and slipped over the last step.
  void outputs(const EvalContext& ctx, double* values) const override {
    at_anchored(ctx, [&](double w, const Eigen::Vector3d& e, double state) {
      const Eigen::Vector3d f = -w * kt_ * e;
      for (int k = 0; k < 3; ++k) values[k] += f(k);
      values[state == kSlipped ? 4 : 3] += w;
    });
  }

 protected:
  bool acts(const EvalContext& ctx) const override { return ctx.h > 0.0 && ctx.scheme != StepScheme::Static; }

  void element(const EvalContext& ctx, const Beam& b, int e, VecY& r, MatY* K) const override {
    const VecY y1 = this->gather(ctx, ctx.x, b, e), y0 = this->gather(ctx, ctx.x_old, b, e);
    for (int g = 0; g < points_; ++g) {
      const CentreLinePoint<W> q = Base::point(b, e, g);
      FrictionPoint f;
      if (!friction_point(law_, shape_, mu_, kt_, position(q, y1), anchor(slot(e, g), position(q, y0)),
                          direction(q, y0), K != nullptr, f))
        continue;
      for (int i = 0; i < W; ++i) r.template segment<3>(3 * i) += q.w * q.N[static_cast<size_t>(i)] * f.force;
      if (!K) continue;
      for (int i = 0; i < W; ++i)
        for (int j = 0; j < W; ++j)
          K->template block<3, 3>(3 * i, 3 * j) +=
              q.w * q.N[static_cast<size_t>(i)] * q.N[static_cast<size_t>(j)] * f.stiffness;
    }
  }

 private:
  /// Where a point is held over the step: its committed anchor, or where the step started if it
  /// had none (it touches down in this step).
  static Eigen::Vector3d anchor(const double* h, const Eigen::Vector3d& x0) {
    return h[3] == kFree ? x0 : Eigen::Vector3d(h[0], h[1], h[2]);
  }
  /// f(weight, elastic slip P (x - a), state) at every anchored point of this rank's elements.
  template <class F>
  void at_anchored(const EvalContext& ctx, F&& f) const {
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      const VecY y = this->gather(ctx, ctx.x, b, e);
      for (int g = 0; g < points_; ++g) {
        const double* h = slot(e, g);
        if (h[3] == kFree) continue;
        const CentreLinePoint<W> q = Base::point(b, e, g);
        const Eigen::Vector3d x = position(q, y), n = shape_.gradient(x);
        const Eigen::Vector3d d = x - Eigen::Vector3d(h[0], h[1], h[2]);
        f(q.w, Eigen::Vector3d(d - n.dot(d) * n), h[3]);
      }
    }
  }
  /// The beam's unit direction in the shape's surface at the point in state y (the centre line's
  /// tangent less its normal part); zero when the coefficients are equal (not read then).
  Eigen::Vector3d direction(const CentreLinePoint<W>& q, const VecY& y) const {
    if (mu_.isotropic()) return Eigen::Vector3d::Zero();
    Eigen::Vector3d t = Base::tangent(q, y);
    const Eigen::Vector3d n = shape_.gradient(position(q, y));
    t -= n.dot(t) * n;
    const double norm = t.norm();
    return norm > 0.0 ? Eigen::Vector3d(t / norm) : t;
  }

  Shape shape_;
  Penalty law_;
  Coefficients mu_;
  double kt_ = 0.0;
  std::string label_;
};

/// Friction on a cylinder carried by a body (a drum, a sheave: `body` on the [[contact]] entry),
/// the law of ContactFriction with equal coefficients, in the body's frame: with D = (d1, d2, d3)
/// the body's axes and phi its centre of mass, a point's body coordinates are
/// xi = D^T (x - phi), the cylinder is fixed there (axis a, radius R through the centre), and each
/// anchor is kept as body coordinates alpha, so that a sticking point turns with the drum. The
/// spring's force F = k_t D e1 acts on the beam's point and, opposite, on the body at the same
/// place, phi + D xi = x (the body's phi takes -F, its d_k take -xi_k F): the pair has no net force
/// and no moment. (At the anchor instead, the body's share would change when an accepted step
/// moves the anchor, and the energy balance would count another force than the step's.) Its
/// derivatives with respect to the point and the body's 12 coordinates come by forward-mode
/// automatic differentiation.
template <int W>
class DrumFriction final : public BeamOnBodyElements<W, 12>, public PointHistory<4>, public OutputSource {
  using Base = BeamOnBodyElements<W, 12>;
  static constexpr int kBody = 12, kVars = 3 + kBody, kDofs = Base::kDofs;
  static constexpr int kPerPoint = 4;  // alpha, then the state
  static constexpr double kFree = 0.0, kStuck = 1.0, kSlipped = 2.0;
  using typename Base::Point;
  using typename Base::VecY;
  using typename Base::MatY;
  using Vars = Eigen::Matrix<double, kVars, 1>;
  using AD = Eigen::AutoDiffScalar<Vars>;
  template <class T>
  using Vec3 = Eigen::Matrix<T, 3, 1>;

 public:
  DrumFriction(int beam, int body, const Model& m, const EffectParams& p, const std::string& label,
               const Eigen::Vector3d& axis, double radius)
      : Base(beam, body), law_(bed(p)), mu_(p.number("mu")), axis_(axis), R_(radius), label_(label) {
    if (!(mu_ > 0.0)) throw ParamError("mu", "friction on a contact needs mu > 0");
    if (p.num.count("mu_axial") || p.num.count("mu_transverse"))
      throw ParamError(p.num.count("mu_axial") ? "mu_axial" : "mu_transverse",
                       "friction on a shape carried by a body takes one mu (along and across alike) so far");
    kt_ = tangential_stiffness(p, law_.k);
    size_history(m.beam(beam).n_spans(), Base::n_points(m.beam(beam)));
  }
  std::string type() const override { return "contact_friction"; }
  std::string label() const override { return label_; }

  void distribute(const Model& m) override {
    Base::distribute(m);
    own_spans(m.beam(this->beam_).n_spans(), this->elements_);
  }

  PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const override {
    PetscFunctionBeginUser;
    if (!acts(ctx)) PetscFunctionReturn(0);
    for (int e : this->elements_) {
      VecY re = VecY::Zero();
      element(ctx, e, re, nullptr);
      this->scatter(ctx, e, re, r);
    }
    PetscFunctionReturn(0);
  }
  PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const override {
    PetscFunctionBeginUser;
    if (!acts(ctx)) PetscFunctionReturn(0);
    for (int e : this->elements_) {
      VecY re = VecY::Zero();
      MatY K = MatY::Zero();
      if (!element(ctx, e, re, &K)) continue;  // no point in contact: the body's columns stay off this span
      const auto d = this->dofs(ctx.map, ctx.model, e);
      PetscCall(J.add(kDofs, d.data(), kDofs, d.data(), K.data()));
    }
    PetscFunctionReturn(0);
  }
  void commit(const EvalContext& ctx) override {
    if (!acts(ctx)) return;
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      const VecY y1 = this->gather(ctx, ctx.x, e), y0 = this->gather(ctx, ctx.x_old, e);
      for (int g = 0; g < points_; ++g) {
        const Point q = Base::point(b, e, g);
        double* h = slot(e, g);
        const Vars s1 = stack(Base::position(q, y1), y1);
        Vec3<double> e1;
        Vars f;
        bool slipped = false;
        if (!law(s1, anchor(h, q, y0), f, e1, slipped)) {
          for (int k = 0; k < kPerPoint; ++k) h[k] = 0.0;
          continue;
        }
        const Vec3<double> held = body_coordinates(s1) - e1;
        for (int k = 0; k < 3; ++k) h[k] = held(k);
        h[3] = slipped ? kSlipped : kStuck;
      }
    }
  }
  double energy(const EvalContext& ctx) const override {
    double U = 0.0;
    at_anchored(ctx, [&](double w, const Vec3<double>& e, const Vars&, double) { U += 0.5 * w * kt_ * e.squaredNorm(); });
    return U;
  }
  std::vector<std::string> output_names() const override {
    return {"force.x", "force.y", "force.z", "sticking", "slipping"};
  }
  void outputs(const EvalContext& ctx, double* values) const override {
    at_anchored(ctx, [&](double w, const Vec3<double>& e, const Vars& s, double state) {
      const Vec3<double> F = -w * kt_ * (e(0) * s.segment<3>(6) + e(1) * s.segment<3>(9) + e(2) * s.segment<3>(12));
      for (int k = 0; k < 3; ++k) values[k] += F(k);
      values[state == kSlipped ? 4 : 3] += w;
    });
  }

 private:
  static bool acts(const EvalContext& ctx) { return ctx.h > 0.0 && ctx.scheme != StepScheme::Static; }
  static Vars stack(const Eigen::Vector3d& x, const VecY& y) {
    Vars s;
    s << x, y.template tail<kBody>();
    return s;
  }
  /// xi = D^T (x - phi) at s = (x, phi, d1, d2, d3).
  template <class T>
  static Vec3<T> body_coordinates(const Eigen::Matrix<T, kVars, 1>& s) {
    const Vec3<T> z = s.template segment<3>(0) - s.template segment<3>(3);
    return {s.template segment<3>(6).dot(z), s.template segment<3>(9).dot(z), s.template segment<3>(12).dot(z)};
  }
  /// The return map at s held at body coordinates alpha: the residual-sign force on (x, phi, d1,
  /// d2, d3) and the elastic slip e1 in body coordinates. false: not in contact.
  template <class T>
  bool law(const Eigen::Matrix<T, kVars, 1>& s, const Vec3<double>& alpha, Eigen::Matrix<T, kVars, 1>& f, Vec3<T>& e1,
           bool& slipped) const {
    const Vec3<T> xi = body_coordinates(s);
    const Vec3<T> a = axis_.cast<T>();
    const Vec3<T> y = xi - a.dot(xi) * a;
    const T r = y.norm(), g = r - T(R_);
    if (!(value(g) < 0.0)) return false;
    const T N = -T(law_.k) * g;
    const Vec3<T> n = y / r, d = xi - alpha.cast<T>();
    const Vec3<T> e = d - n.dot(d) * n;
    const T phi = T(kt_ / mu_) * e.norm();
    slipped = value(phi) > value(N) * (1.0 + kTie);
    e1 = slipped ? Vec3<T>((N / phi) * e) : e;
    const Vec3<T> F = T(kt_) * (e1(0) * s.template segment<3>(6) + e1(1) * s.template segment<3>(9) +
                                e1(2) * s.template segment<3>(12));
    f.template segment<3>(0) = F;
    f.template segment<3>(3) = -F;
    for (int k = 0; k < 3; ++k) f.template segment<3>(6 + 3 * k) = -xi(k) * F;  // at the point: phi + D xi = x
    return true;
  }
  static double value(double v) { return v; }
  static double value(const AD& v) { return v.value(); }
  /// re += span e's friction forces, K += their derivatives with respect to the step's end;
  /// false if no point is in contact.
  bool element(const EvalContext& ctx, int e, VecY& re, MatY* K) const {
    const Beam& b = ctx.model.beam(this->beam_);
    const VecY y1 = this->gather(ctx, ctx.x, e), y0 = this->gather(ctx, ctx.x_old, e);
    bool any = false;
    for (int g = 0; g < points_; ++g) {
      const Point q = Base::point(b, e, g);
      const Vec3<double> alpha = anchor(slot(e, g), q, y0);
      const Vars s1 = stack(Base::position(q, y1), y1);
      Vars f;
      Eigen::Matrix<double, kVars, kVars> S;
      bool slipped = false;
      if (K) {
        Eigen::Matrix<AD, kVars, 1> sa, fa;
        for (int i = 0; i < kVars; ++i) sa(i) = AD(s1(i), kVars, i);
        Vec3<AD> e1;
        if (!law(sa, alpha, fa, e1, slipped)) continue;
        for (int i = 0; i < kVars; ++i) {
          f(i) = fa(i).value();
          S.row(i) = fa(i).derivatives().transpose();
        }
      } else {
        Vec3<double> e1;
        if (!law(s1, alpha, f, e1, slipped)) continue;
      }
      any = true;
      Base::spread(q, f, S, re, K);
    }
    return any;
  }
  /// A point's anchor in body coordinates: as committed, or where it was at the step's start.
  Vec3<double> anchor(const double* h, const Point& q, const VecY& y0) const {
    if (h[3] != kFree) return {h[0], h[1], h[2]};
    return body_coordinates(stack(Base::position(q, y0), y0));
  }
  /// f(weight, elastic slip in body coordinates, the point's (x, body) state, state) at every
  /// anchored point of this rank's elements, in the state x.
  template <class F>
  void at_anchored(const EvalContext& ctx, F&& f) const {
    const Beam& b = ctx.model.beam(this->beam_);
    for (int e : this->elements_) {
      const VecY y = this->gather(ctx, ctx.x, e);
      for (int g = 0; g < points_; ++g) {
        const double* h = slot(e, g);
        if (h[3] == kFree) continue;
        const Point q = Base::point(b, e, g);
        const Vars s = stack(Base::position(q, y), y);
        const Vec3<double> xi = body_coordinates(s);
        const Vec3<double> yv = xi - axis_.dot(xi) * axis_, n = yv.normalized();
        const Vec3<double> d = xi - Vec3<double>(h[0], h[1], h[2]);
        f(q.w, Vec3<double>(d - n.dot(d) * n), s, h[3]);
      }
    }
  }

  Penalty law_;
  double mu_, kt_ = 0.0;
  Eigen::Vector3d axis_;  // in body components
  double R_;
  std::string label_;
};

/// Friction on the [[contact]] entry's shape: fixed, or a cylinder carried by a body.
std::unique_ptr<Effect> make_contact_friction(const Model& m, const EffectParams& p) {
  if (!p.num.count("body")) return make_on_fixed_shape<ContactFriction>(m, p, "mu");
  if (p.string("shape") != "cylinder")
    throw ParamError("mu", "friction on a sphere carried by a body is not supported yet: leave `mu` out");
  const int beam = beam_param(m, p), body = carrier_body(m, p, "cylinder");
  const Beam& B = m.beam(body);
  Eigen::Matrix3d D;
  for (int i = 0; i < 3; ++i) D.col(i) = Eigen::Map<const Eigen::Vector3d>(B.q_ref().data() + 3 + 3 * i);
  const Eigen::Vector3d axis = D.transpose() * unit_vector_param(p, "axis", "the cylinder's axis");
  const std::string label = p.string("label");
  if (m.beam(beam).is_ancf()) return std::make_unique<DrumFriction<4>>(beam, body, m, p, label, axis, contact_radius(p));
  return std::make_unique<DrumFriction<3>>(beam, body, m, p, label, axis, contact_radius(p));
}

}  // namespace

void register_contact_friction_effects(EffectRegistry& r) {
  EffectSpec s = model_effect_spec("contact_friction", EnergyRole::Dissipative,
                                   "Coulomb friction between a beam and a fixed [[contact]] shape (the entry's mu > "
                                   "0): each point in contact sticks to its anchor on the shape by a tangential "
                                   "spring capped at mu N",
                                   "potential");
  s.rate_force = true;  // none outside a step: HHT weights it by 1, as the rate forces
  r.add(s, [](const Model& m, const EffectParams& p) { return make_contact_friction(m, p); });
}

}  // namespace slidebeam::effects
