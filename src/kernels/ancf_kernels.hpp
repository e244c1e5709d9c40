// SPDX-License-Identifier: MIT
#pragma once
/// @file Element kernels of the 3D gradient-deficient ANCF cable (Gerstmayr & Irschik 2008;
/// the element of Exudyn's ObjectANCFCable).
///
/// Element: 2 nodes, each with position r and slope r' = dr/dx (6 coordinates per node), cubic
/// Hermite interpolation in the reference arc length x in [0, Le]. Element coordinates
///   q = (r_1, r'_1, r_2, r'_2) in R^12,   r(x) = sum_a S_a(x) q_a   (q_a = 3-blocks of q).
///
/// Strain energy: Green axial strain and the quadratic bending form of Berzeri & Shabana (2000),
///   U_e = 1/2 int EA eps^2 dx + 1/2 int EI |r'' - r0''|^2 dx,   eps = 1/2 (r'.r' - r0'.r0'),
/// with r0 the reference (stress-free) configuration. Both strains are quadratic (eps) or linear
/// (r'') in q, so, exactly as for the director beam (docs/theory.md, "The schemes"), the averaged-strain
/// energy-momentum force is an exact discrete gradient.
///
/// Limitations, by construction:
///  * |r''| is the curvature only for an inextensible, arc-length parametrised centre line
///    (|r'| = 1). Stretch couples into bending: |r''|^2 = |r'|^4 kappa^2 + (d|r'|/dx)^2.
///    For EA >> EI/L^2 the cable is nearly inextensible and the error is O(EI kappa^2 / EA).
///  * |r'' - r0''|^2 is frame-indifferent only for a STRAIGHT reference (r0'' = 0). With a curved
///    reference a rigid rotation produces spurious bending energy, and the internal force is no
///    longer torque-free (angular momentum is then not conserved). Use a straight stress-free
///    state, or accept that error for small rotations of curved pieces.
///  * x should be the arc length of the reference (|r0'| = 1): eps is then the Green strain and
///    EA, EI have their usual meaning. For a curved Hermite reference |r0'| deviates slightly
///    from 1; eps0 is taken pointwise so the reference is still stress-free.
///  * No torsion, no shear, no rotary inertia (cable).
///
/// Quadrature: axial energy and mass with 5 Gauss points (eps^2 and S_a S_b are polynomials of
/// degree 8 and 6: exact), bending with 3 points (r'' is linear: exact). So energy, force,
/// tangent, energy-momentum force and mass are all exact integrals of the stated energy.
///
/// Pure functions of local data: no PETSc, no MPI, no heap allocation.

#include <Eigen/Dense>
#include <array>

namespace slidebeam::kernels::ancf {

constexpr int kNodeDofs = 6;    ///< r, r' per node
constexpr int kElDofs = 12;     ///< 2 nodes
constexpr int kAxialPoints = 5; ///< Gauss points of the axial term and the mass matrix
constexpr int kBendPoints = 3;  ///< Gauss points of the bending term

/// Coordinate blocks of q (3 entries each).
enum Block : int { kR1 = 0, kS1 = 1, kR2 = 2, kS2 = 3 };

using ElVec = Eigen::Matrix<double, kElDofs, 1>;
using ElMat = Eigen::Matrix<double, kElDofs, kElDofs>;
using Mat3x12 = Eigen::Matrix<double, 3, kElDofs>;

/// Cubic Hermite basis on [0, Le] in the order (node-1 position, node-1 slope, node-2 position,
/// node-2 slope): value S, first derivative S' = dS/dx and second derivative S'' = d2S/dx2.
struct HermiteBasis {
  std::array<double, 4> S{};
  std::array<double, 4> dS{};
  std::array<double, 4> ddS{};
};

/// Basis at x (x may lie outside [0, Le]: the cubic is extended).
HermiteBasis hermite(double x, double Le);

/// The 3 x 12 interpolation matrix [w_0 I, w_1 I, w_2 I, w_3 I] of four basis weights, e.g.
/// shape_matrix(hermite(x, Le).S) * q = r(x). This is the Jacobian of r(x) (or r'(x)) w.r.t. q.
Mat3x12 shape_matrix(const std::array<double, 4>& w);

/// sum_a w_a q_a
Eigen::Vector3d interpolate(const std::array<double, 4>& w, const ElVec& q);

/// Cross-section data: axial stiffness, bending stiffness, mass per unit reference length.
struct AncfSection {
  double EA = 0.0;
  double EI = 0.0;
  double rhoA = 0.0;
};

/// Axial/mass quadrature point: shape values and slopes, weight (in x), reference eps term
/// eps0 = 1/2 r0'.r0'.
struct AxialPoint {
  std::array<double, 4> S{};
  std::array<double, 4> dS{};
  double w = 0.0;
  double half_s0s0 = 0.0;
};

/// Bending quadrature point: second derivatives, weight, reference r0''.
struct BendPoint {
  std::array<double, 4> ddS{};
  double w = 0.0;
  Eigen::Vector3d ddr0 = Eigen::Vector3d::Zero();
};

/// Tables of one element, built once from its reference coordinates.
struct AncfElement {
  double Le = 0.0;
  std::array<AxialPoint, kAxialPoints> axial{};
  std::array<BendPoint, kBendPoints> bend{};
};

/// Element tables for the reference configuration q_ref (stress-free) and reference length Le.
/// For a straight reference pass r'_1 = r'_2 = unit tangent and Le = |r_2 - r_1|.
AncfElement make_element(double Le, const ElVec& q_ref);

/// Straight reference from node positions: slopes = (X2 - X1)/|X2 - X1|, Le = |X2 - X1|.
ElVec straight_reference(const Eigen::Vector3d& X1, const Eigen::Vector3d& X2);

/// Axial strain eps = 1/2 (r'.r' - r0'.r0') at axial point g.
double axial_strain(const AncfElement& el, int g, const ElVec& q);

/// Strain energy U_e(q).
double energy(const AncfSection& sec, const AncfElement& el, const ElVec& q);

/// Internal force f = dU/dq and (if K is given) the exact tangent K = d2U/dq2. Both are
/// overwritten (not accumulated).
void internal_force(const AncfSection& sec, const AncfElement& el, const ElVec& q, ElVec& f, ElMat* K);

/// Energy-momentum internal force of the step q0 -> q1 (docs/theory.md, "The schemes"):
///   f = int EA eps_avg (d eps/dq)(q_m) dx + int EI S''^T (r''(q_m) - r0'') dx,
/// eps_avg = 1/2 (eps(q0) + eps(q1)), q_m = 1/2 (q0 + q1). Then f . (q1 - q0) = U(q1) - U(q0)
/// exactly (up to roundoff). K (if given) = d f / d q1, exact. Both overwritten.
/// xi > 0 (energy-decaying variant, as the director beam's): the stresses use
/// 1/2 (1 - xi) strain(q0) + 1/2 (1 + xi) strain(q1) for both strains, so the step dissipates
/// xi/2 int (EA deps^2 + EI |d r''|^2) dx >= 0 and still conserves both momenta (straight reference).
void internal_force_em(const AncfSection& sec, const AncfElement& el, const ElVec& q0, const ElVec& q1,
                       ElVec& f, ElMat* K, double xi = 0.0);

/// Kelvin-Voigt damping over the step q0 -> q1 (beam_damping on a cable), accumulated into f and K:
///   f += int c_axial deps/dt (d eps/dq)(q_f) dx + int c_bend S''^T d r''/dt dx,
/// with the mean rates deps/dt = (eps(q1) - eps(q0)) / h and d r''/dt = r''(q1 - q0) / h, q_f =
/// (1 - theta) q0 + theta q1; K += d f / d q1. eps being quadratic, f . (q1 - q0) at theta = 1/2 is
/// int (c_axial deps^2 + c_bend |d r''|^2) dx / h >= 0 exactly.
void kelvin_voigt(const AncfElement& el, double c_axial, double c_bend, double h, double theta, const ElVec& q0,
                  const ElVec& q1, ElVec& f, ElMat* K);

/// Consistent mass matrix M = int rhoA S^T S dx (12 x 12, exact).
ElMat mass_matrix(const AncfSection& sec, const AncfElement& el);

/// Gravity load int rhoA S^T g dx (12, exact). Its potential is -q . load.
ElVec gravity_load(const AncfSection& sec, const AncfElement& el, const Eigen::Vector3d& g);

/// A point of the cable at local coordinate x: r, r', r'' and the basis weights that give them
/// (r = shape_matrix(basis.S) q, r' = shape_matrix(basis.dS) q, ...). For sliding joints on
/// ANCF carriers: d r / d q = shape_matrix(basis.S), d r / d x = r'.
struct CablePoint {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  Eigen::Vector3d dr = Eigen::Vector3d::Zero();
  Eigen::Vector3d ddr = Eigen::Vector3d::Zero();
  HermiteBasis basis{};
};
CablePoint evaluate(double Le, double x, const ElVec& q);

}  // namespace slidebeam::kernels::ancf
