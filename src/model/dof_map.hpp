// SPDX-License-Identifier: MIT
#pragma once
/// @file Global numbering of unknowns and its distribution over ranks.
///
/// Layout: every control point (all beams, numbered consecutively) owns a block of 18 unknowns,
/// its 12 coordinates (phi, d1, d2, d3) followed by the 6 multipliers of its orthonormality
/// constraints; after all control points come the extra unknowns of effects (support and joint
/// multipliers, sliding coordinates). Control points are split evenly over ranks in index order,
/// so one long beam spans several ranks; the extra unknowns live on the last rank.

#include <petscsys.h>

namespace slidebeam {

class DofMap {
 public:
  static constexpr PetscInt kBlock = 18;  ///< unknowns per control point
  static constexpr PetscInt kNq = 12;     ///< coordinates per control point

  DofMap() = default;
  DofMap(PetscInt n_cp, PetscInt n_extra, int rank, int size);

  PetscInt n_cp() const { return n_cp_; }
  PetscInt n_extra() const { return n_extra_; }
  PetscInt global_size() const { return kBlock * n_cp_ + n_extra_; }
  PetscInt local_size() const { return hi_ - lo_; }
  PetscInt owned_lo() const { return lo_; }  ///< first owned global unknown
  PetscInt owned_hi() const { return hi_; }

  PetscInt q(PetscInt cp, int comp) const { return kBlock * cp + comp; }
  PetscInt lambda(PetscInt cp, int k) const { return kBlock * cp + kNq + k; }
  PetscInt extra(PetscInt i) const { return kBlock * n_cp_ + i; }

  /// Rank owning control point cp.
  int cp_owner(PetscInt cp) const;
  bool owns_cp(PetscInt cp) const { return cp_owner(cp) == rank_; }
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  PetscInt cp_begin(int r) const { return (n_cp_ * r) / size_; }
  PetscInt n_cp_ = 0, n_extra_ = 0, lo_ = 0, hi_ = 0;
  int rank_ = 0, size_ = 1;
};

}  // namespace slidebeam
