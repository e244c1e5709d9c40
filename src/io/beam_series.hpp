// SPDX-License-Identifier: MIT
#pragma once
/// @file One record of the beams' XDMF series, sampled from the model's state straight into
/// the arrays the record writer takes: a record every step costs less than a small scene's
/// step.

#include "io/record_writer.hpp"
#include "model/model.hpp"

#include <petscvec.h>

#include <string>
#include <vector>

namespace slidebeam::io {

class BeamSeriesSampler {
 public:
  /// `beams` in series order, `samples_per_span` points per knot span (and each beam's end);
  /// `reference`: the sample points' reference positions (n x 3, the mesh displacements are
  /// measured from); `half2`, `half3`: the section's half extents along d2 and d3 (n).
  BeamSeriesSampler(std::vector<int> beams, int samples_per_span, std::vector<double> reference,
                    std::vector<double> half2, std::vector<double> half3);

  /// The fields of the state (x, v) in record order: velocity, d1, d2, d3, force, moment, strain,
  /// tension, displacement, section_d2, section_d3 (the beams' samples one after the other).
  /// Fills `position` (n x 3) with the sample points. Collective.
  std::vector<RecordField> sample(const Model& model, Vec x, Vec v, std::vector<double>& position) const;

  std::size_t points() const { return half2_.size(); }

 private:
  std::vector<int> beams_;
  int samples_per_span_;
  std::vector<double> reference_, half2_, half3_;
  mutable std::vector<BeamSamples> scratch_;  // per beam, reused from record to record
};

}  // namespace slidebeam::io
