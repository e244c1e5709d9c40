// SPDX-License-Identifier: MIT
#include "io/beam_series.hpp"

#include <cstring>
#include <stdexcept>
#include <utility>

namespace slidebeam::io {

namespace {
RecordField field(const char* name, std::size_t rows, std::size_t cols) {
  RecordField f;
  f.name = name;
  f.shape = cols ? std::vector<std::int64_t>{static_cast<std::int64_t>(rows), static_cast<std::int64_t>(cols)}
                 : std::vector<std::int64_t>{static_cast<std::int64_t>(rows)};
  f.bytes.resize(rows * (cols ? cols : 1) * sizeof(double));
  return f;
}
double* values(RecordField& f) { return reinterpret_cast<double*>(f.bytes.data()); }
}  // namespace

BeamSeriesSampler::BeamSeriesSampler(std::vector<int> beams, int samples_per_span, std::vector<double> reference,
                                     std::vector<double> half2, std::vector<double> half3)
    : beams_(std::move(beams)),
      samples_per_span_(samples_per_span),
      reference_(std::move(reference)),
      half2_(std::move(half2)),
      half3_(std::move(half3)),
      scratch_(beams_.size()) {
  if (reference_.size() != 3 * half2_.size() || half3_.size() != half2_.size())
    throw std::invalid_argument("BeamSeriesSampler: n x 3 reference points and n half extents needed");
}

std::vector<RecordField> BeamSeriesSampler::sample(const Model& model, Vec x, Vec v, std::vector<double>& position) const {
  const std::size_t n = points();
  enum { kVelocity, kD1, kD2, kD3, kForce, kMoment, kStrain, kTension, kDisplacement, kSection2, kSection3 };
  std::vector<RecordField> f;
  f.reserve(11);
  for (const char* name : {"velocity", "d1", "d2", "d3", "force", "moment"}) f.push_back(field(name, n, 3));
  f.push_back(field("strain", n, 6));
  f.push_back(field("tension", n, 0));
  for (const char* name : {"displacement", "section_d2", "section_d3"}) f.push_back(field(name, n, 3));
  position.resize(3 * n);
  std::size_t first = 0;  // the beam's first sample point
  for (const int& beam : beams_) {
    const auto q = model.beam_coordinates(beam, x);
    const auto qd = v ? model.beam_coordinates(beam, v) : std::vector<double>{};
    BeamSamples& b = scratch_[static_cast<std::size_t>(&beam - beams_.data())];
    model.beam(beam).sample_into(q, qd, samples_per_span_, b);
    const std::size_t m = b.s.size();
    if (first + m > n) throw std::invalid_argument("BeamSeriesSampler: more sample points than reference points");
    auto copy = [&](int k, const std::vector<double>& from, std::size_t width) {
      std::memcpy(values(f[static_cast<std::size_t>(k)]) + width * first, from.data(), width * m * sizeof(double));
    };
    copy(kVelocity, b.velocity, 3);
    copy(kD1, b.d1, 3);
    copy(kD2, b.d2, 3);
    copy(kD3, b.d3, 3);
    copy(kForce, b.force, 3);
    copy(kMoment, b.moment, 3);
    copy(kStrain, b.strain, 6);
    copy(kTension, b.tension, 1);
    std::memcpy(position.data() + 3 * first, b.position.data(), 3 * m * sizeof(double));
    first += m;
  }
  if (first != n) throw std::invalid_argument("BeamSeriesSampler: fewer sample points than reference points");
  double* disp = values(f[kDisplacement]);
  double* sec2 = values(f[kSection2]);
  double* sec3 = values(f[kSection3]);
  const double* d2 = values(f[kD2]);
  const double* d3 = values(f[kD3]);
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const std::size_t j = 3 * i + static_cast<std::size_t>(k);
      disp[j] = position[j] - reference_[j];
      sec2[j] = d2[j] * half2_[i];
      sec3[j] = d3[j] * half3_[i];
    }
  return f;
}

}  // namespace slidebeam::io
