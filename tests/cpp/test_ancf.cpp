// SPDX-License-Identifier: MIT
// Tests of the ANCF cable kernels: Hermite basis, finite-difference checks of force, tangent and
// energy-momentum force, the discrete-gradient identity, rigid-motion invariance, mass and gravity,
// a static roll-up under an end moment (dense Newton) and a free-flying energy-momentum run.
#include "kernels/ancf_kernels.hpp"

#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <random>
#include <vector>

using namespace slidebeam::kernels::ancf;

namespace {
constexpr double kPi = 3.14159265358979323846;

// A curved reference element: a piece of a helix of radius 2, pitch 0.3 per radian, between
// angles t0 and t1, parametrised by arc length (|r0'| = 1 at the nodes).
AncfElement helix_element(double t0, double t1, ElVec& q_ref) {
  const double R = 2.0, c = 0.3, v = std::sqrt(R * R + c * c);
  auto pos = [&](double t) -> Eigen::Vector3d { return Eigen::Vector3d(R * std::cos(t), R * std::sin(t), c * t); };
  auto tan = [&](double t) -> Eigen::Vector3d { return Eigen::Vector3d(-R * std::sin(t), R * std::cos(t), c) / v; };
  q_ref << pos(t0), tan(t0), pos(t1), tan(t1);
  return make_element(v * (t1 - t0), q_ref);
}

// A curved, stretched state: the reference rotated, stretched by 3 %, plus random noise.
ElVec deformed(const ElVec& q_ref, unsigned seed, double noise = 0.05) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-noise, noise);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -1, 2).normalized()).toRotationMatrix();
  ElVec q;
  for (int a = 0; a < 4; ++a) q.segment<3>(3 * a) = 1.03 * R * q_ref.segment<3>(3 * a);
  for (int i = 0; i < kElDofs; ++i) q(i) += u(gen);
  return q;
}

const AncfSection kSec{2.0e3, 3.0, 1.7};

// Measured numbers go to stdout on rank 0 only (every rank runs every test).
void report(const char* fmt, ...) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;
  std::va_list args;
  va_start(args, fmt);
  std::printf("[ ANCF     ] ");
  std::vprintf(fmt, args);
  va_end(args);
}
}  // namespace

TEST(AncfHermite, InterpolatesNodalValuesAndDerivativesAreConsistent) {
  const double Le = 0.7;
  const HermiteBasis b0 = hermite(0.0, Le), b1 = hermite(Le, Le);
  for (int a = 0; a < 4; ++a) {
    EXPECT_NEAR(b0.S[a], a == 0 ? 1.0 : 0.0, 1e-15);
    EXPECT_NEAR(b0.dS[a], a == 1 ? 1.0 : 0.0, 1e-15);
    EXPECT_NEAR(b1.S[a], a == 2 ? 1.0 : 0.0, 1e-15);
    EXPECT_NEAR(b1.dS[a], a == 3 ? 1.0 : 0.0, 1e-14);
  }
  const double h = 1e-6;
  for (double x : {0.1, 0.33, 0.69}) {
    const HermiteBasis b = hermite(x, Le), bp = hermite(x + h, Le), bm = hermite(x - h, Le);
    for (int a = 0; a < 4; ++a) {
      EXPECT_NEAR(b.dS[a], (bp.S[a] - bm.S[a]) / (2 * h), 1e-8);
      EXPECT_NEAR(b.ddS[a], (bp.dS[a] - bm.dS[a]) / (2 * h), 1e-8);
    }
    // a straight line r = X + x t is reproduced exactly, including r' = t and r'' = 0
    const Eigen::Vector3d X(0.2, -1, 3), t = Eigen::Vector3d(1, 2, -2) / 3.0;
    const ElVec q = straight_reference(X, X + Le * t);
    const CablePoint c = evaluate(Le, x, q);
    EXPECT_LT((c.r - (X + x * t)).norm(), 1e-14);
    EXPECT_LT((c.dr - t).norm(), 1e-14);
    EXPECT_LT(c.ddr.norm(), 1e-13);
    EXPECT_LT((shape_matrix(c.basis.S) * q - c.r).norm(), 1e-15);
    EXPECT_LT((shape_matrix(c.basis.dS) * q - c.dr).norm(), 1e-15);
  }
}

TEST(AncfKernels, ForceIsEnergyGradientAndTangentIsForceDerivative) {
  // Curved (helix) reference, so eps0 and r0'' are exercised; curved, stretched current state.
  ElVec q_ref;
  const AncfElement el = helix_element(0.2, 0.9, q_ref);
  ElVec f0;
  internal_force(kSec, el, q_ref, f0, nullptr);
  EXPECT_LT(f0.norm(), 1e-12) << "reference state must be stress-free";
  EXPECT_LT(energy(kSec, el, q_ref), 1e-26);
  const ElVec q = deformed(q_ref, 7);
  ElVec f;
  ElMat K;
  internal_force(kSec, el, q, f, &K);
  ASSERT_GT(f.norm(), 1.0);
  // central differences, step 1e-6: truncation O(h^2 * U''') ~ 1e-9 relative, roundoff ~1e-10
  const double h = 1e-6, tol = 1e-6;
  for (int i = 0; i < kElDofs; ++i) {
    ElVec qp = q, qm = q;
    qp(i) += h;
    qm(i) -= h;
    const double dU = (energy(kSec, el, qp) - energy(kSec, el, qm)) / (2 * h);
    EXPECT_NEAR(f(i), dU, tol * f.norm()) << "force entry " << i;
    ElVec fp, fm;
    internal_force(kSec, el, qp, fp, nullptr);
    internal_force(kSec, el, qm, fm, nullptr);
    const ElVec col = (fp - fm) / (2 * h);
    EXPECT_LT((K.col(i) - col).norm(), tol * K.norm()) << "tangent column " << i;
  }
  EXPECT_LT((K - K.transpose()).norm(), 1e-13 * K.norm());
}

TEST(AncfKernels, EnergyMomentumForceDerivativeMatchesFiniteDifferences) {
  ElVec q_ref;
  const AncfElement el = helix_element(-0.3, 0.5, q_ref);
  const ElVec q0 = deformed(q_ref, 11), q1 = deformed(q_ref, 12, 0.2);
  for (double xi : {0.0, 0.3}) {
    ElVec f;
    ElMat K;
    internal_force_em(kSec, el, q0, q1, f, &K, xi);
    const double h = 1e-6, tol = 1e-6;
    for (int i = 0; i < kElDofs; ++i) {
      ElVec qp = q1, qm = q1, fp, fm;
      qp(i) += h;
      qm(i) -= h;
      internal_force_em(kSec, el, q0, qp, fp, nullptr, xi);
      internal_force_em(kSec, el, q0, qm, fm, nullptr, xi);
      const ElVec col = (fp - fm) / (2 * h);
      EXPECT_LT((K.col(i) - col).norm(), tol * K.norm()) << "xi " << xi << " column " << i;
    }
  }
  // With q0 == q1 the EM force is the ordinary internal force.
  ElVec f, fem;
  internal_force(kSec, el, q1, f, nullptr);
  internal_force_em(kSec, el, q1, q1, fem, nullptr);
  EXPECT_LT((f - fem).norm(), 1e-13 * f.norm());
}

TEST(AncfKernels, EnergyMomentumForceIsDiscreteGradientForLargeStep) {
  ElVec q_ref;
  const AncfElement el = helix_element(0.0, 1.1, q_ref);
  const ElVec q0 = deformed(q_ref, 3);
  // a large step: rotate by 1 rad, stretch by 10 %, shift, and add 0.3 of noise
  ElVec q1 = deformed(q_ref, 4, 0.3);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.0, Eigen::Vector3d(0.3, 1, -0.2).normalized()).toRotationMatrix();
  for (int a = 0; a < 4; ++a) q1.segment<3>(3 * a) = 1.1 * R * q1.segment<3>(3 * a);
  q1.segment<3>(0) += Eigen::Vector3d(0.5, -0.2, 1.0);
  q1.segment<3>(6) += Eigen::Vector3d(0.5, -0.2, 1.0);
  const double U0 = energy(kSec, el, q0), U1 = energy(kSec, el, q1);
  ElVec f;
  internal_force_em(kSec, el, q0, q1, f, nullptr);
  const double work = f.dot(q1 - q0);
  const double scale = std::max(std::abs(U0), std::abs(U1));
  report("EM discrete gradient: U0 %.6e U1 %.6e, |f.dq - dU| / U = %.2e\n", U0, U1,
              std::abs(work - (U1 - U0)) / scale);
  EXPECT_LT(std::abs(work - (U1 - U0)), 1e-12 * scale);
  // The midpoint-rule force (strain at q_m instead of the averaged strain) is not a discrete gradient:
  ElVec fmid;
  internal_force(kSec, el, 0.5 * (q0 + q1), fmid, nullptr);
  EXPECT_GT(std::abs(fmid.dot(q1 - q0) - (U1 - U0)), 1e-3 * scale);
  // xi > 0: the step dissipates xi/2 int (EA deps^2 + EI |d r''|^2) dx >= 0.
  const double xi = 0.2;
  ElVec fx;
  internal_force_em(kSec, el, q0, q1, fx, nullptr, xi);
  double diss = 0.0;
  for (int g = 0; g < kAxialPoints; ++g) {
    const double de = axial_strain(el, g, q1) - axial_strain(el, g, q0);
    diss += 0.5 * xi * el.axial[g].w * kSec.EA * de * de;
  }
  for (const BendPoint& p : el.bend)
    diss += 0.5 * xi * p.w * kSec.EI * (interpolate(p.ddS, q1) - interpolate(p.ddS, q0)).squaredNorm();
  EXPECT_GT(diss, 0.0);
  EXPECT_NEAR(fx.dot(q1 - q0), U1 - U0 + diss, 1e-12 * scale);
}

TEST(AncfKernels, RigidMotionOfStraightReferenceIsStressFree) {
  const Eigen::Vector3d X1(0.3, 0.1, -0.2), X2 = X1 + 1.7 * Eigen::Vector3d(2, -1, 2) / 3.0;
  const ElVec q_ref = straight_reference(X1, X2);
  const AncfElement el = make_element((X2 - X1).norm(), q_ref);
  const AncfSection sec{1e6, 2.0, 1.0};
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(1, -2, 0.5);
  ElVec q;
  q << R * X1 + t, R * q_ref.segment<3>(3), R * X2 + t, R * q_ref.segment<3>(9);
  ElVec f;
  ElMat K;
  internal_force(sec, el, q, f, &K);
  EXPECT_LT(energy(sec, el, q), 1e-20);
  EXPECT_LT(f.norm(), 1e-9);  // EA = 1e6: roundoff of eps ~1e-16 gives forces ~1e-10
  // The tangent annihilates infinitesimal rigid motions (translations and rotations).
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
    ElVec tr = ElVec::Zero(), rot;
    tr.segment<3>(0) = e;
    tr.segment<3>(6) = e;
    for (int a = 0; a < 4; ++a) rot.segment<3>(3 * a) = e.cross(q.segment<3>(3 * a));
    EXPECT_LT((K * tr).norm(), 1e-9 * K.norm());
    EXPECT_LT((K * rot).norm(), 1e-9 * K.norm());
  }
  // A stretched state is not stress-free (the test can fail).
  ElVec qs = q;
  qs.segment<3>(9) *= 1.01;
  EXPECT_GT(energy(sec, el, qs), 1.0);
}

TEST(AncfKernels, MassMatrixAndGravity) {
  const double Le = 0.8;
  const ElVec q_ref = straight_reference(Eigen::Vector3d::Zero(), Eigen::Vector3d(Le, 0, 0));
  const AncfElement el = make_element(Le, q_ref);
  const AncfSection sec{1.0, 1.0, 2.5};
  const ElMat M = mass_matrix(sec, el);
  // the classical Hermite mass matrix rhoA Le / 420 [...] (x) I3
  Eigen::Matrix4d m;
  const double L = Le;
  m << 156, 22 * L, 54, -13 * L, 22 * L, 4 * L * L, 13 * L, -3 * L * L, 54, 13 * L, 156, -22 * L, -13 * L,
      -3 * L * L, -22 * L, 4 * L * L;
  m *= sec.rhoA * Le / 420.0;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      EXPECT_LT((M.block<3, 3>(3 * a, 3 * b) - m(a, b) * Eigen::Matrix3d::Identity()).norm(), 1e-14);
  // unit rigid translation: u^T M u = rhoA Le
  for (int k = 0; k < 3; ++k) {
    ElVec u = ElVec::Zero();
    u(k) = u(6 + k) = 1.0;
    EXPECT_NEAR(u.dot(M * u), sec.rhoA * Le, 1e-14);
  }
  // gravity: the position entries sum to rhoA Le g, the load equals M u_g (u_g the translation by g)
  const Eigen::Vector3d g(0.1, -9.81, 0.3);
  const ElVec fg = gravity_load(sec, el, g);
  EXPECT_LT((fg.segment<3>(0) + fg.segment<3>(6) - sec.rhoA * Le * g).norm(), 1e-13);
  ElVec ug = ElVec::Zero();
  ug.segment<3>(0) = ug.segment<3>(6) = g;
  EXPECT_LT((fg - M * ug).norm(), 1e-13);
  EXPECT_NEAR(fg(3 + 1), sec.rhoA * g.y() * Le * Le / 12.0, 1e-14);  // int S_2 = Le^2 / 12
}

// ------------------------------------------------------------------------------------------------
// Multi-element helpers (dense, test only). Node n owns coordinates 6n .. 6n+5 = (r, r'), so
// element e's 12 coordinates are the contiguous segment 6e .. 6e+11.
namespace {
struct Cable {
  AncfSection sec;
  std::vector<AncfElement> els;
  int n_dofs() const { return 6 * (static_cast<int>(els.size()) + 1); }
};

Cable straight_cable(const AncfSection& sec, int N, double L, Eigen::VectorXd& q) {
  Cable c{sec, {}};
  q.resize(6 * (N + 1));
  for (int n = 0; n <= N; ++n) q.segment<6>(6 * n) << n * L / N, 0, 0, 1, 0, 0;
  for (int e = 0; e < N; ++e) c.els.push_back(make_element(L / N, q.segment<12>(6 * e)));
  return c;
}

double total_energy(const Cable& c, const Eigen::VectorXd& q) {
  double U = 0;
  for (size_t e = 0; e < c.els.size(); ++e) U += energy(c.sec, c.els[e], q.segment<12>(6 * e));
  return U;
}

void assemble(const Cable& c, const Eigen::VectorXd& q, Eigen::VectorXd& f, Eigen::MatrixXd& K) {
  f.setZero(c.n_dofs());
  K.setZero(c.n_dofs(), c.n_dofs());
  ElVec fe;
  ElMat Ke;
  for (size_t e = 0; e < c.els.size(); ++e) {
    internal_force(c.sec, c.els[e], q.segment<12>(6 * e), fe, &Ke);
    f.segment<12>(6 * e) += fe;
    K.block<12, 12>(6 * e, 6 * e) += Ke;
  }
}

void assemble_em(const Cable& c, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, Eigen::VectorXd& f,
                 Eigen::MatrixXd& K) {
  f.setZero(c.n_dofs());
  K.setZero(c.n_dofs(), c.n_dofs());
  ElVec fe;
  ElMat Ke;
  for (size_t e = 0; e < c.els.size(); ++e) {
    internal_force_em(c.sec, c.els[e], q0.segment<12>(6 * e), q1.segment<12>(6 * e), fe, &Ke);
    f.segment<12>(6 * e) += fe;
    K.block<12, 12>(6 * e, 6 * e) += Ke;
  }
}

Eigen::MatrixXd global_mass(const Cable& c) {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(c.n_dofs(), c.n_dofs());
  for (size_t e = 0; e < c.els.size(); ++e) M.block<12, 12>(6 * e, 6 * e) += mass_matrix(c.sec, c.els[e]);
  return M;
}

// Roll-up of a cantilever (L = 1, EI = 1, EA = 1e6) under an end moment M = 2 pi EI / L about z.
// The moment is the conservative load with potential -M theta, theta = atan2(r'_y, r'_x) the angle
// of the end slope in the x-y plane (a branch-free gradient field, so load stepping keeps it
// continuous). Returns the tip position; `steps` load steps, dense Newton on the free coordinates.
Eigen::Vector3d roll_up(int N, int steps, int& newton_total) {
  const double L = 1.0, EI = 1.0, EA = 1e6, Mz = 2 * kPi * EI / L;
  Eigen::VectorXd q;
  const Cable c = straight_cable({EA, EI, 1.0}, N, L, q);
  const int n = c.n_dofs(), nf = n - 6, ts = 6 * N + 3;  // first 6 clamped; tip slope at ts
  Eigen::VectorXd f;
  Eigen::MatrixXd K;
  newton_total = 0;
  for (int s = 1; s <= steps; ++s) {
    const double m = Mz * s / steps;
    for (int it = 0;; ++it) {
      EXPECT_LT(it, 30) << "Newton did not converge, N " << N << " step " << s;
      if (it >= 30) return q.segment<3>(6 * N);
      assemble(c, q, f, K);
      const double a = q(ts), b = q(ts + 1), r2 = a * a + b * b;
      f(ts) -= m * (-b / r2);
      f(ts + 1) -= m * (a / r2);
      K(ts, ts) -= m * 2 * a * b / (r2 * r2);
      K(ts, ts + 1) -= m * (b * b - a * a) / (r2 * r2);
      K(ts + 1, ts) -= m * (b * b - a * a) / (r2 * r2);
      K(ts + 1, ts + 1) -= m * (-2 * a * b) / (r2 * r2);
      const Eigen::VectorXd dq = K.bottomRightCorner(nf, nf).partialPivLu().solve(-f.tail(nf));
      q.tail(nf) += dq;
      ++newton_total;
      if (dq.lpNorm<Eigen::Infinity>() < 1e-12) break;
    }
  }
  return q.segment<3>(6 * N);
}
}  // namespace

TEST(AncfStatic, EndMomentRollsCantileverUpToFullCircle) {
  // Continuum solution of this energy (uniform state, ignoring the O(sqrt(EI/EA)) boundary layer at
  // the clamp): slope angle rate k, stretch l with EI l^2 k = M and EA eps = -EI k^2 (the Green
  // strain couples bending and stretch), eps = (l^2 - 1)/2. The tip is then l/k (sin kL, 1 - cos kL),
  // ~7.9e-5 away from the root for EA = 1e6: the floor of |tip - root|.
  const double L = 1.0, EI = 1.0, EA = 1e6, M = 2 * kPi * EI / L;
  double k = M / EI, l = 1.0;
  for (int i = 0; i < 50; ++i) {
    l = std::sqrt(1.0 - 2.0 * EI * k * k / EA);
    k = M / (EI * l * l);
  }
  const Eigen::Vector3d exact(l / k * std::sin(k * L), l / k * (1 - std::cos(k * L)), 0.0);
  // Tolerances on |tip - continuum| per N: the observed error (2.6e-1, 6.1e-3, 1.2e-4, 6.3e-6) falls
  // by 40, 50, 19 per halving (4th order asymptotically; 90 degrees per element at N = 4), so each
  // bound is ~1.5-2.5x the observed value. |tip - root| adds the ~7.9e-5 floor of finite EA.
  const double tol[4] = {0.3, 1e-2, 2.5e-4, 1.5e-5};
  double prev = 1e300;
  int i = 0;
  for (int N : {4, 8, 16, 32}) {
    int newton = 0;
    const Eigen::Vector3d tip = roll_up(N, 20, newton);
    const double to_root = tip.norm(), to_exact = (tip - exact).norm();
    report("roll-up N %2d: |tip - root| %.3e, |tip - continuum| %.3e, tip (%.3e, %.3e, %.1e), "
                "%d Newton its\n",
                N, to_root, to_exact, tip.x(), tip.y(), tip.z(), newton);
    EXPECT_LT(to_exact, tol[i]) << "N " << N;
    EXPECT_LT(to_root, tol[i] + 1e-4) << "N " << N;
    ++i;
    EXPECT_LT(to_exact, prev) << "error must shrink with N";
    EXPECT_LT(std::abs(tip.z()), 1e-12);
    prev = to_exact;
  }
}

TEST(AncfDynamics, FreeFlyingCableConservesEnergyAndMomenta) {
  // Straight cable, stretched by 2 %, spinning about a skew axis with a translation velocity and a
  // bending perturbation; energy-momentum midpoint scheme
  //   M (v1 - v0)/h + f_EM(q0, q1) = 0,  (q1 - q0)/h = (v0 + v1)/2,
  // solved for q1 by dense Newton (v1 eliminated: R = M (2 (q1 - q0)/h - 2 v0)/h + f_EM).
  const int N = 4;
  const double L = 1.0, h = 2e-3;
  const int steps = 400;
  Eigen::VectorXd q;
  const Cable c = straight_cable({1e4, 0.5, 1.3}, N, L, q);
  const int n = c.n_dofs();
  const Eigen::MatrixXd M = global_mass(c);
  // initial state: stretched about the centre, spin omega, translation v_c, a bending wiggle
  const Eigen::Vector3d xc(0.5 * L, 0, 0), omega(0.4, 1.0, 3.0), vc(0.2, -0.1, 0.05);
  Eigen::VectorXd v(n);
  for (int m = 0; m <= N; ++m) {
    Eigen::Vector3d r = xc + 1.02 * (q.segment<3>(6 * m) - xc), s = 1.02 * q.segment<3>(6 * m + 3);
    q.segment<3>(6 * m) = r;
    q.segment<3>(6 * m + 3) = s;
    v.segment<3>(6 * m) = vc + omega.cross(r) + Eigen::Vector3d(0, 0, 0.3 * std::sin(2 * kPi * m / N));
    v.segment<3>(6 * m + 3) = omega.cross(s);
  }
  auto momenta = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv, Eigen::Vector3d& p, Eigen::Vector3d& J) {
    const Eigen::VectorXd Mv = M * vv;
    p.setZero();
    J.setZero();
    for (int m = 0; m <= N; ++m) {
      p += Mv.segment<3>(6 * m);  // int rhoA rdot = sum over position blocks of (M v)
      J += qq.segment<3>(6 * m).cross(Mv.segment<3>(6 * m)) +
           qq.segment<3>(6 * m + 3).cross(Mv.segment<3>(6 * m + 3));
    }
  };
  auto total = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv) {
    return 0.5 * vv.dot(M * vv) + total_energy(c, qq);
  };
  const double E0 = total(q, v);
  Eigen::Vector3d p0, J0;
  momenta(q, v, p0, J0);
  double max_dE = 0, max_dp = 0, max_dJ = 0, U_min = 1e300, U_max = 0;
  Eigen::VectorXd f;
  Eigen::MatrixXd K;
  int newton = 0;
  for (int s = 0; s < steps; ++s) {
    Eigen::VectorXd q1 = q + h * v;
    for (int it = 0;; ++it) {
      ASSERT_LT(it, 25) << "Newton did not converge at step " << s;
      assemble_em(c, q, q1, f, K);
      const Eigen::VectorXd R = M * (2.0 * (q1 - q) / h - 2.0 * v) / h + f;
      K += (2.0 / (h * h)) * M;
      const Eigen::VectorXd dq = K.partialPivLu().solve(-R);
      q1 += dq;
      ++newton;
      if (dq.lpNorm<Eigen::Infinity>() < 1e-14) break;
    }
    v = 2.0 * (q1 - q) / h - v;
    q = q1;
    Eigen::Vector3d p, J;
    momenta(q, v, p, J);
    const double U = total_energy(c, q);
    U_min = std::min(U_min, U);
    U_max = std::max(U_max, U);
    max_dE = std::max(max_dE, std::abs(total(q, v) - E0) / E0);
    max_dp = std::max(max_dp, (p - p0).norm() / p0.norm());
    max_dJ = std::max(max_dJ, (J - J0).norm() / J0.norm());
  }
  report("EM free flight: %d steps, %d Newton its, E0 %.6e, U in [%.3e, %.3e], max rel dE %.2e, "
              "dp %.2e, dJ %.2e\n",
              steps, newton, E0, U_min, U_max, max_dE, max_dp, max_dJ);
  EXPECT_GT(U_max - U_min, 1e-2 * E0) << "the run must exchange strain and kinetic energy";
  EXPECT_LT(max_dE, 1e-10);
  EXPECT_LT(max_dp, 1e-12);
  EXPECT_LT(max_dJ, 1e-12);
}
