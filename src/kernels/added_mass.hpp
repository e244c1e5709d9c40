// SPDX-License-Identifier: MIT
#pragma once
/// @file Point kernels of the added mass of a line in a fluid: the kinetic energy of the water a
/// rope or chain carries with it, per unit reference length
///
///   T_a = 1/2 v^T A(b) v,   A(b) = m_n (I - P) + m_t P,   P = b b^T / (b . b),
///
/// b = x' the centre line's tangent, v its velocity, m_n = C_n rho pi D^2 / 4 and m_t = C_t rho pi
/// D^2 / 4 (normal and tangential added-mass coefficients C_n, C_t). Lagrange's equations give the
/// point forces f_r (on the position, weighted by the shape functions N) and f_b (on the tangent,
/// weighted by N'): f_r = d/dt (A v), f_b = -dT_a/db.
///
/// Energy-momentum and midpoint: f_r = (A(b1) v1 - A(b0) v0) / h and f_b = -g, g a discrete
/// gradient of psi(b) = 1/2 v0^T A(b) v1 (the velocities of both ends held): g . (b1 - b0) =
/// psi(b1) - psi(b0) exactly. With (b1 - b0) = h N' (v0 + v1) / 2 and (r1 - r0) = h (v0 + v1) / 2
/// the work of (f_r, f_b) over the step is T_a(b1, v1) - T_a(b0, v0): the step conserves the
/// kinetic energy it adds, for any step size. The quotient psi = n / d (n = (b . v0)(b . v1), d =
/// b . b, both quadratic in b, so their midpoint gradients are exact discrete gradients) has the
/// discrete gradient
///
///   g = 1/2 (m_t - m_n) [(d0 + d1) / 2 grad n(bm) - (n0 + n1) / 2 grad d(bm)] / (d0 d1),
///
/// bm = (b0 + b1) / 2 (n1 / d1 - n0 / d0 = [(n1 - n0) (d0 + d1) / 2 - (n0 + n1) / 2 (d1 - d0)] /
/// (d0 d1)), with no division by |b1 - b0|.
///
/// Newmark and HHT: Lagrange's equations at the step's end, f_r = A(b1) a1 + dA(b1)[b'1] v1,
/// f_b = -dT_a/db(b1, v1), with Newmark's a1, v1 (and the tangent's rates b'1, likewise).
///
/// Pure functions of local data (templated on the scalar for automatic differentiation).

#include <Eigen/Dense>

namespace slidebeam::kernels::added_mass {

template <class S>
using Vec3 = Eigen::Matrix<S, 3, 1>;

/// Added mass per unit reference length across (m_n) and along (m_t) the line.
struct Coefficients {
  double m_n = 0.0, m_t = 0.0;
};

/// A(b) v.
template <class S, class T>
Vec3<S> apply(const Coefficients& c, const Vec3<T>& b, const Vec3<S>& v) {
  const S bv = b.template cast<S>().dot(v);
  const S bb = S(b.squaredNorm());
  return c.m_n * v + ((c.m_t - c.m_n) * bv / bb) * b.template cast<S>();
}

/// A(b) itself.
inline Eigen::Matrix3d matrix(const Coefficients& c, const Vec3<double>& b) {
  return c.m_n * Eigen::Matrix3d::Identity() + ((c.m_t - c.m_n) / b.squaredNorm()) * b * b.transpose();
}

/// The point forces of one step under energy-momentum or midpoint: from the start's position
/// r0, tangent b0 and velocity v0 to the end's r1, b1 (v1 = 2 (r1 - r0) / h - v0).
template <class S>
void midpoint_forces(const Coefficients& c, double h, const Vec3<double>& r0, const Vec3<double>& b0,
                     const Vec3<double>& v0, const Vec3<S>& r1, const Vec3<S>& b1, Vec3<S>& f_r, Vec3<S>& f_b) {
  const Vec3<S> v1 = (2.0 / h) * (r1 - r0.template cast<S>()) - v0.template cast<S>();
  const Vec3<S> v0s = v0.template cast<S>(), b0s = b0.template cast<S>();
  f_r = (apply(c, b1, v1) - apply(c, b0, v0).template cast<S>()) / h;
  const Vec3<S> bm = 0.5 * (b0s + b1);
  const S n0 = b0s.dot(v0s) * b0s.dot(v1), n1 = b1.dot(v0s) * b1.dot(v1);
  const S d0 = S(b0.squaredNorm()), d1 = b1.squaredNorm();
  const Vec3<S> grad_n = v0s * v1.dot(bm) + v1 * v0s.dot(bm);
  const Vec3<S> g = (0.5 * (d0 + d1) * grad_n - (n0 + n1) * bm) / (d0 * d1);
  f_b = -0.5 * (c.m_t - c.m_n) * g;
}

/// midpoint_forces with its derivatives with respect to the end's position r1 and tangent b1,
/// by hand (the residual's kernel, differentiated; checked against finite differences with the
/// step's Jacobian).
struct PointTangent {
  Eigen::Matrix3d fr_r, fr_b, fb_r, fb_b;
};

inline PointTangent midpoint_tangent(const Coefficients& c, double h, const Vec3<double>& r0, const Vec3<double>& b0,
                                     const Vec3<double>& v0, const Vec3<double>& r1, const Vec3<double>& b1,
                                     Vec3<double>& f_r, Vec3<double>& f_b) {
  using M3 = Eigen::Matrix3d;
  const M3 I = M3::Identity();
  const double dm = c.m_t - c.m_n;
  const Vec3<double> v1 = (2.0 / h) * (r1 - r0) - v0;
  const double d0 = b0.squaredNorm(), d1 = b1.squaredNorm(), bv1 = b1.dot(v1);
  f_r = (apply(c, b1, v1) - apply(c, b0, v0)) / h;
  const Vec3<double> bm = 0.5 * (b0 + b1);
  const double n0 = b0.dot(v0) * b0.dot(v1), n1 = b1.dot(v0) * b1.dot(v1);
  const Vec3<double> grad_n = v0 * v1.dot(bm) + v1 * v0.dot(bm);
  const double D = d0 * d1;
  const Vec3<double> num = 0.5 * (d0 + d1) * grad_n - (n0 + n1) * bm;
  const Vec3<double> g = num / D;
  f_b = -0.5 * dm * g;
  PointTangent t;
  t.fr_r = (2.0 / (h * h)) * matrix(c, b1);  // d v1 / d r1 = 2 / h
  t.fr_b = (dm / h) * (b1 * v1.transpose() / d1 + (bv1 / d1) * I - (2.0 * bv1 / (d1 * d1)) * b1 * b1.transpose());
  // g through v1 (d/dr1 = 2/h d/dv1) and through b1 (bm, n1, d1)
  const M3 num_v = 0.5 * (d0 + d1) * (v0 * bm.transpose() + v0.dot(bm) * I) -
                   bm * (b0.dot(v0) * b0.transpose() + b1.dot(v0) * b1.transpose());
  const M3 num_b = grad_n * b1.transpose() + 0.25 * (d0 + d1) * (v0 * v1.transpose() + v1 * v0.transpose()) -
                   bm * (b1.dot(v1) * v0.transpose() + b1.dot(v0) * v1.transpose()) - 0.5 * (n0 + n1) * I;
  t.fb_r = (-0.5 * dm * (2.0 / h) / D) * num_v;
  t.fb_b = (-0.5 * dm / D) * (num_b - g * (2.0 * d0) * b1.transpose());
  return t;
}

/// The start of a Newmark step at a point: position, velocity and acceleration of the centre
/// line (r, v, a) and of its tangent (b, vb, ab).
struct NewmarkStart {
  Vec3<double> r, v, a, b, vb, ab;
};

/// The point forces of one step under Newmark or HHT (Lagrange's equations at the end r1, b1).
template <class S>
void endpoint_forces(const Coefficients& c, double h, double beta, double gamma, const NewmarkStart& s,
                     const Vec3<S>& r1, const Vec3<S>& b1, Vec3<S>& f_r, Vec3<S>& f_b) {
  const double c0 = 1.0 / (beta * h * h), ca = 1.0 / (2.0 * beta) - 1.0;
  const auto rates = [&](const Vec3<S>& x1, const Vec3<double>& x0, const Vec3<double>& v0, const Vec3<double>& a0,
                         Vec3<S>& v1, Vec3<S>& a1) {
    a1 = c0 * (x1 - (x0 + h * v0).template cast<S>()) - (ca * a0).template cast<S>();
    v1 = (v0 + h * (1.0 - gamma) * a0).template cast<S>() + (h * gamma) * a1;
  };
  Vec3<S> v1, a1, vb1, ab1;
  rates(r1, s.r, s.v, s.a, v1, a1);
  rates(b1, s.b, s.vb, s.ab, vb1, ab1);
  const S bb = b1.squaredNorm(), bv = b1.dot(v1), bvb = b1.dot(vb1);
  const double dm = c.m_t - c.m_n;
  // dP[vb] v = (vb (b . v) + b (vb . v)) / |b|^2 - 2 (b . vb)(b . v) b / |b|^4
  const Vec3<S> dPv = (vb1 * bv + b1 * vb1.dot(v1)) / bb - (2.0 * bvb * bv / (bb * bb)) * b1;
  f_r = apply(c, b1, a1) + dm * dPv;
  f_b = -dm * ((bv / bb) * v1 - (bv * bv / (bb * bb)) * b1);
}

}  // namespace slidebeam::kernels::added_mass
