// SPDX-License-Identifier: MIT
#include "kernels/beam_kernels.hpp"
#include "kernels/hot.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

namespace slidebeam::kernels {

// The helpers of the SIMD span kernel are forced inline: called from an x86-64-v3 clone
// (SB_HOT_KERNEL), a helper GCC leaves out of line runs its baseline code on every call, and
// whether it does changes with the size of this file (a new kernel elsewhere in it made the
// pendulum's steps 1.5x slower).
#define SB_LANE_INLINE __attribute__((always_inline)) inline

namespace {
// Betsch & Steinmann (2002) objective director strains:
//   Gamma_i = d_i . phi' (- delta_i1), K_1 = 1/2 (d3.d2' - d2.d3'), K_2 = 1/2 (d1.d3' - d3.d1'),
//   K_3 = 1/2 (d2.d1' - d1.d2').
constexpr StrainTable kSimoReissner = {{
    {1, {{{kD1, kPhiS, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kD2, kPhiS, 1.0}, {0, 0, 0.0}}}},
    {1, {{{kD3, kPhiS, 1.0}, {0, 0, 0.0}}}},
    {2, {{{kD3, kD2S, 0.5}, {kD2, kD3S, -0.5}}}},
    {2, {{{kD1, kD3S, 0.5}, {kD3, kD1S, -0.5}}}},
    {2, {{{kD2, kD1S, 0.5}, {kD1, kD2S, -0.5}}}},
}};
// The seed's small-strain Green-Lagrange measure, corrected (docs/theory.md, "Strain measures"):
//   eps = 1/2 phi'.phi' (- 1/2), gamma_a = phi'.d_a, kappa1 = 1/2 (d2'.d3 - d3'.d2),
//   kappa2 = phi'.d3', kappa3 = phi'.d2'.
constexpr StrainTable kSeed = {{
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
  if (q == Quadrature::Full || q == Quadrature::AssumedStrain) {
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
      P.block<3, 3>(3 * (kD1SS + i), c + 3 * (1 + i)) = gp.ddN[a] * I;
    }
  }
  return P;
}

namespace {
// The field map P (21 x 36) is made of scalar multiples of I3: z-block 0 (phi') takes dN_a phi_a,
// z-block i (d_i) takes N_a d_i,a and z-block 3+i (d_i') takes dN_a d_i,a. Products with P are
// done block by block (about 10x fewer operations than the dense 21 x 36 products).
VecZ apply_P(const GaussPoint& gp, const VecEl& q) {
  VecZ z = VecZ::Zero();
  for (int a = 0; a < 3; ++a) {
    const int c = kNq * a;
    z.segment<3>(3 * kPhiS) += gp.dN[a] * q.segment<3>(c);
    for (int i = 1; i <= 3; ++i) {
      z.segment<3>(3 * i) += gp.N[a] * q.segment<3>(c + 3 * i);
      z.segment<3>(3 * (3 + i)) += gp.dN[a] * q.segment<3>(c + 3 * i);
      z.segment<3>(3 * (6 + i)) += gp.ddN[a] * q.segment<3>(c + 3 * i);
    }
  }
  return z;
}
// r += w P^T g
void add_Pt(const GaussPoint& gp, double w, const VecZ& g, VecEl& r) {
  for (int a = 0; a < 3; ++a) {
    const int c = kNq * a;
    r.segment<3>(c) += w * gp.dN[a] * g.segment<3>(3 * kPhiS);
    for (int i = 1; i <= 3; ++i)
      r.segment<3>(c + 3 * i) += w * (gp.N[a] * g.segment<3>(3 * i) + gp.dN[a] * g.segment<3>(3 * (3 + i)) +
                                       gp.ddN[a] * g.segment<3>(3 * (6 + i)));
  }
}
// A span's tangent K = sum over its points of w P^T Kz P, gathered point by point in two parts
// (docs/developer.md, "Design notes"):
// - the geometric part: every strain is a sum of c z_a . z_b, so sum_k sigma_k d^2 eps_k / dz^2
//   is a 10 x 10 matrix of scalars times I3 (the turning term's constant part too), and P maps it
//   to a 12 x 12 one over (control point, field), S, again times I3;
// - the rest, the material part B_m^T C B_1 and the turning term's G^T [s]x G', is a sum of
//   rank-one products a b^T. Their rows P^T a, P^T b are kept in a phi part (9) and a director part
//   (27) and multiplied once per span: the curvature and turning rows have no phi part.
// P is applied block by block: no 30 x 36 product is formed.
typedef double Quad __attribute__((vector_size(4 * sizeof(double))));
// The rank-one rows of a span's tangent in a permuted order of its 36 coordinates: the director
// part (27) first, then a zero, the phi part (9) and three zeros, so that rows are whole SIMD
// vectors and rows without phi terms skip them.
constexpr int kRowWidth = 40, kPhiOffset = 28;
// acc += sum_r U(r, i) V(r, :NV vectors) (always inlined: compiled into each clone of its caller)
template <int NV>
[[gnu::always_inline]] inline void add_row_products(int n, const double (*U)[kRowWidth], const double (*V)[kRowWidth],
                                                    int i, Quad* acc) {
  for (int r = 0; r < n; ++r) {
    const double u = U[r][i];
    for (int v = 0; v < NV; ++v) {
      Quad x;
      std::memcpy(&x, &V[r][4 * v], sizeof x);
      acc[v] += u * x;
    }
  }
}
// Kp(i, :) = sum_r Ud(r, i) Vd(r, :) + sum_r Um(r, i) Vm(r, :) over the rows i given (Kp
// row-major): the director rows' first ND vectors of columns, the mixed rows' first NM.
template <int ND, int NM>
SB_HOT_KERNEL void add_rank_one_products(int nd, const double (*Ud)[kRowWidth], const double (*Vd)[kRowWidth], int nm,
                                         const double (*Um)[kRowWidth], const double (*Vm)[kRowWidth], int first_row,
                                         int end_row, double (*Kp)[kRowWidth]) {
  constexpr int N = ND > NM ? ND : NM;
  for (int i = first_row; i < end_row; ++i) {
    Quad acc[N] = {};
    add_row_products<ND>(nd, Ud, Vd, i, acc);
    add_row_products<NM>(nm, Um, Vm, i, acc);
    for (int v = 0; v < N; ++v) std::memcpy(&Kp[i][4 * v], &acc[v], sizeof(Quad));
  }
}
class SpanTangent {
 public:
  SpanTangent() {}  // (user-provided: value-initialization would zero the row buffers)
  using Hessian = std::array<std::array<double, 10>, 10>;  ///< over z's 3-blocks, times I3
  /// K += w P^T (H x I3) P
  void add_geometric(const GaussPoint& gp, double w, const Hessian& H) {
    double Y[10][12] = {};  // H P over (control point, field)
    for (int u = 0; u < 10; ++u)
      for (int v = 0; v < 10; ++v) {
        if (H[u][v] == 0.0) continue;
        for (int b = 0; b < 3; ++b) Y[u][4 * b + field(v)] += H[u][v] * coefficient(gp, v, b);
      }
    for (int u = 0; u < 10; ++u)
      for (int a = 0; a < 3; ++a) {
        const double c = w * coefficient(gp, u, a);
        if (c == 0.0) continue;
        double* row = S_[4 * a + field(u)];
        for (int j = 0; j < 12; ++j) row[j] += c * Y[u][j];
      }
  }
  /// K += w P^T a b^T P
  void add_rank_one(const GaussPoint& gp, double w, const VecZ& a, const VecZ& b) {
    const bool mixed = a.head<3>().squaredNorm() > 0.0 || b.head<3>().squaredNorm() > 0.0;
    int& n = mixed ? nm_ : nd_;
    map_row(gp, w, a, (mixed ? Um_ : Ud_)[n]);
    map_row(gp, 1.0, b, (mixed ? Vm_ : Vd_)[n]);
    ++n;
  }
  void add_to(MatEl& K) const {
    for (int a = 0; a < 3; ++a)
      for (int f = 0; f < 4; ++f)
        for (int b = 0; b < 3; ++b)
          for (int g = 0; g < 4; ++g) {
            const double s = S_[4 * a + f][4 * b + g];
            if (s == 0.0) continue;
            for (int c = 0; c < 3; ++c) K(kNq * a + 3 * f + c, kNq * b + 3 * g + c) += s;
          }
    if (nd_ + nm_ == 0) return;
    alignas(32) double Kp[kRowWidth][kRowWidth];
    constexpr int kD = kPhiOffset / 4, kAll = kRowWidth / 4;  // vectors of director columns, of all
    if (nm_ == 0)
      add_rank_one_products<kD, 0>(nd_, Ud_, Vd_, 0, Um_, Vm_, 0, 27, Kp);
    else {
      add_rank_one_products<kD, kAll>(nd_, Ud_, Vd_, nm_, Um_, Vm_, 0, 27, Kp);
      add_rank_one_products<0, kAll>(0, Ud_, Vd_, nm_, Um_, Vm_, kPhiOffset, kPhiOffset + 9, Kp);
    }
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int j = 0; j < 9; ++j)
          for (int i = 0; i < 9; ++i) K(kNq * a + 3 + i, kNq * b + 3 + j) += Kp[9 * a + i][9 * b + j];
    if (nm_ == 0) return;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c) {
          const double* phi_row = Kp[kPhiOffset + 3 * a + c];
          for (int j = 0; j < 9; ++j) K(kNq * a + c, kNq * b + 3 + j) += phi_row[9 * b + j];
          for (int j = 0; j < 3; ++j) K(kNq * a + c, kNq * b + j) += phi_row[kPhiOffset + 3 * b + j];
          for (int i = 0; i < 9; ++i) K(kNq * a + 3 + i, kNq * b + c) += Kp[9 * a + i][kPhiOffset + 3 * b + c];
        }
  }

 private:
  static constexpr int kMaxRows = 12 * kSpanLanes;  // per point: 6 material rows, 6 of the turning term
  // z-block u takes field(u) of control point a times coefficient(u, a): phi' dN phi, d_i N d_i,
  // d_i' dN d_i, d_i'' ddN d_i
  static int field(int u) { return u == kPhiS ? 0 : (u - 1) % 3 + 1; }
  static double coefficient(const GaussPoint& gp, int u, int a) {
    return u == kPhiS || (u >= kD1S && u < kD1SS) ? gp.dN[a] : u < kD1S ? gp.N[a] : gp.ddN[a];
  }
  // row = w P^T z in the permuted order
  static void map_row(const GaussPoint& gp, double w, const VecZ& z, double* row) {
    for (int a = 0; a < 3; ++a) {
      const double n = w * gp.N[a], dn = w * gp.dN[a], ddn = w * gp.ddN[a];
      for (int c = 0; c < 3; ++c) row[kPhiOffset + 3 * a + c] = dn * z(3 * kPhiS + c);
      for (int i = 0; i < 9; ++i) row[9 * a + i] = n * z(3 * kD1 + i) + dn * z(3 * kD1S + i) + ddn * z(3 * kD1SS + i);
    }
    row[27] = row[37] = row[38] = row[39] = 0.0;
  }
  double S_[12][12] = {};
  // the rows without a phi part (director rows) and with one (mixed rows)
  alignas(32) double Ud_[kMaxRows][kRowWidth], Vd_[kMaxRows][kRowWidth];
  alignas(32) double Um_[kMaxRows][kRowWidth], Vm_[kMaxRows][kRowWidth];
  int nd_ = 0, nm_ = 0;
};
// The material part s Ba^T diag(C) Bb, row by row (rows of zero stiffness skipped: an
// assumed-strain point's Gamma rows, whose stiffness acts through the knots).
void add_material_rows(const GaussPoint& gp, const Mat6Z& Ba, const Stiffness& C, const Mat6Z& Bb, double s,
                       SpanTangent& K) {
  for (int k = 0; k < 6; ++k)
    if (C(k) != 0.0) K.add_rank_one(gp, gp.w, VecZ((s * C(k)) * Ba.row(k).transpose()), VecZ(Bb.row(k).transpose()));
}
// H += sum_k f sigma_k d^2 eps_k / dz^2 over z's 3-blocks (the strains' Hessians, constant)
void add_form_hessians(const StrainTable& T, const Vec6& sigma, double f, SpanTangent::Hessian& H) {
  for (int k = 0; k < 6; ++k)
    for (int t = 0; t < T[k].n_terms; ++t) {
      const auto& term = T[k].terms[t];
      H[term.a][term.b] += f * sigma(k) * term.c;
      H[term.b][term.a] += f * sigma(k) * term.c;
    }
}
// g = sum_k sigma_k d eps_k / dz at z, term by term (the 6 x 30 gradient is mostly zeros).
VecZ weighted_gradient(const StrainTable& T, const Vec6& sigma, const VecZ& z) {
  VecZ g = VecZ::Zero();
  for (int k = 0; k < 6; ++k) {
    for (int t = 0; t < T[k].n_terms; ++t) {
      const auto& f = T[k].terms[t];
      const double s = sigma(k) * f.c;
      g.segment<3>(3 * f.a) += s * z.segment<3>(3 * f.b);
      g.segment<3>(3 * f.b) += s * z.segment<3>(3 * f.a);
    }
  }
  return g;
}
}  // namespace

VecZ field_values(const GaussPoint& gp, const VecEl& q) { return apply_P(gp, q); }

namespace {
// The turning term of a corrected Simo-Reissner point, (c/2) K x K' added to the curvature
// (docs/theory.md, "The turning term"). K = K(d, d') and K' = K(d, d'') (the curvature form with d''
// in the derivative's slot: K's derivative along the beam) are quadratic forms, so the term is a
// product of two: its energy-momentum force uses the product rule's discrete gradient.
// a . b of two 3-blocks, for any arithmetic type: doubles, or SIMD lanes that hold several
// quadrature points (the span kernels below)
template <class T>
SB_LANE_INLINE T dot3(const T* a, const T* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
// K_i = 1/2 (d_k . e_j - d_j . e_k), (i, j, k) cyclic, e the block of z at `slot` (d' or d'')
template <class T>
SB_LANE_INLINE void curvature_form(const T* z, int slot, T* K) {
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    K[i] = 0.5 * (dot3(z + 3 * (kD1 + k), z + 3 * (slot + j)) - dot3(z + 3 * (kD1 + j), z + 3 * (slot + k)));
  }
}
// g += sum_i s_i dK_i/dz of curvature_form(z, slot)
template <class T>
SB_LANE_INLINE void curvature_form_gradient(const T* s, const T* z, int slot, T* g) {
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const T h = 0.5 * s[i];
    for (int c = 0; c < 3; ++c) {
      g[3 * (kD1 + k) + c] += h * z[3 * (slot + j) + c];
      g[3 * (slot + j) + c] += h * z[3 * (kD1 + k) + c];
      g[3 * (kD1 + j) + c] -= h * z[3 * (slot + k) + c];
      g[3 * (slot + k) + c] -= h * z[3 * (kD1 + j) + c];
    }
  }
}
template <class T>
SB_LANE_INLINE void cross3(const T* a, const T* b, T* c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
// g += sum_i s_i d[(c/2) K x K']_i / dz with K and K' taken as kbar, kpbar in the product and their
// gradients at z: the exact gradient where kbar = K(z), kpbar = K'(z); the product rule's discrete
// gradient where they are the step's averages and z its midpoint.
template <class T>
SB_LANE_INLINE void turning_gradient(const T* s, const T* kbar, const T* kpbar, const T& c, const T* z, T* g) {
  T a[3], b[3];
  cross3(kpbar, s, a);  // d(K x K') = dK x K' + K x dK': s . (dK x K') = (K' x s) . dK
  cross3(s, kbar, b);   //                                   s . (K x dK') = (s x K) . dK'
  for (int i = 0; i < 3; ++i) {
    a[i] = 0.5 * c * a[i];
    b[i] = 0.5 * c * b[i];
  }
  curvature_form_gradient(a, z, kD1S, g);
  curvature_form_gradient(b, z, kD1SS, g);
}
bool has_turning_term(const StrainTable& T0, const GaussPoint& gp) { return gp.corrected && &T0 == &kSimoReissner; }
Eigen::Vector3d curvature_at(const VecZ& z, int slot) {
  Eigen::Vector3d K;
  curvature_form(z.data(), slot, K.data());
  return K;
}
// The gradient of curvature_form(z, slot), by its two non-zero parts: d (columns of z's director
// blocks d1..d3) and e (columns of the blocks at slot). Row i: -1/2 e_k and 1/2 e_j in director
// blocks j and k, 1/2 d_k and -1/2 d_j in slot blocks j and k.
using Mat39 = Eigen::Matrix<double, 3, 9>;
struct CurvatureGradient {
  Mat39 d, e;
};
CurvatureGradient curvature_gradient(const VecZ& z, int slot) {
  CurvatureGradient G;
  G.d.setZero();
  G.e.setZero();
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    G.d.block<1, 3>(i, 3 * j) = -0.5 * z.segment<3>(3 * (slot + k)).transpose();
    G.d.block<1, 3>(i, 3 * k) = 0.5 * z.segment<3>(3 * (slot + j)).transpose();
    G.e.block<1, 3>(i, 3 * j) = 0.5 * z.segment<3>(3 * (kD1 + k)).transpose();
    G.e.block<1, 3>(i, 3 * k) = -0.5 * z.segment<3>(3 * (kD1 + j)).transpose();
  }
  return G;
}
Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a(2), a(1), a(2), 0, -a(0), -a(1), a(0), 0;
  return S;
}
// The gradients of K = K(d, d') and K' = K(d, d'') at a z.
struct TurningGradients {
  CurvatureGradient k, kp;
  explicit TurningGradients(const VecZ& z) : k(curvature_gradient(z, kD1S)), kp(curvature_gradient(z, kD1SS)) {}
};
// B's curvature rows += those of the turning term with K, K' as given (see turning_gradient) and
// their gradients G at z: (c/2) (K x G' - K' x G).
void add_turning_rows(double c, const Eigen::Vector3d& kbar, const Eigen::Vector3d& kpbar, const TurningGradients& G,
                      Mat6Z& B) {
  const Eigen::Matrix3d A = 0.5 * c * skew(kbar), P = 0.5 * c * skew(kpbar);
  B.block<3, 9>(3, 3 * kD1) += A * G.kp.d - P * G.k.d;
  B.block<3, 9>(3, 3 * kD1S) -= P * G.k.e;
  B.block<3, 9>(3, 3 * kD1SS) += A * G.kp.e;
}
// K += the derivative of turning_gradient(s, kbar, kpbar, c, zm) with s held, where kbar, kpbar
// and zm move with z1 at the rate f (1 for the exact gradient, 1/2 for the step's averages):
// f (c/2) [sum_i a_i H(K_i) + sum_i b_i H(K'_i) + G(zm)^T (-[s]x) G'(z1) + G'(zm)^T [s]x G(z1)]
// with a = kpbar x s, b = s x kbar; Gm at zm, G1 at z1. The curvature forms' Hessians go to H
// (constant, times I3), the rest is six rank-one products.
void add_turning_hessian(const Eigen::Vector3d& s, const Eigen::Vector3d& kbar, const Eigen::Vector3d& kpbar, double c,
                         const TurningGradients& Gm, const TurningGradients& G1, double f, const GaussPoint& gp,
                         SpanTangent::Hessian& H, SpanTangent& K) {
  const double w = 0.5 * c * f;
  const Eigen::Vector3d a = w * kpbar.cross(s), b = w * s.cross(kbar);
  // the terms of curvature_form_gradient with z's blocks as unit vectors
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    for (int slot : {kD1S, kD1SS}) {
      const double h = 0.5 * (slot == kD1S ? a(i) : b(i));
      H[kD1 + k][slot + j] += h;
      H[slot + j][kD1 + k] += h;
      H[kD1 + j][slot + k] -= h;
      H[slot + k][kD1 + j] -= h;
    }
  }
  // G'(zm)^T S G(z1) - G(zm)^T S G'(z1): columns of L times rows of R over z's director, d' and
  // d'' blocks (G' has no d' part, G no d'' part)
  const Eigen::Matrix3d S = w * skew(s);
  const Eigen::Matrix<double, 3, 9> R[4] = {S * G1.k.d, S * G1.k.e, S * G1.kp.d, S * G1.kp.e};
  for (int r = 0; r < 6; ++r) {
    const int m = r % 3;
    VecZ lc = VecZ::Zero(), rr = VecZ::Zero();
    if (r < 3) {  // G'(zm)^T S G(z1)
      lc.segment<9>(3 * kD1) = Gm.kp.d.row(m).transpose();
      lc.segment<9>(3 * kD1SS) = Gm.kp.e.row(m).transpose();
      rr.segment<9>(3 * kD1) = R[0].row(m).transpose();
      rr.segment<9>(3 * kD1S) = R[1].row(m).transpose();
    } else {  // - G(zm)^T S G'(z1)
      lc.segment<9>(3 * kD1) = -Gm.k.d.row(m).transpose();
      lc.segment<9>(3 * kD1S) = -Gm.k.e.row(m).transpose();
      rr.segment<9>(3 * kD1) = R[2].row(m).transpose();
      rr.segment<9>(3 * kD1SS) = R[3].row(m).transpose();
    }
    K.add_rank_one(gp, gp.w, lc, rr);
  }
}
// K and K' at a z
struct Curvatures {
  Eigen::Vector3d k = Eigen::Vector3d::Zero(), kp = Eigen::Vector3d::Zero();
};
Curvatures curvatures_at(const VecZ& z) { return {curvature_at(z, kD1S), curvature_at(z, kD1SS)}; }
// strains e of the point table plus the turning term
Vec6 with_turning(Vec6 e, double c, const Curvatures& K) {
  e.tail<3>() += 0.5 * c * K.k.cross(K.kp);
  return e;
}
}  // namespace

Vec6 point_strains(const StrainTable& T0, const GaussPoint& gp, const VecZ& z) {
  const Vec6 e = strains(point_table(T0, gp), z);
  return has_turning_term(T0, gp) ? with_turning(e, gp.correction_weight, curvatures_at(z)) : e;
}

Vec6 strains(const StrainTable& T, const VecZ& z) {
  Vec6 e;
  for (int k = 0; k < 6; ++k) e(k) = form_value<kNz>(T[k], z);
  return e;
}

double beam_gp_energy(const StrainTable& T0, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                      const VecEl& q) {
  const Vec6 de = point_strains(T0, gp, apply_P(gp, q)) - eps0;  // (energies are not in Newton's loop)
  return 0.5 * gp.w * de.dot(C.cwiseProduct(de));
}

namespace {
// The stiffness of a point's own strains: without the Gamma rows when their stresses are given.
Stiffness pointwise_stiffness(const Stiffness& C, const Eigen::Vector3d* gamma_sigma) {
  Stiffness Cp = C;
  if (gamma_sigma) Cp.head<3>().setZero();
  return Cp;
}
}  // namespace

namespace {
void gp_residual_tangent(const StrainTable& T0, const Stiffness& C0, const Vec6& eps0, const GaussPoint& gp,
                         const VecEl& q, VecEl& r, SpanTangent* K, const Eigen::Vector3d* gamma_sigma) {
  const StrainTable T = point_table(T0, gp);
  const Stiffness C = pointwise_stiffness(C0, gamma_sigma);
  const VecZ z = apply_P(gp, q);
  const bool turns = has_turning_term(T0, gp);
  const double c = gp.correction_weight;
  const Curvatures K0 = turns ? curvatures_at(z) : Curvatures{};
  const Eigen::Vector3d &k = K0.k, &kp = K0.kp;
  Vec6 sigma = C.cwiseProduct((turns ? with_turning(strains(T, z), c, K0) : strains(T, z)) - eps0);
  if (gamma_sigma) sigma.head<3>() = *gamma_sigma;
  VecZ g = weighted_gradient(T, sigma, z);
  const Eigen::Vector3d sigma_k = sigma.tail<3>();
  if (turns) turning_gradient(sigma_k.data(), k.data(), kp.data(), c, z.data(), g.data());
  add_Pt(gp, gp.w, g, r);
  if (K) {
    Mat6Z B;
    for (int i = 0; i < 6; ++i) form_gradient<kNz>(T[i], z, B.row(i));
    std::optional<TurningGradients> G;
    if (turns) add_turning_rows(c, k, kp, G.emplace(z), B);
    add_material_rows(gp, B, C, B, 1.0, *K);
    SpanTangent::Hessian H{};
    add_form_hessians(T, sigma, 1.0, H);
    if (turns) add_turning_hessian(sigma_k, k, kp, c, *G, *G, 1.0, gp, H, *K);
    K->add_geometric(gp, gp.w, H);
  }
}

void gp_residual_tangent_em(const StrainTable& T0, const Stiffness& C0, const Vec6& eps0, const GaussPoint& gp,
                            const VecEl& q0, const VecEl& q1, VecEl& r, SpanTangent* K, double xi,
                            const Eigen::Vector3d* gamma_sigma) {
  const StrainTable T = point_table(T0, gp);
  const Stiffness C = pointwise_stiffness(C0, gamma_sigma);
  const VecZ z0 = apply_P(gp, q0), z1 = apply_P(gp, q1), zm = 0.5 * (z0 + z1);
  const bool turns = has_turning_term(T0, gp);
  const double c = gp.correction_weight;
  const Curvatures K0 = turns ? curvatures_at(z0) : Curvatures{}, K1 = turns ? curvatures_at(z1) : Curvatures{};
  Vec6 e0 = strains(T, z0), e1 = strains(T, z1);
  if (turns) {
    e0 = with_turning(e0, c, K0);
    e1 = with_turning(e1, c, K1);
  }
  // averaged strain, shifted by xi/2 (eps1 - eps0) towards the end of the step
  Vec6 sigma = C.cwiseProduct(0.5 * (1.0 - xi) * e0 + 0.5 * (1.0 + xi) * e1 - eps0);
  if (gamma_sigma) sigma.head<3>() = *gamma_sigma;
  VecZ g = weighted_gradient(T, sigma, zm);
  // the turning term's discrete gradient: the product rule with the step's averages of K and K'
  const Eigen::Vector3d &k1 = K1.k, &kp1 = K1.kp;
  const Eigen::Vector3d kbar = 0.5 * (K0.k + k1), kpbar = 0.5 * (K0.kp + kp1);
  const Eigen::Vector3d sigma_k = sigma.tail<3>();
  if (turns) turning_gradient(sigma_k.data(), kbar.data(), kpbar.data(), c, zm.data(), g.data());
  add_Pt(gp, gp.w, g, r);
  if (K) {
    Mat6Z Bm;
    for (int i = 0; i < 6; ++i) form_gradient<kNz>(T[i], zm, Bm.row(i));
    Mat6Z B1;
    for (int i = 0; i < 6; ++i) form_gradient<kNz>(T[i], z1, B1.row(i));
    std::optional<TurningGradients> Gm, G1;
    if (turns) {
      add_turning_rows(c, kbar, kpbar, Gm.emplace(zm), Bm);
      add_turning_rows(c, k1, kp1, G1.emplace(z1), B1);
    }
    add_material_rows(gp, Bm, C, B1, 0.5 * (1.0 + xi), *K);
    SpanTangent::Hessian H{};
    add_form_hessians(T, sigma, 0.5, H);
    if (turns) add_turning_hessian(sigma_k, kbar, kpbar, c, *Gm, *G1, 0.5, gp, H, *K);
    K->add_geometric(gp, gp.w, H);
  }
}
}  // namespace

void span_kelvin_voigt(const StrainTable& T0, const GaussPoint* gps, int n, const Vec6& c,
                       const Eigen::Vector3d* gamma_sigma, double h, double theta, const VecEl& q0, const VecEl& q1,
                       VecEl& r, MatEl* K) {
  SpanTangent Ks;
  for (int g = 0; g < n; ++g) {
    const GaussPoint& gp = gps[g];
    const StrainTable T = point_table(T0, gp);
    const VecZ z0 = apply_P(gp, q0), z1 = apply_P(gp, q1), zf = (1.0 - theta) * z0 + theta * z1;
    Vec6 sigma = c.cwiseProduct(strains(T, z1) - strains(T, z0)) / h;
    if (gamma_sigma) sigma.head<3>() = gamma_sigma[g];
    VecZ force = VecZ::Zero();
    SpanTangent::Hessian H{};
    for (int k = 0; k < 6; ++k) {
      if (c(k) == 0.0) continue;
      Eigen::Matrix<double, 1, kNz> gf;
      form_gradient<kNz>(T[k], zf, gf);
      force += sigma(k) * gf.transpose();
      if (!K) continue;
      for (int t = 0; t < T[k].n_terms; ++t) {
        const auto& term = T[k].terms[t];
        H[term.a][term.b] += theta * sigma(k) * term.c;
        H[term.b][term.a] += theta * sigma(k) * term.c;
      }
      if (gamma_sigma && k < 3) continue;  // the knot's material part: added per knot
      Eigen::Matrix<double, 1, kNz> g1;
      form_gradient<kNz>(T[k], z1, g1);
      Ks.add_rank_one(gp, gp.w, VecZ((c(k) / h) * gf.transpose()), VecZ(g1.transpose()));
    }
    add_Pt(gp, gp.w, force, r);
    if (K) Ks.add_geometric(gp, gp.w, H);
  }
  if (K) Ks.add_to(*K);
}

void beam_gp_residual_tangent(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                              const VecEl& q, VecEl& r, MatEl* K, const Eigen::Vector3d* gamma_sigma) {
  span_residual_tangent(T, C, &gp, &eps0, 1, gamma_sigma, q, r, K);
}

void beam_gp_residual_tangent_em(const StrainTable& T, const Stiffness& C, const Vec6& eps0, const GaussPoint& gp,
                                 const VecEl& q0, const VecEl& q1, VecEl& r, MatEl* K, double xi,
                                 const Eigen::Vector3d* gamma_sigma) {
  span_residual_tangent_em(T, C, &gp, &eps0, 1, gamma_sigma, q0, q1, r, K, xi);
}

StrainTable point_table(const StrainTable& T, const GaussPoint& gp) {
  if (!gp.corrected || &T != &kSimoReissner) return T;
  StrainTable Tc = T;
  // The axial strain of the centre line, 1/2 (phi'.phi' - 1): no directors in it. With the shear
  // strains enforced only through knot means, d1 . phi' - 1 would let a tensioned rope lengthen
  // without strain by turning its triads to and fro between control points (theory.md).
  Tc[0] = {1, {{{kPhiS, kPhiS, 0.5}, {0, 0, 0.0}}}};
  // Gamma_i -= 1/2 d_i . d_1 (i = 2, 3): the interpolated directors' shear S_1i of S = 1/2 (D^T D - I)
  for (int i = 1; i < 3; ++i) Tc[i].terms[Tc[i].n_terms++] = {kD1 + i, kD1, -0.5};
  // K_i += c (the same form in d', d''): the curvature lost to the shrinkage, about v |K|^2 K
  for (int i = 3; i < 6; ++i)
    for (int t = 0; t < T[i].n_terms; ++t)
      Tc[i].terms[Tc[i].n_terms++] = {T[i].terms[t].a + 3, T[i].terms[t].b + 3, gp.correction_weight * T[i].terms[t].c};
  return Tc;
}

namespace {
// The Gamma forms of both measures (and of a corrected point's table) read z's first four blocks
// only, phi' and the directors: the knots' strains and their gradients work on those.
constexpr int kGammaBlocks = kD3 + 1;
using VecZGamma = Eigen::Matrix<double, 3 * kGammaBlocks, 1>;
using GammaForms = std::array<QuadraticForm, 3>;
// the point's Gamma forms: point_table's first three (which do not depend on its correction weight)
GammaForms gamma_forms(const StrainTable& T, const GaussPoint& gp) {
  GammaForms G = {T[0], T[1], T[2]};
  if (gp.corrected && &T == &kSimoReissner) {
    G[0] = {1, {{{kPhiS, kPhiS, 0.5}, {0, 0, 0.0}}}};
    for (int i = 1; i < 3; ++i) G[i].terms[G[i].n_terms++] = {kD1 + i, kD1, -0.5};
  }
  return G;
}
VecZGamma gamma_fields(const GaussPoint& gp, const VecEl& q) {
  VecZGamma z = VecZGamma::Zero();
  for (int a = 0; a < 3; ++a) {
    z.segment<3>(3 * kPhiS) += gp.dN[a] * q.segment<3>(kNq * a);
    for (int i = 1; i <= 3; ++i) z.segment<3>(3 * i) += gp.N[a] * q.segment<3>(kNq * a + 3 * i);
  }
  return z;
}
}  // namespace

GammaMoments span_gamma_moments(const StrainTable& T, const GaussPoint* gps, const Vec6* eps0, int n,
                                const VecEl& q) {
  GammaMoments m;
  for (int g = 0; g < n; ++g) {
    const GammaForms G = gamma_forms(T, gps[g]);
    const VecZGamma z = gamma_fields(gps[g], q);
    Eigen::Vector3d d;
    for (int k = 0; k < 3; ++k) d(k) = form_value<3 * kGammaBlocks>(G[k], z) - eps0[g](k);
    m.left += gps[g].w * (1.0 - gps[g].t) * d;
    m.right += gps[g].w * gps[g].t * d;
  }
  return m;
}

void span_gamma_moment_gradients(const StrainTable& T, const GaussPoint* gps, int n, const VecEl& q, Mat3El& left,
                                 Mat3El& right) {
  left.setZero();
  right.setZero();
  for (int g = 0; g < n; ++g) {
    const GaussPoint& gp = gps[g];
    const GammaForms G = gamma_forms(T, gp);
    const VecZGamma z = gamma_fields(gp, q);
    for (int k = 0; k < 3; ++k) {
      VecZGamma b = VecZGamma::Zero();  // d Gamma_k / dz
      for (int t = 0; t < G[k].n_terms; ++t) {
        const auto& f = G[k].terms[t];
        b.segment<3>(3 * f.a) += f.c * z.segment<3>(3 * f.b);
        b.segment<3>(3 * f.b) += f.c * z.segment<3>(3 * f.a);
      }
      // P^T b, weighted toward either knot
      for (int a = 0; a < 3; ++a) {
        Eigen::Matrix<double, 1, kNq> row;
        row.segment<3>(0) = gp.dN[a] * b.segment<3>(3 * kPhiS).transpose();
        for (int i = 1; i <= 3; ++i) row.segment<3>(3 * i) = gp.N[a] * b.segment<3>(3 * i).transpose();
        left.block<1, kNq>(k, kNq * a) += (gp.w * (1.0 - gp.t)) * row;
        right.block<1, kNq>(k, kNq * a) += (gp.w * gp.t) * row;
      }
    }
  }
}

double span_energy(const StrainTable& T, const Stiffness& C, const GaussPoint* gps, const Vec6* eps0, int n,
                   bool gamma_from_knots, const VecEl& q) {
  Stiffness Ck = C;
  if (gamma_from_knots) Ck.head<3>().setZero();
  double U = 0.0;
  for (int g = 0; g < n; ++g) U += beam_gp_energy(T, Ck, eps0[g], gps[g], q);
  return U;
}

void span_residual_tangent(const StrainTable& T, const Stiffness& C, const GaussPoint* gps, const Vec6* eps0, int n,
                           const Eigen::Vector3d* gamma_sigma, const VecEl& q, VecEl& r, MatEl* K) {
  if (!K) {
    for (int g = 0; g < n; ++g)
      gp_residual_tangent(T, C, eps0[g], gps[g], q, r, nullptr, gamma_sigma ? gamma_sigma + g : nullptr);
    return;
  }
  SpanTangent Ks;  // (not in a std::optional: that zeroes its 60 kB)
  for (int g = 0; g < n; ++g)
    gp_residual_tangent(T, C, eps0[g], gps[g], q, r, &Ks, gamma_sigma ? gamma_sigma + g : nullptr);
  Ks.add_to(*K);
}

void span_residual_tangent_em(const StrainTable& T, const Stiffness& C, const GaussPoint* gps, const Vec6* eps0,
                              int n, const Eigen::Vector3d* gamma_sigma, const VecEl& q0, const VecEl& q1, VecEl& r,
                              MatEl* K, double xi) {
  if (!K) {
    for (int g = 0; g < n; ++g)
      gp_residual_tangent_em(T, C, eps0[g], gps[g], q0, q1, r, nullptr, xi, gamma_sigma ? gamma_sigma + g : nullptr);
    return;
  }
  SpanTangent Ks;  // (not in a std::optional: that zeroes its 60 kB)
  for (int g = 0; g < n; ++g)
    gp_residual_tangent_em(T, C, eps0[g], gps[g], q0, q1, r, &Ks, xi, gamma_sigma ? gamma_sigma + g : nullptr);
  Ks.add_to(*K);
}

namespace {

// The two measures' strains and weighted gradients g = sum_k sigma_k d eps_k / dz written out
// (the tables above, term by term), for any arithmetic type: doubles, or SIMD lanes that hold
// several quadrature points. z blocks: 0 phi', 1-3 d1..d3, 4-6 d1'..d3'.
struct SimoReissnerForms {
  template <class T>
  SB_LANE_INLINE static void strains(const T* z, T* e) {
    const T *p = z + 3 * kPhiS, *d1 = z + 3 * kD1, *d2 = z + 3 * kD2, *d3 = z + 3 * kD3;
    const T *e1 = z + 3 * kD1S, *e2 = z + 3 * kD2S, *e3 = z + 3 * kD3S;
    e[0] = dot3(d1, p);
    e[1] = dot3(d2, p);
    e[2] = dot3(d3, p);
    e[3] = 0.5 * (dot3(d3, e2) - dot3(d2, e3));
    e[4] = 0.5 * (dot3(d1, e3) - dot3(d3, e1));
    e[5] = 0.5 * (dot3(d2, e1) - dot3(d1, e2));
  }
  template <class T>
  SB_LANE_INLINE static void gradient(const T* s, const T* z, T* g) {
    const T h3 = 0.5 * s[3], h4 = 0.5 * s[4], h5 = 0.5 * s[5];
    const T *p = z + 3 * kPhiS, *d1 = z + 3 * kD1, *d2 = z + 3 * kD2, *d3 = z + 3 * kD3;
    const T *e1 = z + 3 * kD1S, *e2 = z + 3 * kD2S, *e3 = z + 3 * kD3S;
    for (int c = 0; c < 3; ++c) {
      g[3 * kPhiS + c] = s[0] * d1[c] + s[1] * d2[c] + s[2] * d3[c];
      g[3 * kD1 + c] = s[0] * p[c] + h4 * e3[c] - h5 * e2[c];
      g[3 * kD2 + c] = s[1] * p[c] - h3 * e3[c] + h5 * e1[c];
      g[3 * kD3 + c] = s[2] * p[c] + h3 * e2[c] - h4 * e1[c];
      g[3 * kD1S + c] = h5 * d2[c] - h4 * d3[c];
      g[3 * kD2S + c] = h3 * d3[c] - h5 * d1[c];
      g[3 * kD3S + c] = h4 * d1[c] - h3 * d2[c];
    }
  }
};
struct SeedForms {
  template <class T>
  SB_LANE_INLINE static void strains(const T* z, T* e) {
    const T *p = z + 3 * kPhiS, *d2 = z + 3 * kD2, *d3 = z + 3 * kD3;
    const T *e2 = z + 3 * kD2S, *e3 = z + 3 * kD3S;
    e[0] = 0.5 * dot3(p, p);
    e[1] = dot3(p, d2);
    e[2] = dot3(p, d3);
    e[3] = 0.5 * (dot3(e2, d3) - dot3(e3, d2));
    e[4] = dot3(p, e3);
    e[5] = dot3(p, e2);
  }
  template <class T>
  SB_LANE_INLINE static void gradient(const T* s, const T* z, T* g) {
    const T h3 = 0.5 * s[3];
    const T *p = z + 3 * kPhiS, *d2 = z + 3 * kD2, *d3 = z + 3 * kD3;
    const T *e2 = z + 3 * kD2S, *e3 = z + 3 * kD3S;
    for (int c = 0; c < 3; ++c) {
      g[3 * kPhiS + c] = s[0] * p[c] + s[1] * d2[c] + s[2] * d3[c] + s[4] * e3[c] + s[5] * e2[c];
      g[3 * kD1 + c] = 0.0 * p[c];
      g[3 * kD2 + c] = s[1] * p[c] - h3 * e3[c];
      g[3 * kD3 + c] = s[2] * p[c] + h3 * e2[c];
      g[3 * kD1S + c] = 0.0 * p[c];
      g[3 * kD2S + c] = h3 * d3[c] + s[5] * p[c];
      g[3 * kD3S + c] = s[4] * p[c] - h3 * d2[c];
    }
  }
};

// What point_table changes in the Simo-Reissner strains of a corrected point (the centre line's
// axial strain, the director-interpolation correction) and in their weighted gradient, written
// out like the forms above (v: the point's correction weight).
struct DirectorCorrection {
  template <class T>
  SB_LANE_INLINE static void strains(const T* z, const T& v, T* e) {
    const T *d1 = z + 3 * kD1, *d2 = z + 3 * kD2, *d3 = z + 3 * kD3;
    const T *e1 = z + 3 * kD1S, *e2 = z + 3 * kD2S, *e3 = z + 3 * kD3S;
    const T *f1 = z + 3 * kD1SS, *f2 = z + 3 * kD2SS, *f3 = z + 3 * kD3SS;
    const T* p = z + 3 * kPhiS;
    e[0] = 0.5 * dot3(p, p);
    e[1] -= 0.5 * dot3(d2, d1);
    e[2] -= 0.5 * dot3(d3, d1);
    e[3] += 0.5 * v * (dot3(e3, f2) - dot3(e2, f3));
    e[4] += 0.5 * v * (dot3(e1, f3) - dot3(e3, f1));
    e[5] += 0.5 * v * (dot3(e2, f1) - dot3(e1, f2));
  }
  template <class T>
  SB_LANE_INLINE static void gradient(const T* s, const T* z, const T& v, T* g) {
    const T h3 = 0.5 * v * s[3], h4 = 0.5 * v * s[4], h5 = 0.5 * v * s[5];
    const T g1 = 0.5 * s[1], g2 = 0.5 * s[2];
    const T *d1 = z + 3 * kD1, *d2 = z + 3 * kD2, *d3 = z + 3 * kD3;
    const T *e1 = z + 3 * kD1S, *e2 = z + 3 * kD2S, *e3 = z + 3 * kD3S;
    const T *f1 = z + 3 * kD1SS, *f2 = z + 3 * kD2SS, *f3 = z + 3 * kD3SS;
    const T* p = z + 3 * kPhiS;
    for (int c = 0; c < 3; ++c) {
      g[3 * kPhiS + c] += s[0] * (p[c] - d1[c]);
      g[3 * kD1 + c] -= s[0] * p[c] + g1 * d2[c] + g2 * d3[c];
      g[3 * kD2 + c] -= g1 * d1[c];
      g[3 * kD3 + c] -= g2 * d1[c];
      g[3 * kD1S + c] += h4 * f3[c] - h5 * f2[c];
      g[3 * kD2S + c] += h5 * f1[c] - h3 * f3[c];
      g[3 * kD3S + c] += h3 * f2[c] - h4 * f1[c];
      g[3 * kD1SS + c] = h5 * e2[c] - h4 * e3[c];
      g[3 * kD2SS + c] = h3 * e3[c] - h5 * e1[c];
      g[3 * kD3SS + c] = h4 * e1[c] - h3 * e2[c];
    }
  }
};

// A span's quadrature points side by side in the lanes of one SIMD register (GCC vector
// extension: AVX2 in the x86-64-v3 clone, SSE2 pairs otherwise).
typedef double Lanes __attribute__((vector_size(sizeof(double) * kSpanLanes)));
SB_LANE_INLINE Lanes load(const double* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
SB_LANE_INLINE void store(Lanes v, double* p) { std::memcpy(p, &v, sizeof v); }
SB_LANE_INLINE double lane_sum(Lanes v) {
  double s = 0.0;
  for (int l = 0; l < kSpanLanes; ++l) s += v[l];
  return s;
}

// (always inlined: it must be compiled into each clone of span_residual_em)
// Corrected: the Simo-Reissner forms with the director correction (z then includes d'').
template <class Forms, bool Corrected>
__attribute__((always_inline)) inline void span_residual(const Stiffness& C, const SpanEmState& st, const VecEl& q1, VecEl& r,
                                                         double xi, const double (*gamma_sigma)[kSpanLanes]) {
  constexpr int nz = Corrected ? kNz : 3 * kD1SS;
  Lanes N[3], dN[3], ddN[3], z1[kNz], zm[kNz], e1[6], sigma[6], g[kNz], v{};
  for (int a = 0; a < 3; ++a) {
    N[a] = load(st.N[a]);
    dN[a] = load(st.dN[a]);
    if (Corrected) ddN[a] = load(st.ddN[a]);
  }
  if (Corrected) v = load(st.correction_weight);
  const double* q = q1.data();
  for (int c = 0; c < 3; ++c) z1[c] = dN[0] * q[c] + dN[1] * q[kNq + c] + dN[2] * q[2 * kNq + c];
  for (int k = 3; k < kNq; ++k) {
    const double qa = q[k], qb = q[kNq + k], qc = q[2 * kNq + k];
    z1[k] = N[0] * qa + N[1] * qb + N[2] * qc;
    z1[9 + k] = dN[0] * qa + dN[1] * qb + dN[2] * qc;
    if (Corrected) z1[18 + k] = ddN[0] * qa + ddN[1] * qb + ddN[2] * qc;
  }
  Forms::strains(z1, e1);
  Lanes k1[3], kp1[3];
  if (Corrected) {
    DirectorCorrection::strains(z1, v, e1);
    curvature_form(z1, kD1S, k1);
    curvature_form(z1, kD1SS, kp1);
    Lanes t[3];
    cross3(k1, kp1, t);
    for (int i = 0; i < 3; ++i) e1[3 + i] += 0.5 * v * t[i];
  }
  const double a0 = 0.5 * (1.0 - xi), a1 = 0.5 * (1.0 + xi);
  for (int k = 0; k < 6; ++k) sigma[k] = C(k) * (a0 * load(st.e0[k]) + a1 * e1[k] - load(st.eps0[k]));
  if (gamma_sigma)
    for (int k = 0; k < 3; ++k) sigma[k] = load(gamma_sigma[k]);
  for (int k = 0; k < nz; ++k) zm[k] = 0.5 * (load(st.z0[k]) + z1[k]);
  Forms::gradient(sigma, zm, g);
  if (Corrected) {
    DirectorCorrection::gradient(sigma, zm, v, g);
    Lanes kbar[3], kpbar[3];
    for (int i = 0; i < 3; ++i) {
      kbar[i] = 0.5 * (load(st.k0[i]) + k1[i]);
      kpbar[i] = 0.5 * (load(st.kp0[i]) + kp1[i]);
    }
    turning_gradient(sigma + 3, kbar, kpbar, v, zm, g);
  }
  const Lanes w = load(st.w);
  for (int a = 0; a < 3; ++a) {
    const Lanes wN = w * N[a], wdN = w * dN[a];
    double* ra = r.data() + kNq * a;
    for (int c = 0; c < 3; ++c) ra[c] += lane_sum(wdN * g[c]);
    if (Corrected) {
      const Lanes wddN = w * ddN[a];
      for (int k = 3; k < kNq; ++k) ra[k] += lane_sum(wN * g[k] + wdN * g[9 + k] + wddN * g[18 + k]);
    } else {
      for (int k = 3; k < kNq; ++k) ra[k] += lane_sum(wN * g[k] + wdN * g[9 + k]);
    }
  }
}
}  // namespace

SpanEmState span_em_state(const StrainTable& T, const GaussPoint* gps, const Vec6* eps0, int n_gp, const VecEl& q0) {
  SpanEmState st{};
  st.corrected = &T == &kSimoReissner && n_gp > 0 && gps[0].corrected;
  for (int g = 0; g < n_gp; ++g) {
    const GaussPoint& gp = gps[g];
    for (int a = 0; a < 3; ++a) {
      st.N[a][g] = gp.N[a];
      st.dN[a][g] = gp.dN[a];
    }
    st.w[g] = gp.w;
    for (int a = 0; a < 3; ++a) st.ddN[a][g] = gp.ddN[a];
    st.correction_weight[g] = gp.correction_weight;
    const VecZ z = apply_P(gp, q0);
    const Vec6 e = point_strains(T, gp, z);
    for (int k = 0; k < kNz; ++k) st.z0[k][g] = z(k);
    if (st.corrected) {
      const Eigen::Vector3d k0 = curvature_at(z, kD1S), kp0 = curvature_at(z, kD1SS);
      for (int i = 0; i < 3; ++i) {
        st.k0[i][g] = k0(i);
        st.kp0[i][g] = kp0(i);
      }
    }
    for (int k = 0; k < 6; ++k) {
      st.e0[k][g] = e(k);
      st.eps0[k][g] = eps0[g](k);
    }
  }
  return st;
}

SB_HOT_KERNEL
void span_residual_em(const StrainTable& T, const Stiffness& C, const SpanEmState& st, const VecEl& q1, VecEl& r,
                      double xi, const double (*gamma_sigma)[kSpanLanes]) {
  if (&T == &kSimoReissner) {
    if (st.corrected)
      span_residual<SimoReissnerForms, true>(C, st, q1, r, xi, gamma_sigma);
    else
      span_residual<SimoReissnerForms, false>(C, st, q1, r, xi, gamma_sigma);
    return;
  }
  if (&T == &kSeed) {
    span_residual<SeedForms, false>(C, st, q1, r, xi, gamma_sigma);
    return;
  }
  // a table known only at run time: point by point
  for (int g = 0; g < kSpanLanes && st.w[g] != 0.0; ++g) {
    VecZ z0;
    Vec6 e0, ref;
    GaussPoint gp{};
    for (int a = 0; a < 3; ++a) {
      gp.N[a] = st.N[a][g];
      gp.dN[a] = st.dN[a][g];
      gp.ddN[a] = st.ddN[a][g];
    }
    gp.w = st.w[g];
    gp.correction_weight = st.correction_weight[g];
    gp.corrected = st.corrected;
    for (int k = 0; k < kNz; ++k) z0(k) = st.z0[k][g];
    for (int k = 0; k < 6; ++k) {
      e0(k) = st.e0[k][g];
      ref(k) = st.eps0[k][g];
    }
    const StrainTable Tg = point_table(T, gp);
    const VecZ z1 = apply_P(gp, q1);
    Vec6 sigma = C.cwiseProduct(0.5 * (1.0 - xi) * e0 + 0.5 * (1.0 + xi) * strains(Tg, z1) - ref);
    if (gamma_sigma)
      for (int k = 0; k < 3; ++k) sigma(k) = gamma_sigma[k][g];
    add_Pt(gp, gp.w, weighted_gradient(Tg, sigma, 0.5 * (z0 + z1)), r);
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

namespace {
// The 6 x 6 normal equations (G G^T) dlambda = -G f / s by an unrolled Cholesky: for triads far
// from orthonormal.
void multiplier_update_cholesky(const double (&d)[3][3], double* const (&f)[3], double* lambda, double s) {
  double g[6], A[6][6];
  for (int r = 0; r < 6; ++r) {
    const int a = kTriadPairA[r], b = kTriadPairB[r];
    g[r] = a == b ? dot3(d[a], f[a]) : dot3(d[b], f[a]) + dot3(d[a], f[b]);
  }
  // <row r, row c> = sum over director slots of the products of their 3-blocks; every such
  // product is an entry of the directors' Gram matrix
  double gram[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j) gram[i][j] = gram[j][i] = dot3(d[i], d[j]);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c <= r; ++c) {
      // row r has d[rb] in slot ra and d[ra] in slot rb (once if ra == rb)
      const int ra = kTriadPairA[r], rb = kTriadPairB[r], ca = kTriadPairA[c], cb = kTriadPairB[c];
      double v = 0.0;
      if (ra == ca) v += gram[rb][cb];
      if (cb != ca && ra == cb) v += gram[rb][ca];
      if (rb != ra) {
        if (rb == ca) v += gram[ra][cb];
        if (cb != ca && rb == cb) v += gram[ra][ca];
      }
      A[r][c] = v;
    }
  double inv[6];  // 1 / L_jj: multiplications instead of a division per entry
  for (int j = 0; j < 6; ++j) {  // Cholesky A = L L^T in place (lower triangle)
    double djj = A[j][j];
    for (int k = 0; k < j; ++k) djj -= A[j][k] * A[j][k];
    inv[j] = 1.0 / std::sqrt(djj);
    for (int i = j + 1; i < 6; ++i) {
      double v = A[i][j];
      for (int k = 0; k < j; ++k) v -= A[i][k] * A[j][k];
      A[i][j] = v * inv[j];
    }
  }
  for (int i = 0; i < 6; ++i) {  // L y = g
    for (int k = 0; k < i; ++k) g[i] -= A[i][k] * g[k];
    g[i] *= inv[i];
  }
  for (int i = 5; i >= 0; --i) {  // L^T x = y
    for (int k = i + 1; k < 6; ++k) g[i] -= A[k][i] * g[k];
    g[i] *= inv[i];
  }
  const double inv_s = 1.0 / s;
  for (int r = 0; r < 6; ++r) {
    const double dl = -g[r] * inv_s;
    lambda[r] += dl;
    const int a = kTriadPairA[r], b = kTriadPairB[r];
    for (int k = 0; k < 3; ++k) {
      f[a][k] += s * dl * d[b][k];
      if (b != a) f[b][k] += s * dl * d[a][k];
    }
  }
}
}  // namespace

// In matrix form the constraint forces are s D Lambda (D = [d1 d2 d3], Lambda symmetric: its
// diagonal the multipliers of 1/2 d_a.d_a, its off-diagonal those of d_a.d_b), and G f is the
// symmetric part of D^T f. The update is the Lyapunov equation S dLambda + dLambda S = -B with
// S = D^T D, B = (D^T f + f^T D) / s. A nearly orthonormal triad (S = I + E; the midpoint triad of
// energy-momentum has |E| ~ rotation^2 / 4) solves it by the sweeps dLambda = -(B + E dLambda +
// dLambda E) / 2, each gaining -log10|E| digits: two or three 3 x 3 products instead of the
// Cholesky's chain of square roots and divisions. This runs at every Newton iterate of every
// triad.
SB_HOT_KERNEL
void orthonormality_multiplier_update(const double (&d)[3][3], double* const (&f)[3], double* lambda, double s) {
  double E[3][3], B[3][3], L[3][3], X[3][3];
  double emax = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      X[a][b] = dot3(d[a], f[b]);
      E[a][b] = dot3(d[a], d[b]) - (a == b ? 1.0 : 0.0);
      emax = std::max(emax, std::abs(E[a][b]));
    }
  if (!(emax < 0.05)) {
    multiplier_update_cholesky(d, f, lambda, s);
    return;
  }
  const double inv_s = 1.0 / s;
  double lmax = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      B[a][b] = (X[a][b] + X[b][a]) * inv_s;
      L[a][b] = -0.5 * B[a][b];
      lmax = std::max(lmax, std::abs(L[a][b]));
    }
  // each sweep multiplies the error by at most 3 emax (< 0.15)
  for (int it = 0; it < 40 && emax * lmax > 0.0; ++it) {
    double P[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) P[a][b] = E[a][0] * L[0][b] + E[a][1] * L[1][b] + E[a][2] * L[2][b];
    double change = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = a; b < 3; ++b) {
        const double v = -0.5 * (B[a][b] + P[a][b] + P[b][a]);
        change = std::max(change, std::abs(v - L[a][b]));
        L[a][b] = L[b][a] = v;
      }
    if (change <= 1e-17 * lmax) break;
  }
  for (int r = 0; r < 6; ++r) lambda[r] += L[kTriadPairA[r]][kTriadPairB[r]];
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) f[a][k] += s * (L[a][0] * d[0][k] + L[a][1] * d[1][k] + L[a][2] * d[2][k]);
}

SB_HOT_KERNEL
void closest_orthonormal_frame(double* d) {
  Eigen::Map<Eigen::Matrix3d> D(d);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d A = D.transpose() * D;
  double err = (A - I).cwiseAbs().maxCoeff();
  if (err < 0.1) {
    // Newton-Schulz converges quadratically: from a Newton update's O(|w|^2) error, two
    // iterations reach roundoff (a few ulp; asking for less only spins to the cap). One
    // product D^T D per iteration serves both the test and the update.
    for (int it = 0; it < 6 && err > 4e-16; ++it) {
      D = 0.5 * D * (3.0 * I - A);
      A.noalias() = D.transpose() * D;
      err = (A - I).cwiseAbs().maxCoeff();
    }
    return;
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(D, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() > 0) D = R;
}

}  // namespace slidebeam::kernels
