// SPDX-License-Identifier: MIT
#pragma once
/// @file Global numbering of unknowns and its distribution over ranks.
///
/// Layout: every control point owns a contiguous slot of unknowns: its coordinates, the
/// multipliers of its own constraints, then the extra unknowns of the effects anchored at it
/// (ExtraUnknowns::elimination_anchor: a joint's multipliers and sliding coordinate after its slider's
/// points, a support's multipliers after the supported points). The block size depends on the
/// beam's formulation: a director control point has 12 coordinates (phi, d1, d2, d3) and 6
/// orthonormality multipliers (18), an ANCF node 6 coordinates (r, r') and none. Extras without
/// an anchor come after all slots, on the last rank.
///
/// Slots are numbered in a given order of the control points (the model's numbering order: points
/// that are coupled lie close, Model::finalize) and split over ranks in that order into parts of
/// about equal numbers of unknowns, so one long beam spans several ranks and a beam hanging from
/// another lies on the rank of the stretch it hangs from. The numbering depends on the scene
/// alone, not on the number of ranks.

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
  /// ranks hold nothing. order: the control points in numbering order (a permutation; empty:
  /// index order). joined[p] != 0: no rank boundary right before position p of the order (the
  /// points an effect's extras take their pivots from stay on one rank); empty: none.
  DofMap(const std::vector<int>& coordinates, const std::vector<int>& multipliers, PetscInt n_extra, int rank,
         int size, const std::vector<int>& attached = {}, int owners = 0, const std::vector<PetscInt>& order = {},
         const std::vector<char>& joined = {});

  PetscInt n_cp() const { return n_cp_; }
  PetscInt n_extra() const { return n_extra_; }
  PetscInt global_size() const { return slots_end_ + n_extra_; }
  PetscInt local_size() const { return hi_ - lo_; }
  PetscInt owned_lo() const { return lo_; }  ///< first owned global unknown
  PetscInt owned_hi() const { return hi_; }

  /// Coordinates and all unknowns (coordinates + multipliers) of control point cp.
  int n_coordinates(PetscInt cp) const { return n_q_[static_cast<size_t>(cp)]; }
  int block_size(PetscInt cp) const { return n_q_[static_cast<size_t>(cp)] + n_lambda_[static_cast<size_t>(cp)]; }
  /// The block plus the extras anchored at cp.
  int slot_size(PetscInt cp) const { return slot_[static_cast<size_t>(cp)]; }
  /// First extra unknown anchored at cp (right after its block).
  PetscInt attached(PetscInt cp) const { return q(cp, block_size(cp)); }

  PetscInt q(PetscInt cp, int comp) const { return start_[static_cast<size_t>(cp)] + comp; }
  PetscInt lambda(PetscInt cp, int k) const { return q(cp, n_coordinates(cp)) + k; }
  /// i-th extra without an anchor.
  PetscInt extra(PetscInt i) const { return slots_end_ + i; }

  /// Rank owning control point cp.
  int cp_owner(PetscInt cp) const { return owner_[static_cast<size_t>(cp)]; }
  bool owns_cp(PetscInt cp) const { return cp_owner(cp) == rank_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  int owners() const { return owners_; }  ///< ranks that own unknowns (the first ones)

 private:
  std::vector<PetscInt> start_;  // first unknown of every control point's slot
  std::vector<int> slot_;        // slot sizes
  std::vector<int> owner_;       // owning rank of every control point
  std::vector<int> n_q_;         // coordinates per control point
  std::vector<int> n_lambda_;    // multipliers per control point
  PetscInt n_cp_ = 0, n_extra_ = 0, slots_end_ = 0, lo_ = 0, hi_ = 0;
  int rank_ = 0, size_ = 1, owners_ = 1;
};

}  // namespace slidebeam
