// SPDX-License-Identifier: MIT
#include "model/effect.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace slidebeam {

double EffectParams::number(const std::string& key) const {
  auto it = num.find(key);
  if (it == num.end()) throw std::invalid_argument("missing number parameter '" + key + "'");
  return it->second;
}
double EffectParams::number(const std::string& key, double fallback) const {
  auto it = num.find(key);
  return it == num.end() ? fallback : it->second;
}
const std::vector<double>& EffectParams::vector(const std::string& key, size_t expected_size) const {
  auto it = vec.find(key);
  if (it == vec.end()) throw std::invalid_argument("missing vector parameter '" + key + "'");
  if (it->second.size() != expected_size)
    throw std::invalid_argument("parameter '" + key + "' must have " + std::to_string(expected_size) + " entries");
  return it->second;
}
const std::string& EffectParams::string(const std::string& key) const {
  auto it = str.find(key);
  if (it == str.end()) throw std::invalid_argument("missing string parameter '" + key + "'");
  return it->second;
}
std::string EffectParams::string(const std::string& key, const std::string& fallback) const {
  auto it = str.find(key);
  return it == str.end() ? fallback : it->second;
}

void GhostIndex::assign(std::vector<PetscInt> dofs) {
  dofs_ = std::move(dofs);
  table_.clear();
  base_ = 0;
  if (dofs_.empty()) return;
  // A dense table over [first, last] unless the list is sparse in that range (a rank that reads
  // a few unknowns far from its own): then binary search.
  const PetscInt span = dofs_.back() - dofs_.front() + 1;
  if (span > 8 * size() + 4096) return;
  base_ = dofs_.front();
  table_.assign(static_cast<size_t>(span), -1);
  for (PetscInt i = 0; i < size(); ++i) table_[dofs_[i] - base_] = i;
}

PetscInt GhostIndex::search(PetscInt global) const {
  auto it = std::lower_bound(dofs_.begin(), dofs_.end(), global);
  // Effects only read what they declared in needed_dofs(); anything else is a programming error.
  if (it == dofs_.end() || *it != global)
    throw std::logic_error("unknown " + std::to_string(global) + " is not ghosted on this rank");
  return static_cast<PetscInt>(it - dofs_.begin());
}

PetscErrorCode MatSink::add(PetscInt m, const PetscInt* rows, PetscInt n, const PetscInt* cols,
                            const PetscScalar* v) const {
  PetscFunctionBeginUser;
  if (coo_) {
    coo_->add(m, rows, n, cols, v, scale_);
  } else if (reader_) {
    (*reader_)(m, rows, n, cols, v);
  } else if (scale_ == 1.0) {
    PetscCall(MatSetValues(A_, m, rows, n, cols, v, ADD_VALUES));
  } else {
    std::vector<PetscScalar> w(v, v + m * n);
    for (auto& x : w) x *= scale_;
    PetscCall(MatSetValues(A_, m, rows, n, cols, w.data(), ADD_VALUES));
  }
  PetscFunctionReturn(0);
}

void CooAssembly::begin() { cursor_ = call_cursor_ = 0; }

void CooAssembly::add(PetscInt m, const PetscInt* rows, PetscInt n, const PetscInt* cols, const PetscScalar* v,
                      double scale) {
  const size_t count = static_cast<size_t>(m) * static_cast<size_t>(n);
  const size_t sig = 2 + static_cast<size_t>(m + n);
  if (!pattern_changed_) {
    const PetscInt* c = calls_.data() + call_cursor_;
    const bool same = call_cursor_ + sig <= calls_.size() && c[0] == m && c[1] == n &&
                      std::equal(rows, rows + m, c + 2) && std::equal(cols, cols + n, c + 2 + m);
    if (!same) pattern_changed_ = true;
  }
  if (pattern_changed_) {  // (re)record from here on
    calls_.resize(call_cursor_);
    calls_.push_back(m);
    calls_.push_back(n);
    calls_.insert(calls_.end(), rows, rows + m);
    calls_.insert(calls_.end(), cols, cols + n);
    i_.resize(cursor_ + count);
    j_.resize(cursor_ + count);
    for (PetscInt a = 0; a < m; ++a)
      for (PetscInt b = 0; b < n; ++b) {
        i_[cursor_ + static_cast<size_t>(a * n + b)] = rows[a];
        j_[cursor_ + static_cast<size_t>(a * n + b)] = cols[b];
      }
  }
  if (v_.size() < cursor_ + count) v_.resize(cursor_ + count);
  if (scale == 1.0) std::copy(v, v + count, v_.begin() + static_cast<std::ptrdiff_t>(cursor_));
  else
    for (size_t k = 0; k < count; ++k) v_[cursor_ + k] = scale * v[k];
  cursor_ += count;
  call_cursor_ += sig;
}

PetscErrorCode CooAssembly::end(Mat A) {
  PetscFunctionBeginUser;
  if (cursor_ != i_.size() || call_cursor_ != calls_.size()) pattern_changed_ = true;
  int changed = pattern_changed_ ? 1 : 0;
  MPI_Comm comm;
  PetscCall(PetscObjectGetComm(reinterpret_cast<PetscObject>(A), &comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &changed, 1, MPI_INT, MPI_MAX, comm));
  if (changed) {
    i_.resize(cursor_);
    j_.resize(cursor_);
    calls_.resize(call_cursor_);
    std::vector<PetscInt> ic(i_), jc(j_);  // PETSc may reorder its input arrays
    PetscCall(MatSetPreallocationCOO(A, static_cast<PetscCount>(ic.size()), ic.data(), jc.data()));
    pattern_changed_ = false;
    if (recorded_) ++generation_;
    recorded_ = true;
  }
  v_.resize(cursor_);
  PetscCall(MatSetValuesCOO(A, v_.data(), INSERT_VALUES));
  PetscFunctionReturn(0);
}

EffectRegistry& EffectRegistry::instance() {
  static EffectRegistry* registry = [] {
    auto* r = new EffectRegistry();
    register_builtin_effects(*r);
    return r;
  }();
  return *registry;
}

const char* energy_role_name(EnergyRole role) {
  switch (role) {
    case EnergyRole::Stored: return "stored";
    case EnergyRole::Constraint: return "constraint";
    case EnergyRole::External: return "external";
    case EnergyRole::Dissipative: return "dissipative";
    case EnergyRole::Driving: return "driving";
  }
  return "stored";
}

void EffectRegistry::add(EffectSpec spec, EffectFactory f) {
  std::string name = spec.type;
  entries_[name] = {std::move(spec), std::move(f)};
}

std::unique_ptr<Effect> EffectRegistry::create(const std::string& name, const Model& model,
                                               const EffectParams& p) const {
  auto it = entries_.find(name);
  if (it == entries_.end()) {
    std::string known;
    for (const auto& kv : entries_) known += (known.empty() ? "" : ", ") + kv.first;
    throw std::invalid_argument("unknown effect type '" + name + "' (registered: " + known + ")");
  }
  return it->second.second(model, p);
}

std::vector<std::string> EffectRegistry::names() const {
  std::vector<std::string> n;
  for (const auto& kv : entries_) n.push_back(kv.first);
  return n;
}

const EffectSpec& EffectRegistry::spec(const std::string& name) const {
  auto it = entries_.find(name);
  if (it == entries_.end()) throw std::invalid_argument("unknown effect type '" + name + "'");
  return it->second.first;
}

namespace {
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}
std::string json_number(double v) {
  if (std::isinf(v)) return v > 0 ? "\"inf\"" : "\"-inf\"";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}
const char* kind_name(ParamSpec::Kind k) {
  switch (k) {
    case ParamSpec::Kind::Number: return "number";
    case ParamSpec::Kind::Integer: return "integer";
    case ParamSpec::Kind::Vector: return "vector";
    case ParamSpec::Kind::Choice: return "choice";
    case ParamSpec::Kind::Beam: return "beam";
    case ParamSpec::Kind::Track: return "track";
    case ParamSpec::Kind::Point: return "point";
    case ParamSpec::Kind::End: return "end";
    case ParamSpec::Kind::Position: return "position";
    case ParamSpec::Kind::Motion: return "motion";
    case ParamSpec::Kind::Beams: return "beams";
    case ParamSpec::Kind::Ends: return "ends";
    case ParamSpec::Kind::Points: return "points";
    case ParamSpec::Kind::TimeFunction: return "time_function";
    case ParamSpec::Kind::Name: return "name";
  }
  return "number";
}
}  // namespace

std::string EffectRegistry::specs_json() const {
  std::string out = "[";
  bool first = true;
  for (const auto& kv : entries_) {
    const EffectSpec& s = kv.second.first;
    out += first ? "\n" : ",\n";
    first = false;
    out += "  {\"type\": " + json_string(s.type) + ", \"table\": " + json_string(s.table) +
           ", \"variant\": " + json_string(s.variant) + ", \"single\": " + (s.single ? "true" : "false") +
           ", \"meaning\": " + json_string(s.meaning) + ", \"role\": " + json_string(energy_role_name(s.role)) + ", \"stored\": " + json_string(s.stored) +
           ", \"params\": [";
    for (size_t i = 0; i < s.params.size(); ++i) {
      const ParamSpec& p = s.params[i];
      out += std::string(i ? "," : "") + "\n    {\"key\": " + json_string(p.key) + ", \"kind\": " +
             json_string(kind_name(p.kind)) + ", \"unit\": " + json_string(p.unit) + ", \"meaning\": " +
             json_string(p.meaning) + ", \"default\": " + json_string(p.fallback) + ", \"min\": " + json_number(p.min) +
             ", \"max\": " + json_number(p.max) + ", \"min_open\": " + (p.min_open ? "true" : "false") +
             ", \"size\": " + std::to_string(p.size) + ", \"optional\": " + (p.optional ? "true" : "false") +
             ", \"on\": " + json_string(p.on) + ", \"choices\": [";
      for (size_t c = 0; c < p.choices.size(); ++c) out += (c ? ", " : "") + json_string(p.choices[c]);
      out += "]}";
    }
    out += "]}";
  }
  return out + "\n]\n";
}

}  // namespace slidebeam
