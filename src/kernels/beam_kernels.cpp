// SPDX-License-Identifier: MIT
#include "kernels/beam_kernels.hpp"

#include <cmath>

namespace slidebeam::kernels {

namespace {
// Betsch & Steinmann (2002) objective director strains:
//   Gamma_i = d_i . phi' (- delta_i1), K_1 = 1/2 (d3.d2' - d2.d3'), K_2 = 1/2 (d1.d3' - d3.d1'),
//   K_3 = 1/2 (d2.d1' - d1.d2').
const StrainTable kSimoReissner = {{
    {1, {{{kD1, kPhiS, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kD2, kPhiS, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kD3, kPhiS, 1.0}, {0, 0, 0.0}}}},
    {2, {{{kD3, kD2S, 0.5}, {kD2, kD3S, -0.5}}}},
    {2, {{{kD1, kD3S, 0.5}, {kD3, kD1S, -0.5}}}},
    {2, {{{kD2, kD1S, 0.5}, {kD1, kD2S, -0.5}}}},
}};
// The seed's small-strain Green-Lagrange measure, corrected (formulation.md section 3):
//   eps = 1/2 phi'.phi' (- 1/2), gamma_a = phi'.d_a, kappa1 = 1/2 (d2'.d3 - d3'.d2),
//   kappa2 = phi'.d3', kappa3 = phi'.d2'.
const StrainTable kSeed = {{
    {1, {{{kPhiS, kPhiS, 0.5}, {0, 0, 0.0}}}},
    {1, {{{kPhiS, kD2, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kPhiS, kD3, 1.0}, {0, 0, 0.0}}}},
    {2, {{{kD2S, kD3, 0.5}, {kD3S, kD2, -0.5}}}},
    {1, {{{kPhiS, kD3S, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kPhiS, kD2S, 1.0}, {0, 0, 0.0}}}},
}};
// Blocks of one control point's coordinates.
constexpr int kPhi = 0, kQ1 = 1, kQ2 = 2, kQ3 = 3;
const std::array<QuadraticForm, 6> kOrthonormality = {{
    {1, {{{kQ1, kQ1, 0.5}, {0, 0, 0.0}}}},
    {1, {{{kQ2, kQ2, 0.5}, {0, 0, 0.0}}}},
    {1, {{{kQ3, kQ3, 0.5}, {0, 0, 0.0}}}},
    {1, {{{kQ1, kQ2, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kQ1, kQ3, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kQ2, kQ3, 1.0}, {0, 0, 0.0}}}},
}};
// constants of the orthonormality forms (1/2 (d.d - 1))
constexpr double kOrthoConst[6] = {-0.5, -0.5, -0.5, 0.0, 0.0, 0.0};
}  // namespace

const StrainTable& strain_table(StrainMeasure m) {
  return m == StrainMeasure::SimoReissner ? kSimoReissner : kSeed;
}

int gauss_rule(Quadrature q, std::array<double, 3>& x, std::array<double, 3>& w) {
  if (q == Quadrature::Full) {
    const double a = std::sqrt(0.6);
    x = {0.5 * (1 - a), 0.5, 0.5 * (1 + a)};
    w = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    return 3;
  }
  const double a = 1.0 / std::sqrt(3.0);
  x = {0.5 * (1 - a), 0.5 * (1 + a), 0.0};
  w = {0.5, 0.5, 0.0};
  return 2;
}

MatZEl field_map(const GaussPoint& gp) {
  MatZEl P = MatZEl::Zero();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (int a = 0; a < 3; ++a) {
    const int c = kNq * a;
    P.block<3, 3>(3 * kPhiS, c) = gp.dN[a] * I;
    for (int i = 0; i < 3; ++i) {
      P.block<3, 3>(3 * (kD1 + i), c + 3 * (1 + i)) = gp.N[a] * I;
      P.block<3, 3>(3 * (kD1S + i), c + 3 * (1 + i)) = gp.dN[a] * I;
    }
  }
  return P;
}

Vec6 strains(const StrainTable& T, const VecZ& z) {
  Vec6 e;
  for (int k = 0; k < 6; ++k) e(k) = form_value<kNz>(T[k], z);
  return e;
}

double beam_gp_energy(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                      const VecEl& q) {
  const VecZ z = field_map(gp) * q;
  const Vec6 de = strains(T, z) - eps0;
  return 0.5 * gp.w * de.dot(C.cwiseProduct(de));
}

void beam_gp_residual_tangent(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                              const VecEl& q, VecEl& r, MatEl* K) {
  const MatZEl P = field_map(gp);
  const VecZ z = P * q;
  Mat6Z B;
  for (int k = 0; k < 6; ++k) form_gradient<kNz>(T[k], z, B.row(k));
  const Vec6 sigma = C.cwiseProduct(strains(T, z) - eps0);
  r.noalias() += gp.w * (P.transpose() * (B.transpose() * sigma));
  if (K) {
    MatZ Kz = B.transpose() * C.asDiagonal() * B;
    for (int k = 0; k < 6; ++k) form_add_hessian<kNz>(T[k], sigma(k), Kz);
    K->noalias() += gp.w * (P.transpose() * Kz * P);
  }
}

void beam_gp_residual_tangent_em(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                                 const VecEl& q0, const VecEl& q1, VecEl& r, MatEl* K) {
  const MatZEl P = field_map(gp);
  const VecZ z0 = P * q0, z1 = P * q1, zm = 0.5 * (z0 + z1);
  Mat6Z Bm;
  for (int k = 0; k < 6; ++k) form_gradient<kNz>(T[k], zm, Bm.row(k));
  const Vec6 sigma = C.cwiseProduct(0.5 * (strains(T, z0) + strains(T, z1)) - eps0);
  r.noalias() += gp.w * (P.transpose() * (Bm.transpose() * sigma));
  if (K) {
    Mat6Z B1;
    for (int k = 0; k < 6; ++k) form_gradient<kNz>(T[k], z1, B1.row(k));
    MatZ Kz = 0.5 * (Bm.transpose() * C.asDiagonal() * B1);
    for (int k = 0; k < 6; ++k) form_add_hessian<kNz>(T[k], 0.5 * sigma(k), Kz);
    K->noalias() += gp.w * (P.transpose() * Kz * P);
  }
}

const std::array<QuadraticForm, 6>& orthonormality_forms() { return kOrthonormality; }

Vec6 orthonormality(const Vec12& q) {
  Vec6 phi;
  for (int k = 0; k < 6; ++k) phi(k) = form_value<kNq>(kOrthonormality[k], q) + kOrthoConst[k];
  return phi;
}

Mat6x12 orthonormality_jacobian(const Vec12& q) {
  Mat6x12 G;
  for (int k = 0; k < 6; ++k) form_gradient<kNq>(kOrthonormality[k], q, G.row(k));
  return G;
}

Mat12 orthonormality_hessian(const Vec6& lambda) {
  Mat12 H = Mat12::Zero();
  for (int k = 0; k < 6; ++k) form_add_hessian<kNq>(kOrthonormality[k], lambda(k), H);
  return H;
}

}  // namespace slidebeam::kernels
