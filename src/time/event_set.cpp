// SPDX-License-Identifier: MIT
#include "time/event_set.hpp"

#include "util/petsc_check.hpp"

namespace slidebeam {

EventSet::EventSet(const Model& model) : model_(model) {
  const auto& effects = model.effects();
  for (size_t e = 0; e < effects.size(); ++e) {
    const auto* source = part_of<EventSource>(*effects[e]);
    if (!source || source->n_events() == 0) continue;
    sources_.push_back({source, indicators_.size()});
    for (int i = 0; i < source->n_events(); ++i)
      indicators_.push_back({static_cast<int>(e), i, source->event_scale(model, i)});
  }
}

std::vector<double> EventSet::values(Vec x) const {
  std::vector<double> g(indicators_.size(), 0.0);
  if (g.empty()) return g;
  PetscInt lo = 0, hi = 0;
  SB_CHECK(VecGetOwnershipRange(x, &lo, &hi));
  const PetscScalar* xa = nullptr;
  SB_CHECK(VecGetArrayRead(x, &xa));
  for (const Source& s : sources_) s.source->event_values(model_, xa, lo, hi, g.data() + s.first);
  SB_CHECK(VecRestoreArrayRead(x, &xa));
  MPI_Allreduce(MPI_IN_PLACE, g.data(), static_cast<int>(g.size()), MPI_DOUBLE, MPI_SUM, model_.comm());
  return g;
}

int EventSet::first_crossed(const std::vector<double>& g) const {
  for (size_t k = 0; k < g.size(); ++k)
    if (g[k] < -kCrossed * indicators_[k].scale) return static_cast<int>(k);
  return -1;
}

}  // namespace slidebeam
