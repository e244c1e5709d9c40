// SPDX-License-Identifier: MIT
#include "effects/common.hpp"

#include <algorithm>
#include <limits>

#include "model/time_function.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace slidebeam {

TimeFunction TimeFunction::from(const EffectParams& p) {
  TimeFunction f;
  const std::string kind = p.string("tf_type", "constant");
  if (kind == "constant") f.kind = Kind::Constant;
  else if (kind == "ramp") f.kind = Kind::Ramp;
  else if (kind == "smooth_ramp") f.kind = Kind::SmoothRamp;
  else if (kind == "hat") f.kind = Kind::Hat;
  else if (kind == "step") f.kind = Kind::Step;
  else if (kind == "sine") f.kind = Kind::Sine;
  else if (kind == "table") f.kind = Kind::Table;
  else if (kind == "spline") f.kind = Kind::Spline;
  else throw std::invalid_argument("unknown time function '" + kind + "'");
  f.t0 = p.number("tf_t0", f.t0);
  f.t1 = p.number("tf_t1", f.t1);
  f.t2 = p.number("tf_t2", f.t2);
  if (f.kind == Kind::Sine) {
    f.amplitude = p.number("tf_amplitude", f.amplitude);
    f.frequency = p.number("tf_frequency");
    f.phase = p.number("tf_phase", f.phase);
    f.offset = p.number("tf_offset", f.offset);
    if (!(f.frequency > 0.0) || !std::isfinite(f.frequency) || !std::isfinite(f.amplitude) ||
        !std::isfinite(f.phase) || !std::isfinite(f.offset))
      throw std::invalid_argument("sine time function: frequency must be > 0 and all parameters finite");
  }
  if (f.kind == Kind::Table || f.kind == Kind::Spline) {
    const auto t = p.vec.find("tf_times"), v = p.vec.find("tf_values");
    if (t == p.vec.end() || v == p.vec.end()) throw std::invalid_argument(kind + " time function: tf_times and tf_values needed");
    f.times = t->second;
    f.values = v->second;
    if (f.times.empty() || f.times.size() != f.values.size())
      throw std::invalid_argument(kind + " time function: times and values must have the same, nonzero length");
    for (size_t i = 0; i < f.times.size(); ++i)
      if (!std::isfinite(f.times[i]) || !std::isfinite(f.values[i]) || (i > 0 && !(f.times[i] > f.times[i - 1])))
        throw std::invalid_argument(kind + " time function: times must be finite and strictly increasing, values finite");
    if (f.kind == Kind::Spline) f.curvatures = spline_curvatures(f.times, f.values);
  }
  return f;
}

std::vector<double> TimeFunction::spline_curvatures(const std::vector<double>& times, const std::vector<double>& values) {
  const size_t n = times.size();
  std::vector<double> m(n, 0.0);
  if (n < 2) return m;
  // h_{i-1} m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_i m_{i+1} = 6 (slope_i - slope_{i-1}) inside; at the
  // ends the zero end slopes: 2 h_0 m_0 + h_0 m_1 = 6 slope_0, h m_{n-2} + 2 h m_{n-1} = -6 slope_{n-2}.
  // Thomas' algorithm (the matrix is diagonally dominant).
  std::vector<double> diag(n), upper(n, 0.0), rhs(n);
  auto h = [&](size_t i) { return times[i + 1] - times[i]; };
  auto slope = [&](size_t i) { return (values[i + 1] - values[i]) / h(i); };
  diag[0] = 2.0 * h(0), upper[0] = h(0), rhs[0] = 6.0 * slope(0);
  for (size_t i = 1; i + 1 < n; ++i) {
    diag[i] = 2.0 * (h(i - 1) + h(i)), upper[i] = h(i), rhs[i] = 6.0 * (slope(i) - slope(i - 1));
  }
  diag[n - 1] = 2.0 * h(n - 2), rhs[n - 1] = -6.0 * slope(n - 2);
  for (size_t i = 1; i < n; ++i) {  // the lower entry of row i is h(i - 1) = upper[i - 1]
    const double w = upper[i - 1] / diag[i - 1];
    diag[i] -= w * upper[i - 1];
    rhs[i] -= w * rhs[i - 1];
  }
  m[n - 1] = rhs[n - 1] / diag[n - 1];
  for (size_t i = n - 1; i-- > 0;) m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
  return m;
}

namespace effects {

std::string format_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

std::string format_point(const Eigen::Vector3d& p) {
  return "(" + format_number(p[0]) + ", " + format_number(p[1]) + ", " + format_number(p[2]) + ")";
}

int beam_param(const Model& model, const EffectParams& p) {
  const double v = p.number("beam");
  const int b = static_cast<int>(v);
  if (b < 0 || b >= static_cast<int>(model.beams().size()) || b != v)
    throw std::invalid_argument("no beam with index " + std::to_string(v));
  return b;
}

int director_beam_param(const Model& model, const EffectParams& p, const std::string& who) {
  const int b = beam_param(model, p);
  if (model.beam(b).is_ancf())
    throw std::invalid_argument(who + ": beam '" + model.beam(b).name() + "' is an ANCF cable (director beams only)");
  return b;
}

int ancf_beam_param(const Model& model, const EffectParams& p, const std::string& who) {
  const int b = beam_param(model, p);
  if (!model.beam(b).is_ancf())
    throw std::invalid_argument(who + ": beam '" + model.beam(b).name() + "' is a director beam (ANCF cables only)");
  return b;
}

std::vector<PetscInt> stencil_dofs(const DofMap& map, const Beam& b, const PositionStencil& st) {
  std::vector<PetscInt> d;
  for (int j = 0; j < st.n; ++j)
    for (int k = 0; k < 3; ++k) d.push_back(map.q(b.first_cp() + st.cp[j], st.comp[j] + k));
  return d;
}

Eigen::Vector3d stencil_point(const LocalValues& x, const DofMap& map, const Beam& b, const PositionStencil& st) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int j = 0; j < st.n; ++j)
    r += st.w[j] * Eigen::Map<const Eigen::Vector3d>(x.cp(map, b.first_cp() + st.cp[j]) + st.comp[j]);
  return r;
}

void scatter_stencil(const LocalValues& r, const DofMap& map, const Beam& b, const PositionStencil& st,
                     const Eigen::Vector3d& f) {
  for (int j = 0; j < st.n; ++j) Eigen::Map<Eigen::Vector3d>(r.cp(map, b.first_cp() + st.cp[j]) + st.comp[j]) += st.w[j] * f;
}

SlidingJointLink::SlidingJointLink(const Model& m, const EffectParams& p, const char* type)
    : guide_(p.string("guide", "")), type_(type) {
  if (guide_.empty() && !p.num.count("beam"))
    throw ParamError("beam", "give the slider's `beam` (a [[sliding_joint]]'s slider) or a `guide` by its name");
  if (guide_.empty()) slider_ = beam_param(m, p);
  else if (p.num.count("beam")) throw ParamError("guide", "give the slider's `beam` or a `guide`, not both");
}

void SlidingJointLink::link(const Model& m, const JointTarget* joint) {
  if (!joint && !guide_.empty())
    throw std::invalid_argument(std::string(type_) + ": no [[guide]] named '" + guide_ + "' before it");
  if (!joint)
    throw std::invalid_argument(std::string(type_) + ": beam '" + m.beam(slider_).name() +
                                "' is not the slider of a sliding_joint");
  joint_ = joint;
}

std::string SlidingJointLink::link_label(const Model& m) const {
  return std::string(type_) + "[" + (guide_.empty() ? m.beam(slider_).name() : guide_) + "]";
}

int end_cp(const Beam& b, double s) {
  const double tol = 1e-12 * b.length();
  if (std::abs(s) <= tol) return 0;
  if (std::abs(s - b.length()) <= tol) return b.n_cp() - 1;
  return -1;
}

void ControlPointBand::layout(const Beam& b, const std::vector<int>& spans, const std::vector<int>& knots) {
  reach_ = knots.empty() ? 2 : 3;
  lo_ = std::numeric_limits<int>::max();
  hi_ = -1;
  for (int e : spans) {
    lo_ = std::min(lo_, e);
    hi_ = std::max(hi_, e + 2);
  }
  for (int i : knots) {
    lo_ = std::min(lo_, knot_first_cp(b, i));
    hi_ = std::max(hi_, knot_last_cp(b, i));
  }
  if (hi_ < lo_) lo_ = 0, hi_ = -1;
  v_.assign(static_cast<size_t>(hi_ - lo_ + 1) * kernels::kNq * static_cast<size_t>(width()), 0.0);
}

PetscErrorCode ControlPointBand::flush(const DofMap& map, const Beam& b, const MatSink& J) const {
  PetscFunctionBeginUser;
  constexpr int kRowsMax = kernels::kNq, kColsMax = kernels::kNq * 7;
  PetscInt rows[kRowsMax], cols[kColsMax];
  double block[kRowsMax * kColsMax];
  for (int cp = lo_; cp <= hi_; ++cp) {
    const int c0 = std::max(lo_, cp - reach_), c1 = std::min(hi_, cp + reach_);
    const int n = kernels::kNq * (c1 - c0 + 1);
    for (int i = 0; i < kernels::kNq; ++i) rows[i] = map.q(b.first_cp() + cp, i);
    for (int c = c0; c <= c1; ++c)
      for (int j = 0; j < kernels::kNq; ++j) cols[kernels::kNq * (c - c0) + j] = map.q(b.first_cp() + c, j);
    for (int i = 0; i < kernels::kNq; ++i) {
      const double* src = &v_[row_offset(cp, i)] + kernels::kNq * (c0 - cp + reach_);
      std::copy(src, src + n, block + static_cast<size_t>(i * n));
    }
    PetscCall(J.add(kernels::kNq, rows, n, cols, block));
  }
  PetscFunctionReturn(0);
}

void add_cp_blocks(const DofMap& map, PetscInt cp0, int n, std::vector<PetscInt>& dofs) {
  for (PetscInt cp = cp0; cp < cp0 + n; ++cp)
    for (PetscInt k = 0; k < map.block_size(cp); ++k) dofs.push_back(map.q(cp, 0) + k);
}

kernels::VecEl gather_span(const LocalValues& x, const DofMap& map, const Beam& b, int e) {
  kernels::VecEl q;
  for (int a = 0; a < 3; ++a) {
    const PetscScalar* c = x.cp(map, b.first_cp() + e + a);
    for (int k = 0; k < kernels::kNq; ++k) q(kernels::kNq * a + k) = c[k];
  }
  return q;
}

std::array<PetscInt, kernels::kNqEl> span_q_dofs(const DofMap& map, const Beam& b, int e) {
  std::array<PetscInt, kernels::kNqEl> d{};
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < kernels::kNq; ++k) d[kernels::kNq * a + k] = map.q(b.first_cp() + e + a, k);
  return d;
}

void scatter_span(const DofMap& map, const LocalValues& r, const Beam& b, int e, const kernels::VecEl& v) {
  for (int a = 0; a < 3; ++a) {
    PetscScalar* c = r.cp(map, b.first_cp() + e + a);
    for (int k = 0; k < kernels::kNq; ++k) c[k] += v(kernels::kNq * a + k);
  }
}

}  // namespace effects
}  // namespace slidebeam
