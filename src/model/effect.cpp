// SPDX-License-Identifier: MIT
#include "model/effect.hpp"

#include <algorithm>
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

PetscInt LocalValues::index(PetscInt global) const {
  auto it = std::lower_bound(dofs_->begin(), dofs_->end(), global);
  // Effects only read what they declared in needed_dofs(); anything else is a programming error.
  if (it == dofs_->end() || *it != global)
    throw std::logic_error("unknown " + std::to_string(global) + " is not ghosted on this rank");
  return static_cast<PetscInt>(it - dofs_->begin());
}

PetscErrorCode MatSink::add(PetscInt m, const PetscInt* rows, PetscInt n, const PetscInt* cols,
                            const PetscScalar* v) const {
  PetscFunctionBeginUser;
  PetscCall(MatSetValues(A_, m, rows, n, cols, v, ADD_VALUES));
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

void EffectRegistry::add(const std::string& name, EffectFactory f) { factories_[name] = std::move(f); }

std::unique_ptr<Effect> EffectRegistry::create(const std::string& name, const Model& model,
                                               const EffectParams& p) const {
  auto it = factories_.find(name);
  if (it == factories_.end()) {
    std::string known;
    for (const auto& kv : factories_) known += (known.empty() ? "" : ", ") + kv.first;
    throw std::invalid_argument("unknown effect type '" + name + "' (registered: " + known + ")");
  }
  return it->second(model, p);
}

std::vector<std::string> EffectRegistry::names() const {
  std::vector<std::string> n;
  for (const auto& kv : factories_) n.push_back(kv.first);
  return n;
}

}  // namespace slidebeam
