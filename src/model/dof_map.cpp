// SPDX-License-Identifier: MIT
#include "model/dof_map.hpp"

#include <algorithm>
#include <stdexcept>

namespace slidebeam {

DofMap::DofMap(const std::vector<int>& coordinates, const std::vector<int>& multipliers, PetscInt n_extra, int rank,
               int size, const std::vector<int>& attached, int owners)
    : n_q_(coordinates), n_lambda_(multipliers), n_cp_(static_cast<PetscInt>(coordinates.size())), n_extra_(n_extra), rank_(rank), size_(size),
      owners_(owners > 0 ? std::min(owners, size) : size) {
  if (multipliers.size() != coordinates.size())
    throw std::invalid_argument("DofMap: one coordinate and one multiplier count per control point");
  if (!attached.empty() && attached.size() != coordinates.size())
    throw std::invalid_argument("DofMap: one count of attached extras per control point");
  offset_.assign(coordinates.size() + 1, 0);
  for (size_t c = 0; c < coordinates.size(); ++c)
    offset_[c + 1] = offset_[c] + coordinates[c] + multipliers[c] + (attached.empty() ? 0 : attached[c]);
  // the last owner also holds the extras after all slots; ranks past the owners hold nothing
  const PetscInt total = offset_.back() + n_extra;
  lo_ = rank < owners_ ? offset_[static_cast<size_t>(cp_begin(rank))] : total;
  hi_ = rank < owners_ - 1 ? offset_[static_cast<size_t>(cp_begin(rank + 1))] : total;
}

int DofMap::cp_owner(PetscInt cp) const {
  // inverse of cp_begin: the largest r with cp_begin(r) <= cp
  int r = static_cast<int>(((cp + 1) * owners_ - 1) / n_cp_);
  while (r > 0 && cp_begin(r) > cp) --r;
  while (r < owners_ - 1 && cp_begin(r + 1) <= cp) ++r;
  return r;
}

}  // namespace slidebeam
