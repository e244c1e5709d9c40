// SPDX-License-Identifier: MIT
#pragma once
/// @file A director beam: reference control points, section, quadrature tables and reference
/// strains. Pure data plus basis evaluation; no PETSc.

#include "kernels/beam_kernels.hpp"
#include "kernels/bspline.hpp"

#include <string>
#include <vector>

namespace slidebeam {

/// Section resultant stiffness and inertia (formulation.md sections 3-4).
struct Section {
  double EA = 0, kGA2 = 0, kGA3 = 0, GJ = 0, EI2 = 0, EI3 = 0;
  double rhoA = 0, rhoI2 = 0, rhoI3 = 0;
};

/// Everything needed to create a beam.
struct BeamSpec {
  std::string name;
  int n_spans = 1;
  double length = 1.0;  ///< reference arc length L; the spline parameter is xi = s / L
  Section section;
  kernels::StrainMeasure strain = kernels::StrainMeasure::SimoReissner;
  kernels::Quadrature quadrature = kernels::Quadrature::Full;
  /// (n_spans+2) x 12 reference coordinates (phi, d1, d2, d3) of the control points, row-major.
  std::vector<double> q_ref;
};

/// Basis at an arc-length coordinate: span, N and dN/ds of its three control points.
struct PointBasis {
  int span = 0;
  std::array<double, 3> N{};
  std::array<double, 3> dN{};
};

/// Fields of a beam sampled along its centre line (output). Arrays are row-major, one row per
/// sample: s (1), position, velocity, d1, d2, d3, spatial force and moment resultants (3 each),
/// strains minus reference strains (6, the order of the stiffness).
struct BeamSamples {
  std::vector<double> s, position, velocity, d1, d2, d3, strain, force, moment;
};

class Beam {
 public:
  Beam(const BeamSpec& spec, int id, int first_cp);

  int id() const { return id_; }
  const std::string& name() const { return spec_.name; }
  int n_spans() const { return spec_.n_spans; }
  int n_cp() const { return spec_.n_spans + 2; }
  /// Coordinates and constraint multipliers of each control point (the DofMap block sizes):
  /// phi, d1, d2, d3 and the 6 orthonormality multipliers.
  int coordinates_per_cp() const { return 12; }
  int multipliers_per_cp() const { return 6; }
  double length() const { return spec_.length; }
  int first_cp() const { return first_cp_; }  ///< global index of the first control point
  const Section& section() const { return spec_.section; }
  kernels::StrainMeasure strain_measure() const { return spec_.strain; }
  const kernels::StrainTable& strain_table() const { return kernels::strain_table(spec_.strain); }
  const kernels::Stiffness& stiffness() const { return stiffness_; }
  const std::vector<double>& q_ref() const { return spec_.q_ref; }

  /// Quadrature of span e: n_gp() points (stiffness rule) with reference strains.
  int n_gp() const { return n_gp_; }
  const kernels::GaussPoint& gp(int e, int g) const { return gps_[e * n_gp_ + g]; }
  const kernels::Vec6& eps0(int e, int g) const { return eps0_[e * n_gp_ + g]; }
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

 private:
  BeamSpec spec_;
  int id_;
  int first_cp_;
  int n_gp_ = 0;
  kernels::Stiffness stiffness_;
  std::vector<kernels::GaussPoint> gps_, gps_full_;
  std::vector<kernels::Vec6> eps0_;
};

}  // namespace slidebeam
