// SPDX-License-Identifier: MIT
#pragma once
/// @file Element kernels of the director beam (docs/theory.md, "The director beam").
///
/// Every strain of both measures is a bilinear form c * z_a . z_b in the field vector at a
/// quadrature point, z = (phi', d1, d2, d3, d1', d2', d3', d1'', d2'', d3'') in R^30. One table of such terms per
/// measure therefore gives the strain, its gradient B = d eps/dz (linear in z) and its Hessian
/// (constant), and so the energy, the internal force and the exact tangent. The same property
/// makes the averaged-strain energy-momentum scheme exact. The one exception, the turning term of
/// the assumed-strain beam's curvature (point_strains), is a cross product of two such forms and
/// is written out beside the tables.
///
/// Pure functions of local data: no PETSc, no MPI, no heap allocation.

#include <Eigen/Dense>
#include <array>

namespace slidebeam::kernels {

enum class StrainMeasure { SimoReissner, Seed };
/// Stiffness quadrature of a span: 3-point Gauss (full), 2-point Gauss (reduced), or 3-point Gauss
/// with the assumed membrane and shear strains at the knots (span_gamma_moments; locking-free,
/// docs/theory.md).
enum class Quadrature { Full, Reduced, AssumedStrain };

/// Blocks of the field vector z at a quadrature point.
/// (The second derivatives enter only the director-interpolation correction of point_table.)
enum FieldBlock : int {
  kPhiS = 0, kD1 = 1, kD2 = 2, kD3 = 3, kD1S = 4, kD2S = 5, kD3S = 6, kD1SS = 7, kD2SS = 8, kD3SS = 9
};
constexpr int kNz = 30;       ///< size of z
constexpr int kNq = 12;       ///< coordinates per control point: phi, d1, d2, d3
constexpr int kNqEl = 3 * kNq;  ///< coordinates of a quadratic span (3 control points)

using Vec6 = Eigen::Matrix<double, 6, 1>;
using VecZ = Eigen::Matrix<double, kNz, 1>;
using Mat6Z = Eigen::Matrix<double, 6, kNz>;
using VecEl = Eigen::Matrix<double, kNqEl, 1>;
/// (row-major: the layout the global assembly takes)
using MatEl = Eigen::Matrix<double, kNqEl, kNqEl, Eigen::RowMajor>;
using MatZEl = Eigen::Matrix<double, kNz, kNqEl>;
using Vec12 = Eigen::Matrix<double, kNq, 1>;
using Mat12 = Eigen::Matrix<double, kNq, kNq>;
using Mat6x12 = Eigen::Matrix<double, 6, kNq>;

/// c * z_a . z_b
struct BilinearTerm {
  int a;
  int b;
  double c;
};
/// One strain component: a sum of at most four bilinear terms.
struct QuadraticForm {
  int n_terms;
  std::array<BilinearTerm, 4> terms;
};
/// Six strains in the order (axial, shear 2, shear 3, torsion, bending about d2, bending about d3),
/// matching the stiffness diag(EA, kGA2, kGA3, GJ, EI2, EI3).
using StrainTable = std::array<QuadraticForm, 6>;

/// The table of a strain measure (without constants: reference strains are subtracted instead).
const StrainTable& strain_table(StrainMeasure m);

/// Section stiffness diag(EA, kGA2, kGA3, GJ, EI2, EI3).
using Stiffness = Vec6;

/// Quadratic forms: value, gradient, and Hessian accumulation. Shared by strains and constraints.
template <int N>
double form_value(const QuadraticForm& f, const Eigen::Matrix<double, N, 1>& z) {
  double v = 0.0;
  for (int t = 0; t < f.n_terms; ++t) {
    const auto& T = f.terms[t];
    v += T.c * z.template segment<3>(3 * T.a).dot(z.template segment<3>(3 * T.b));
  }
  return v;
}
template <int N>
void form_gradient(const QuadraticForm& f, const Eigen::Matrix<double, N, 1>& z,
                   Eigen::Ref<Eigen::Matrix<double, 1, N>, 0, Eigen::InnerStride<>> g) {
  g.setZero();
  for (int t = 0; t < f.n_terms; ++t) {
    const auto& T = f.terms[t];
    g.template segment<3>(3 * T.a) += T.c * z.template segment<3>(3 * T.b).transpose();
    g.template segment<3>(3 * T.b) += T.c * z.template segment<3>(3 * T.a).transpose();
  }
}
/// H += w * d^2 f / dz^2
template <int N>
void form_add_hessian(const QuadraticForm& f, double w, Eigen::Matrix<double, N, N>& H) {
  for (int t = 0; t < f.n_terms; ++t) {
    const auto& T = f.terms[t];
    for (int k = 0; k < 3; ++k) {
      H(3 * T.a + k, 3 * T.b + k) += w * T.c;
      H(3 * T.b + k, 3 * T.a + k) += w * T.c;
    }
  }
}

/// Basis data of one quadrature point of a span: N, dN/ds and d2N/ds2 (already divided by the
/// parameter-to-arc-length factor) and the integration weight in arc length. corrected: the
/// point's strains carry the director-interpolation correction of point_table, with the weight
/// bspline::director_correction_weight (arc length squared).
struct GaussPoint {
  std::array<double, 3> N;
  std::array<double, 3> dN;
  double w;
  std::array<double, 3> ddN{};
  double correction_weight = 0.0;
  bool corrected = false;
  double t = 0.0;  ///< position in the span, 0 at its left knot, 1 at its right
};

constexpr int kSpanLanes = 4;  ///< at most this many quadrature points per span

/// Map z = P q from the 36 coordinates of a span's control points to the field vector.
MatZEl field_map(const GaussPoint& gp);
/// z = field_map(gp) * q, block by block (without forming the map).
VecZ field_values(const GaussPoint& gp, const VecEl& q);

/// The strain table at a quadrature point. The measure's own table, except for corrected points of
/// the Simo-Reissner measure (assumed strains), where the axial strain is the centre line's,
/// 1/2 (phi'.phi' - 1), and the shear and curvature compensate to leading order the stretch of
/// directors interpolated between orthonormal control points (theory.md, "director interpolation"):
///   Gamma_i - 1/2 d_i . d_1 (i = 2, 3)  and  K_i + c K_i(d', d''),
/// K_i(d', d'') being the curvature form with d' in place of d and d'' in place of d', c the
/// point's correction_weight. All are still quadratic forms in the coordinates and objective, so
/// everything built on the tables (exact energy-momentum, frame indifference, the exact tangent)
/// holds unchanged.
StrainTable point_table(const StrainTable& T, const GaussPoint& gp);
/// Strains at z of the table given (without the turning term: point_strains gives a point's).
Vec6 strains(const StrainTable& T, const VecZ& z);
/// The strains of a quadrature point at z: those of point_table(T, gp), and at corrected points
/// of the Simo-Reissner measure the turning term (c/2) K x K' added to the curvature, K and K' the
/// curvature forms K(d, d') and K(d, d'') (theory.md, "The turning term"). It is a product of two
/// quadratic forms; the kernels below differentiate it exactly and give it the product rule's
/// discrete gradient in energy-momentum steps, which keeps those exact.
Vec6 point_strains(const StrainTable& T, const GaussPoint& gp, const VecZ& z);

/// Gauss-Legendre points and weights on [0,1] for a quadrature rule (3 = full, 2 = reduced).
int gauss_rule(Quadrature q, std::array<double, 3>& x, std::array<double, 3>& w);

/// Strain energy of one quadrature point: w/2 (eps - eps0)^T C (eps - eps0).
double beam_gp_energy(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                      const VecEl& q);

/// Internal force of one quadrature point, r += w B(q)^T C (eps(q) - eps0) with B = d eps/dq,
/// and (if K is given) the exact tangent K += d r/dq = w [B^T C B + sum_k sigma_k d^2 eps_k/dq^2].
/// gamma_sigma (may be null): the point's Gamma stresses given from outside (the knots' assumed
/// strains); they replace its own, and the tangent keeps only their geometric terms.
void beam_gp_residual_tangent(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                              const VecEl& q, VecEl& r, MatEl* K, const Eigen::Vector3d* gamma_sigma = nullptr);

/// Energy-momentum internal force of one quadrature point (docs/theory.md, "The schemes"): the
/// gradient at the midpoint q_m = (q0 + q1)/2 with the AVERAGED strain,
/// r += w B(q_m)^T C (1/2 (eps(q0) + eps(q1)) - eps0), so that U(q1) - U(q0) = r . (q1 - q0) exactly.
/// K (if given) += d r / d q1 = w [1/2 sum_k sigma_k d^2 eps_k/dq^2 + (1+xi)/2 B(q_m)^T C B(q1)].
/// xi > 0 (energy-decaying variant): the strain in sigma becomes eps_avg + xi/2 (eps(q1) - eps(q0)),
/// so the step dissipates xi/2 w (deps)^T C deps >= 0, most in the fast (stiff) modes, and still
/// conserves momentum (the force is still B(q_m)^T sigma of frame-indifferent strains).
/// gamma_sigma: as for beam_gp_residual_tangent (the step's Gamma stresses).
void beam_gp_residual_tangent_em(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                                 const VecEl& q0, const VecEl& q1, VecEl& r, MatEl* K, double xi = 0.0,
                                 const Eigen::Vector3d* gamma_sigma = nullptr);

/// The assumed membrane and shear strains (quadrature = "assumed_strain"). The first three
/// strains, Gamma (axial and the two shears), enter the energy only through their weighted means
/// at the knots, b_i = int H_i (Gamma - Gamma_ref) ds / m_i with H_i the piecewise-linear hat of
/// knot i and m_i = int H_i ds: W_Gamma = 1/2 sum_i m_i b_i^T C_Gamma b_i (the lumped projection
/// onto continuous piecewise-linear strains). The b_i are fixed linear combinations of point
/// strains, so they stay quadratic forms in the coordinates. A span contributes to its two knots
/// the moments sum_g w_g H(x_g) (Gamma_g - Gamma_ref,g), H = 1 - t (left) and t (right) with t the
/// point's position in the span (GaussPoint::t).
struct GammaMoments {
  Eigen::Vector3d left = Eigen::Vector3d::Zero(), right = Eigen::Vector3d::Zero();
};
GammaMoments span_gamma_moments(const StrainTable& T, const GaussPoint* gps, const Vec6* eps0, int n,
                                const VecEl& q);
/// The derivatives d/dq of a span's moments toward its left and right knots at q (3 x 36 each).
using Mat3El = Eigen::Matrix<double, 3, kNqEl>;
void span_gamma_moment_gradients(const StrainTable& T, const GaussPoint* gps, int n, const VecEl& q, Mat3El& left,
                                 Mat3El& right);

/// Whole-span versions of the three point kernels above, over the span's n quadrature points.
/// gamma_sigma (may be null): the Gamma stresses at the points, C_Gamma times the assumed strains
/// interpolated from the knots; they replace the points' own, and the tangent then holds the
/// Gamma part's geometric terms only (its material part couples the knot's spans:
/// span_gamma_moment_gradients). span_energy with gamma_sigma counts torsion and bending only.
double span_energy(const StrainTable& T, const Stiffness& C, const GaussPoint* gps, const Vec6* eps0, int n,
                   bool gamma_from_knots, const VecEl& q);
void span_residual_tangent(const StrainTable& T, const Stiffness& C, const GaussPoint* gps, const Vec6* eps0, int n,
                           const Eigen::Vector3d* gamma_sigma, const VecEl& q, VecEl& r, MatEl* K);
/// Energy-momentum: gamma_sigma holds the step's Gamma stresses (from the knots' averaged strains).
void span_residual_tangent_em(const StrainTable& T, const Stiffness& C, const GaussPoint* gps, const Vec6* eps0,
                              int n, const Eigen::Vector3d* gamma_sigma, const VecEl& q0, const VecEl& q1, VecEl& r,
                              MatEl* K, double xi = 0.0);

/// Kelvin-Voigt damping of a span's points: the viscous stresses sigma_k = c_k (eps_k(q1) -
/// eps_k(q0)) / h, c the damping per strain (tau C), and r += w P^T sum_k sigma_k d eps_k/dz at the
/// force state z_f = (1 - theta) z(q0) + theta z(q1); (if K is given) K += d r / d q1 = w P^T
/// [theta sum_k sigma_k d^2 eps_k/dz^2 + sum_k (c_k / h) (d eps_k/dz (z_f))^T d eps_k/dz (z(q1))] P.
/// gamma_sigma (may be null): the points' Gamma stresses given from outside (the knots'); they
/// replace the points' own, and the tangent then leaves out their material part (it couples a
/// knot's spans). The points' strains are those of point_table (no turning term).
void span_kelvin_voigt(const StrainTable& T, const GaussPoint* gps, int n, const Vec6& c,
                       const Eigen::Vector3d* gamma_sigma, double h, double theta, const VecEl& q0, const VecEl& q1,
                       VecEl& r, MatEl* K);

/// What an energy-momentum step needs of one span at q_n, for span_residual_em: its quadrature
/// points' basis and weights, z(q_n), eps(q_n) and the reference strains, point g in lane g
/// (unused lanes zero, weight 0). Constant during a step: computed once per step.
struct alignas(32) SpanEmState {
  double N[3][kSpanLanes], dN[3][kSpanLanes], w[kSpanLanes];
  double ddN[3][kSpanLanes], correction_weight[kSpanLanes];  ///< corrected points only (point_table)
  bool corrected;
  double z0[kNz][kSpanLanes];
  double k0[3][kSpanLanes], kp0[3][kSpanLanes];  ///< K(d, d') and K(d, d'') at q_n (corrected points)
  double e0[6][kSpanLanes];
  double eps0[6][kSpanLanes];
};
/// gps and eps0: the span's n_gp <= kSpanLanes quadrature points and their reference strains.
SpanEmState span_em_state(const StrainTable& T, const GaussPoint* gps, const Vec6* eps0, int n_gp, const VecEl& q0);

/// The energy-momentum internal force of one span, r += that of span_residual_tangent_em
/// (without the tangent), from the span's cached state at q_n. The points are computed together
/// in SIMD lanes and the strain measure's terms are written out: this runs in every Newton
/// iteration of every span. gamma_sigma (may be null): the points' Gamma stresses, component k of
/// point g in gamma_sigma[k][g].
void span_residual_em(const StrainTable& T, const Stiffness& C, const SpanEmState& s, const VecEl& q1, VecEl& r,
                      double xi = 0.0, const double (*gamma_sigma)[kSpanLanes] = nullptr);

/// Orthonormality constraints of one control point (seed eq. 2), as quadratic forms in the
/// control point's 12 coordinates (blocks phi, d1, d2, d3).
const std::array<QuadraticForm, 6>& orthonormality_forms();
Vec6 orthonormality(const Vec12& q);
Mat6x12 orthonormality_jacobian(const Vec12& q);
/// sum_k lambda_k d^2 Phi_k / dq^2
Mat12 orthonormality_hessian(const Vec6& lambda);
/// The six orthonormality forms pair the director slots (d1, d2, d3): form r is
/// c d_{kA[r]} . d_{kB[r]}, in the order 1/2 d1.d1, 1/2 d2.d2, 1/2 d3.d3, d1.d2, d1.d3, d2.d3.
/// Its gradient puts d_{kB[r]} in slot kA[r] and d_{kA[r]} in slot kB[r] (once for a square).
constexpr int kTriadPairA[6] = {0, 1, 2, 0, 0, 1};
constexpr int kTriadPairB[6] = {0, 1, 2, 1, 2, 2};

/// The residual rows of one control point's constraints, written out (they are in every Newton
/// iteration): r += G(qf)^T lambda on the coordinates, g += Phi(q) on the multiplier rows.
inline void orthonormality_residual(const double* q, const double* qf, const double* lambda, double* r, double* g) {
  auto dot = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  for (int k = 0; k < 6; ++k) {
    const int a = kTriadPairA[k], b = kTriadPairB[k];
    const double* da = q + 3 + 3 * a;
    const double* db = q + 3 + 3 * b;
    g[k] += a == b ? 0.5 * (dot(da, da) - 1.0) : dot(da, db);
    for (int c = 0; c < 3; ++c) {
      r[3 + 3 * a + c] += lambda[k] * qf[3 + 3 * b + c];
      if (b != a) r[3 + 3 * b + c] += lambda[k] * qf[3 + 3 * a + c];
    }
  }
}

/// Multipliers of one triad that leave its force rows no component along G^T, where the forces
/// are s G^T lambda + (terms free of lambda) and G is the constraint Jacobian at the directors d
/// (rows d1, d2, d3): dlambda = -(G G^T)^-1 G f / s, then f += s G^T dlambda and lambda +=
/// dlambda. f points to the three director blocks of the force rows. Exact, since the residual
/// is linear in lambda; G G^T is SPD near an orthonormal triad.
void orthonormality_multiplier_update(const double (&d)[3][3], double* const (&f)[3], double* lambda, double s);

/// Replace the three columns of d (d1, d2, d3, contiguous) by the closest orthonormal frame,
/// the polar factor: Newton-Schulz iterations from a nearly orthonormal frame, an SVD otherwise.
/// A degenerate frame or a reflection is left alone.
void closest_orthonormal_frame(double* d);

}  // namespace slidebeam::kernels
