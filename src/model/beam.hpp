// SPDX-License-Identifier: MIT
#pragma once
/// @file A beam: reference control points, section, quadrature tables and reference strains.
/// Two formulations: the director beam (quadratic B-splines, control points phi, d1, d2, d3) and
/// the ANCF cable (cubic Hermite elements, nodes r, r'; kernels/ancf_kernels.hpp). Pure data
/// plus basis evaluation; no PETSc.

#include "kernels/ancf_kernels.hpp"
#include "kernels/beam_kernels.hpp"
#include "kernels/bspline.hpp"

#include <array>
#include <string>
#include <vector>

namespace slidebeam {

/// Section resultant stiffness and inertia (docs/theory.md, "The director beam").
struct Section {
  double EA = 0, kGA2 = 0, kGA3 = 0, GJ = 0, EI2 = 0, EI3 = 0;
  double rhoA = 0, rhoI2 = 0, rhoI3 = 0;
};

/// How a beam is discretised.
///  - Director: n_spans quadratic B-spline spans, n_spans + 2 control points of 12 coordinates
///    (phi, d1, d2, d3) and 6 orthonormality multipliers each.
///  - Ancf: n_spans equal cubic Hermite elements of the gradient-deficient ANCF cable,
///    n_spans + 1 nodes of 6 coordinates (r, r' = dr/ds) and no multipliers. Uses EA, EI2 (the
///    one bending stiffness) and rhoA of the section.
///  - Rigid: a rigid body, one control point (phi its centre of mass, d1, d2, d3 its body
///    frame) with the director triad's 6 orthonormality multipliers, no spans and no strain; its
///    inertia is BeamSpec::mass and BeamSpec::euler.
enum class Formulation { Director, Ancf, Rigid };

/// Everything needed to create a beam.
struct BeamSpec {
  std::string name;
  Formulation formulation = Formulation::Director;
  int n_spans = 1;  ///< knot spans (director) or elements (ANCF)
  double length = 1.0;  ///< reference arc length L; the spline parameter is xi = s / L
  Section section;
  kernels::StrainMeasure strain = kernels::StrainMeasure::SimoReissner;
  kernels::Quadrature quadrature = kernels::Quadrature::Full;
  /// Reference coordinates of the control points, row-major: (n_spans+2) x 12 (phi, d1, d2, d3)
  /// for a director beam, (n_spans+1) x 6 (r, r') for an ANCF cable.
  std::vector<double> q_ref;
  /// > 0 (director beams, Simo-Reissner strains): a rope's stress-free state is straight and
  /// untwisted, of this length; q_ref (of arc length `length`) is only where it starts. 0: q_ref
  /// is the stress-free state.
  double unstretched_length = 0.0;
  /// Rigid: the body's mass and its Euler tensor E = int X X^T dm about the centre of mass, in
  /// components of its body frame (row-major; E = tr(J)/2 I - J for the inertia tensor J).
  double mass = 0.0;
  std::array<double, 9> euler{};
};

/// Basis at an arc-length coordinate: span, N and dN/ds of its three control points.
struct PointBasis {
  int span = 0;
  std::array<double, 3> N{};
  std::array<double, 3> dN{};
};

/// Where a point of the centre line sits in the unknowns: r(s) = sum_j w[j] y_j with y_j the
/// coordinate 3-block starting at component comp[j] of the beam's control point cp[j] (index
/// within the beam). Director: the phi blocks of a span's 3 control points; ANCF: r and r' of an
/// element's 2 nodes. So d r(s) / d y_j = w[j] I.
struct PositionStencil {
  int n = 0;
  int span = 0;  ///< knot span / element holding the point
  std::array<int, 4> cp{};
  std::array<int, 4> comp{};
  std::array<double, 4> w{};
};

/// Fields of a beam sampled along its centre line (output). Arrays are row-major, one row per
/// sample: s (1), position, velocity, d1, d2, d3, spatial force and moment resultants (3 each),
/// strains minus reference strains (6, the order of the stiffness).
/// ANCF cable: d1 is the unit tangent r'/|r'|, d2 and d3 are zero (a cable has no section
/// frame); strain = (eps, 0, 0, k) with eps the Green axial strain and k = r' x r'' / |r'|^3 the
/// spatial curvature vector; force = EA eps t, moment = EI r' x (r'' - r0'').
/// tension: the axial force, sigma_0 = EA Gamma_1 (director) or EA eps (ANCF).
/// Director beams with the assumed-strain quadrature report the element's own membrane and shear
/// strains (the knots' values interpolated along the span), so force and tension are what the
/// element uses.
struct BeamSamples {
  std::vector<double> s, position, velocity, d1, d2, d3, strain, force, moment, tension;
};

class Beam {
 public:
  Beam(const BeamSpec& spec, int id, int first_cp);

  int id() const { return id_; }
  const std::string& name() const { return spec_.name; }
  Formulation formulation() const { return spec_.formulation; }
  bool is_ancf() const { return spec_.formulation == Formulation::Ancf; }
  bool is_rigid() const { return spec_.formulation == Formulation::Rigid; }
  int n_spans() const { return spec_.n_spans; }  ///< knot spans (director) or elements (ANCF); 0 (rigid)
  int n_cp() const { return is_rigid() ? 1 : spec_.n_spans + (is_ancf() ? 1 : 2); }  ///< control points or nodes
  /// Rigid: mass and Euler tensor (BeamSpec).
  double body_mass() const { return spec_.mass; }
  const std::array<double, 9>& euler() const { return spec_.euler; }
  /// Rigid: the point X (components in the body frame, from the centre of mass) as a stencil:
  /// r = phi + X_1 d1 + X_2 d2 + X_3 d3.
  PositionStencil body_point(const std::array<double, 3>& X) const;
  /// Rigid: the body point drawn at `drawn` (global coordinates of the reference state).
  PositionStencil body_point_drawn(const std::array<double, 3>& drawn) const;
  /// Coordinates and constraint multipliers of each control point (the DofMap block sizes):
  /// director: phi, d1, d2, d3 and the 6 orthonormality multipliers; ANCF: r, r' and none.
  int coordinates_per_cp() const { return is_ancf() ? kernels::ancf::kNodeDofs : 12; }
  int multipliers_per_cp() const { return is_ancf() ? 0 : 6; }
  /// The control point (index within the beam) whose owner evaluates span e: the middle one of
  /// a director span (neighbouring spans mostly stay on one rank), the first node of an element.
  int span_owner_cp(int e) const { return is_rigid() ? 0 : is_ancf() ? e : e + 1; }
  /// Centre-line point s as a combination of coordinate blocks (both formulations).
  PositionStencil position_at(double s) const;

  /// ANCF: element tables (reference, quadrature) of element e, and the section data.
  const kernels::ancf::AncfElement& ancf_element(int e) const { return ancf_elements_.at(static_cast<size_t>(e)); }
  kernels::ancf::AncfSection ancf_section() const {
    return {spec_.section.EA, spec_.section.EI2, spec_.section.rhoA};
  }
  /// ANCF: the element holding s (the last one at s = L) and the local coordinate x in it.
  int ancf_element_at(double s, double& x) const;
  double length() const { return spec_.length; }
  int first_cp() const { return first_cp_; }  ///< global index of the first control point
  const Section& section() const { return spec_.section; }
  kernels::StrainMeasure strain_measure() const { return spec_.strain; }
  const kernels::StrainTable& strain_table() const { return kernels::strain_table(spec_.strain); }
  const kernels::Stiffness& stiffness() const { return stiffness_; }
  /// Drawn over unstretched length (1 unless BeamSpec::unstretched_length is set). The beam is
  /// parametrised by the drawn arc length s; a piece ds of it is ds / stretch() of rope, so
  /// section() holds the stiffnesses and inertias per unit of s, and the samples' strains are
  /// converted to the rope's (docs/theory.md, "Ropes by their unstretched length").
  double stretch() const { return stretch_; }
  const std::vector<double>& q_ref() const { return spec_.q_ref; }

  /// Quadrature of span e: n_gp() points (stiffness rule) with reference strains.
  int n_gp() const { return n_gp_; }
  const kernels::GaussPoint& gp(int e, int g) const { return gps_[e * n_gp_ + g]; }
  const kernels::Vec6& eps0(int e, int g) const { return eps0_[e * n_gp_ + g]; }
  /// Assumed-strain quadrature: the membrane and shear strains enter through their values at
  /// the knots (kernels::GammaMoments). knot_mass(i) = int H_i ds of knot i = 0 .. n_spans.
  bool gamma_at_knots() const { return spec_.quadrature == kernels::Quadrature::AssumedStrain; }
  double knot_mass(int i) const { return knot_mass_[static_cast<size_t>(i)]; }
  /// The knots' assumed membrane and shear strains b_i in the configuration q (n_cp x 12).
  std::vector<Eigen::Vector3d> knot_gamma(const std::vector<double>& q) const;
  /// The same from the given spans only, span_q(e) their coordinates: the entries of the knots
  /// next to them that have both neighbours' spans among them (the rest hold partial sums).
  template <class SpanCoordinates>
  std::vector<Eigen::Vector3d> knot_gamma(const std::vector<int>& spans, SpanCoordinates&& span_q) const {
    std::vector<Eigen::Vector3d> b(static_cast<size_t>(n_spans() + 1), Eigen::Vector3d::Zero());
    for (int e : spans) {
      const auto m = kernels::span_gamma_moments(strain_table(), &gp(e, 0), &eps0(e, 0), n_gp(), span_q(e));
      b[static_cast<size_t>(e)] += m.left;
      b[static_cast<size_t>(e + 1)] += m.right;
    }
    for (int i = 0; i <= n_spans(); ++i) b[static_cast<size_t>(i)] /= knot_mass(i);
    return b;
  }
  /// Whether the stiffness points carry the director-interpolation correction: the
  /// assumed-strain quadrature with the Simo-Reissner measure.
  bool corrected() const {
    return spec_.quadrature == kernels::Quadrature::AssumedStrain && spec_.strain == kernels::StrainMeasure::SimoReissner;
  }
  /// Full (3-point) quadrature of span e, used for mass and distributed loads whatever the
  /// stiffness rule, so that the mass matrix and gravity are integrated exactly.
  const kernels::GaussPoint& gp_full(int e, int g) const { return gps_full_[e * 3 + g]; }

  PointBasis basis_at(double s) const;
  PointBasis basis_on_span(int span, double s) const;

  /// Fields at samples_per_span points per knot span (and the end), from the control point
  /// coordinates q and their rates q_dot (n_cp x 12 each; q_dot may be empty: zero velocity).
  /// Resultants: sigma = C (eps - eps_ref), n = sigma_0 d1 + sigma_1 d2 + sigma_2 d3,
  /// m = sigma_3 d1 + sigma_4 d2 + sigma_5 d3 (d1 along the axis).
  BeamSamples sample(const std::vector<double>& q, const std::vector<double>& q_dot, int samples_per_span) const;
  /// The same into `out`, reusing its arrays (output samples at every record).
  void sample_into(const std::vector<double>& q, const std::vector<double>& q_dot, int samples_per_span,
                   BeamSamples& out) const;

 private:
  BeamSpec spec_;
  int id_;
  int first_cp_;
  int n_gp_ = 0;
  kernels::Stiffness stiffness_;
  double stretch_ = 1.0;
  /// The stress-free strains at a point whose drawn strains are eps_drawn.
  kernels::Vec6 stress_free(const kernels::Vec6& eps_drawn) const;
  /// Strains per unit of s (minus the stress-free ones) as the rope's, per unit of its length.
  kernels::Vec6 rope_strains(const kernels::Vec6& eps) const;
  /// The axial strain is the centre line's 1/2 (phi'.phi' - 1) (assumed strains), not d1 . phi'.
  bool centre_line_axial() const { return corrected(); }
  std::vector<kernels::GaussPoint> gps_, gps_full_;
  std::vector<kernels::Vec6> eps0_;
  std::vector<double> knot_mass_;
  std::vector<kernels::ancf::AncfElement> ancf_elements_;

  BeamSamples sample_ancf(const std::vector<double>& q, const std::vector<double>& q_dot, int samples_per_span) const;

  /// What sampling a director beam needs at each sample point apart from the coordinates: kept
  /// for the last samples_per_span asked (output samples the same points at every record).
  struct SamplePoint {
    double s;
    PointBasis basis;
    kernels::GaussPoint gp;
    kernels::StrainTable table;
    kernels::Vec6 eps_ref;
    bool centre_line_axial;
  };
  const std::vector<SamplePoint>& sample_points(int samples_per_span) const;
  mutable int sampled_per_span_ = 0;
  mutable std::vector<SamplePoint> sample_points_;
  /// Membrane and shear strains of each span recovered from its two Barlow points (full or
  /// reduced quadrature; see sample_into): the span's values at t = 1/2 -+ 1/(2 sqrt 3).
  std::vector<std::array<Eigen::Vector3d, 2>> barlow_gamma(const std::vector<double>& q) const;
  mutable std::vector<SamplePoint> barlow_points_;
};

}  // namespace slidebeam
