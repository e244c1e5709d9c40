// SPDX-License-Identifier: MIT
#include "model/dof_map.hpp"

namespace slidebeam {

DofMap::DofMap(PetscInt n_cp, PetscInt n_extra, int rank, int size)
    : n_cp_(n_cp), n_extra_(n_extra), rank_(rank), size_(size) {
  lo_ = kBlock * cp_begin(rank);
  hi_ = kBlock * cp_begin(rank + 1) + (rank == size - 1 ? n_extra : 0);
}

int DofMap::cp_owner(PetscInt cp) const {
  // inverse of cp_begin: the largest r with cp_begin(r) <= cp
  int r = static_cast<int>(((cp + 1) * size_ - 1) / n_cp_);
  while (r > 0 && cp_begin(r) > cp) --r;
  while (r < size_ - 1 && cp_begin(r + 1) <= cp) ++r;
  return r;
}

}  // namespace slidebeam
