// SPDX-License-Identifier: MIT
#include "model/dof_map.hpp"

#include <algorithm>
#include <stdexcept>

namespace slidebeam {

DofMap::DofMap(const std::vector<int>& coordinates, const std::vector<int>& multipliers, PetscInt n_extra, int rank,
               int size, const std::vector<int>& attached, int owners, const std::vector<PetscInt>& order,
               const std::vector<char>& joined)
    : n_q_(coordinates), n_lambda_(multipliers), n_cp_(static_cast<PetscInt>(coordinates.size())), n_extra_(n_extra),
      rank_(rank), size_(size), owners_(owners > 0 ? std::min(owners, size) : size) {
  if (multipliers.size() != coordinates.size())
    throw std::invalid_argument("DofMap: one coordinate and one multiplier count per control point");
  if (!attached.empty() && attached.size() != coordinates.size())
    throw std::invalid_argument("DofMap: one count of attached extras per control point");
  const size_t n = coordinates.size();
  std::vector<PetscInt> sequence = order;
  if (sequence.empty()) {
    sequence.resize(n);
    for (size_t c = 0; c < n; ++c) sequence[c] = static_cast<PetscInt>(c);
  }
  if (sequence.size() != n) throw std::invalid_argument("DofMap: the order must list every control point once");
  if (!joined.empty() && joined.size() != n) throw std::invalid_argument("DofMap: one joined flag per control point");
  slot_.resize(n);
  for (size_t c = 0; c < n; ++c) slot_[c] = coordinates[c] + multipliers[c] + (attached.empty() ? 0 : attached[c]);
  start_.assign(n, -1);
  for (PetscInt cp : sequence) {
    if (cp < 0 || cp >= n_cp_ || start_[static_cast<size_t>(cp)] >= 0)
      throw std::invalid_argument("DofMap: the order must list every control point once");
    start_[static_cast<size_t>(cp)] = slots_end_;
    slots_end_ += slot_[static_cast<size_t>(cp)];
  }
  // Rank r owns the slots that start in [r, r + 1) * slots_end / owners, each boundary moved on
  // past joined positions; the last owner also holds the extras after all slots; ranks past the
  // owners hold nothing.
  owner_.resize(n);
  const PetscInt total = slots_end_ + n_extra;
  std::vector<PetscInt> begin(static_cast<size_t>(owners_) + 1, slots_end_);  // first unknown of each owner
  int r = 0;
  for (size_t p = 0; p < n; ++p) {
    const PetscInt cp = sequence[p];
    const PetscInt s = start_[static_cast<size_t>(cp)];
    const bool may_cut = joined.empty() || !joined[p];
    while (may_cut && r < owners_ - 1 && static_cast<long long>(s) * owners_ >= static_cast<long long>(slots_end_) * (r + 1))
      ++r;
    owner_[static_cast<size_t>(cp)] = r;
    for (int k = r; k >= 0 && begin[static_cast<size_t>(k)] == slots_end_; --k) begin[static_cast<size_t>(k)] = s;
  }
  lo_ = rank_ < owners_ ? begin[static_cast<size_t>(rank_)] : total;
  hi_ = rank_ < owners_ - 1 ? begin[static_cast<size_t>(rank_) + 1] : total;
}

}  // namespace slidebeam
