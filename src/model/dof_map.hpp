// SPDX-License-Identifier: MIT
#pragma once
/// @file Global numbering of unknowns and its distribution over ranks.
///
/// Layout: every control point (all beams, numbered consecutively) owns a contiguous slot of
/// unknowns: its coordinates, the multipliers of its own constraints, then the extra unknowns of
/// the effects anchored at it (Effect::elimination_anchor: a joint's multipliers and sliding
/// coordinate after its slider's points, a support's multipliers after the supported points).
/// The block size depends on the beam's formulation: a director control point has 12
/// coordinates (phi, d1, d2, d3) and 6 orthonormality multipliers (18), an ANCF node 6
/// coordinates (r, r') and none. Slot offsets are a prefix sum. Extras live on the rank of the
/// points they constrain, and the natural order eliminates them after those points; extras
/// without an anchor come after all slots, on the last rank. Control points are split evenly
/// over ranks in index order, so one long beam spans several ranks.

#include <petscsys.h>

#include <algorithm>
#include <vector>

namespace slidebeam {

class DofMap {
 public:
  DofMap() = default;
  /// coordinates[cp] and multipliers[cp]: sizes of the two parts of every control point's block;
  /// attached[cp]: extras anchored at cp (empty: none); n_extra: extras after all slots.
  /// owners: how many ranks own unknowns (the first ones; 0: all `size`). A scene too small to
  /// gain from distribution is owned by rank 0 alone: its solve is the serial one, the other
  /// ranks hold nothing.
  DofMap(const std::vector<int>& coordinates, const std::vector<int>& multipliers, PetscInt n_extra, int rank,
         int size, const std::vector<int>& attached = {}, int owners = 0);

  PetscInt n_cp() const { return n_cp_; }
  PetscInt n_extra() const { return n_extra_; }
  PetscInt global_size() const { return offset_.back() + n_extra_; }
  PetscInt local_size() const { return hi_ - lo_; }
  PetscInt owned_lo() const { return lo_; }  ///< first owned global unknown
  PetscInt owned_hi() const { return hi_; }

  /// Coordinates and all unknowns (coordinates + multipliers) of control point cp.
  int n_coordinates(PetscInt cp) const { return n_q_[static_cast<size_t>(cp)]; }
  int block_size(PetscInt cp) const { return n_q_[static_cast<size_t>(cp)] + n_lambda_[static_cast<size_t>(cp)]; }
  /// The block plus the extras anchored at cp.
  int slot_size(PetscInt cp) const { return static_cast<int>(offset_[static_cast<size_t>(cp) + 1] - offset_[static_cast<size_t>(cp)]); }
  /// First extra unknown anchored at cp (right after its block).
  PetscInt attached(PetscInt cp) const { return q(cp, block_size(cp)); }

  PetscInt q(PetscInt cp, int comp) const { return offset_[static_cast<size_t>(cp)] + comp; }
  PetscInt lambda(PetscInt cp, int k) const { return q(cp, n_coordinates(cp)) + k; }
  /// i-th extra without an anchor.
  PetscInt extra(PetscInt i) const { return offset_.back() + i; }

  /// Rank owning control point cp.
  int cp_owner(PetscInt cp) const;
  bool owns_cp(PetscInt cp) const { return cp_owner(cp) == rank_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  int owners() const { return owners_; }  ///< ranks that own unknowns (the first ones)

 private:
  PetscInt cp_begin(int r) const { return (n_cp_ * std::min(r, owners_)) / owners_; }
  std::vector<PetscInt> offset_{0};  // n_cp + 1 prefix sums of slot sizes
  std::vector<int> n_q_;             // coordinates per control point
  std::vector<int> n_lambda_;        // multipliers per control point
  PetscInt n_cp_ = 0, n_extra_ = 0, lo_ = 0, hi_ = 0;
  int rank_ = 0, size_ = 1, owners_ = 1;
};

}  // namespace slidebeam
