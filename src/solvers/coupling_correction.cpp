// SPDX-License-Identifier: MIT
#include "solvers/coupling_correction.hpp"

#include "solvers/director_condensation.hpp"
#include "util/petsc_check.hpp"

#include <algorithm>
#include <iterator>
#include <map>
#include <limits>

namespace slidebeam {

namespace {
PetscLogEvent setup_event() {
  static PetscLogEvent e = 0;
  if (!e) PetscLogEventRegister("SBCouplingSetUp", KSP_CLASSID, &e);
  return e;
}
PetscLogEvent apply_event() {
  static PetscLogEvent e = 0;
  if (!e) PetscLogEventRegister("SBCouplingApply", KSP_CLASSID, &e);
  return e;
}

/// Every rank's items, rank after rank, on every rank.
template <class T>
PetscErrorCode allgather(MPI_Comm comm, const std::vector<T>& mine, MPI_Datatype type, std::vector<T>* all) {
  PetscFunctionBeginUser;
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  std::vector<int> counts(static_cast<size_t>(size)), displs(static_cast<size_t>(size));
  const int n = static_cast<int>(mine.size());
  PetscCallMPI(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
  int total = 0;
  for (int r = 0; r < size; ++r) {
    displs[static_cast<size_t>(r)] = total;
    total += counts[static_cast<size_t>(r)];
  }
  all->resize(static_cast<size_t>(total));
  PetscCallMPI(MPI_Allgatherv(mine.data(), n, type, all->data(), counts.data(), displs.data(), type, comm));
  PetscFunctionReturn(0);
}
}  // namespace

PetscErrorCode fail_on_every_rank(KSP ksp, Vec x, bool* failed) {
  PetscFunctionBeginUser;
  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  int any = reason < 0 ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, PetscObjectComm(reinterpret_cast<PetscObject>(ksp))));
  if (any) PetscCall(VecSet(x, std::numeric_limits<double>::quiet_NaN()));
  if (failed) *failed = any != 0;
  PetscFunctionReturn(0);
}

CouplingCorrection::~CouplingCorrection() {
  VecScatterDestroy(&ghost_scatter_);
  VecDestroy(&ghosts_);
  VecDestroy(&work_);
}

PetscErrorCode CouplingCorrection::attach(KSP ksp) {
  PetscFunctionBeginUser;
  PetscCall(KSPSetPostSolve(ksp, guarded<&CouplingCorrection::post_solve>, this));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::detach(KSP ksp) {
  PetscFunctionBeginUser;
  PetscCall(KSPSetPostSolve(ksp, nullptr, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::post_solve(KSP ksp, Vec /*b*/, Vec x, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<CouplingCorrection*>(ctx);
  bool failed = false;
  PetscCall(fail_on_every_rank(ksp, x, &failed));
  if (failed) PetscFunctionReturn(0);
  Mat A = nullptr;
  PetscCall(KSPGetOperators(ksp, &A, nullptr));
  PetscObjectId id = 0;
  PetscCall(PetscObjectGetId(reinterpret_cast<PetscObject>(A), &id));
  if (self->stale_ || id != self->matrix_id_) {
    PetscCall(self->setup(ksp, A));
    self->matrix_id_ = id;
    self->stale_ = !self->valid_;
  }
  // A post-solve cannot set the KSP's reason: a solve that is not exact is made unusable, so
  // that Newton fails (NaN) and the step is retried on the fallback path.
  if (!self->valid_) PetscCall(VecSet(x, std::numeric_limits<double>::quiet_NaN()));
  else PetscCall(self->correct(A, x));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::find_coupling(Mat A, Coupling* c) const {
  PetscFunctionBeginUser;
  PetscInt lo = 0, hi = 0;
  PetscCall(MatGetOwnershipRange(A, &lo, &hi));
  // The coupling entries E: the off-rank part of this rank's rows, as (row, column, value).
  Mat Ad = nullptr, Ao = nullptr;
  const PetscInt* colmap = nullptr;
  PetscCall(MatMPIAIJGetSeqAIJ(A, &Ad, &Ao, &colmap));
  PetscInt ghosts = 0;
  PetscCall(MatGetSize(Ao, nullptr, &ghosts));
  *c = Coupling{};
  for (PetscInt i = 0; i < hi - lo; ++i) {
    PetscInt nc = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* v = nullptr;
    PetscCall(MatGetRow(Ao, i, &nc, &cols, &v));
    for (PetscInt k = 0; k < nc; ++k) {
      c->rows.push_back(lo + i);
      c->cols.push_back(colmap[cols[k]]);
      c->values.push_back(PetscRealPart(v[k]));
    }
    if (nc > 0) c->coupled_rows.push_back(i);
    PetscCall(MatRestoreRow(Ao, i, &nc, &cols, &v));
  }
  // ... and the columns other ranks couple to that this rank owns
  std::vector<PetscInt> mine_ghosts(colmap, colmap + ghosts), all_ghosts;
  PetscCall(allgather(comm_, mine_ghosts, MPIU_INT, &all_ghosts));
  for (PetscInt g : all_ghosts)
    if (g >= lo && g < hi) c->referenced.push_back(g - lo);
  std::sort(c->referenced.begin(), c->referenced.end());
  c->referenced.erase(std::unique(c->referenced.begin(), c->referenced.end()), c->referenced.end());
  std::set_union(c->coupled_rows.begin(), c->coupled_rows.end(), c->referenced.begin(), c->referenced.end(),
                 std::back_inserter(c->interface));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::applies_to(Mat A, bool* yes) {
  PetscFunctionBeginUser;
  *yes = false;
  if (!enabled_) PetscFunctionReturn(0);
  PetscObjectState state = 0;
  PetscObjectId id = 0;
  PetscCall(MatGetNonzeroState(A, &state));
  PetscCall(PetscObjectGetId(reinterpret_cast<PetscObject>(A), &id));
  if (state != counted_state_ || id != counted_id_) {
    Coupling c;
    PetscCall(find_coupling(A, &c));
    largest_ = static_cast<PetscInt>(c.coupled_rows.size());
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &largest_, 1, MPIU_INT, MPI_MAX, comm_));
    counted_state_ = state;
    counted_id_ = id;
    PetscCall(PetscInfo(A, "ranks coupled through up to %d rows of a rank: %s\n", static_cast<int>(largest_),
                        largest_ <= max_interface_ ? "the exact coupling correction" : "GMRES"));
  }
  // the set-up solves once per interface unknown: not where many joints are cut
  *yes = largest_ <= max_interface_;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::lay_out(int mine) {
  PetscFunctionBeginUser;
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm_, &size));
  counts_.assign(static_cast<size_t>(size), 0);
  displs_.assign(static_cast<size_t>(size), 0);
  PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, counts_.data(), 1, MPI_INT, comm_));
  for (int r = 1; r < size; ++r) displs_[static_cast<size_t>(r)] = displs_[static_cast<size_t>(r - 1)] + counts_[static_cast<size_t>(r - 1)];
  m_ = displs_.back() + counts_.back();
  PetscFunctionReturn(0);
}

/// In the blocks' reduced coordinates a = (u, w) per triad (N^T on the rows, N' on the
/// columns, Jr = N^T D N' the blocks' condensed matrices, M = N' Jr^-1 N^T their reduced
/// solves): the rows of N^T E N' that couple two ranks are N^T's rows over the full rows with
/// off-rank entries, this rank's interface R. With y = M b,
///     x = y + N' Jr^-1 P_R w,   S w = (N^T (b - A y))_R,   S = I + (N^T E N' Jr^-1 P_R)_R,
/// and N' Jr^-1 P_R = Y is what solve_reduced_unit returns: S's column j is e_j plus N^T E Y_j
/// on R, where E Y_j needs Y_j only at the unknowns other ranks' entries reach.
PetscErrorCode CouplingCorrection::setup_reduced(Mat A, const Coupling& coupling) {
  PetscFunctionBeginUser;
  PetscInt hi = 0;
  PetscCall(MatGetOwnershipRange(A, &lo_, &hi));
  const PetscInt n = hi - lo_;
  // R: the reduced rows of the coupled rows, and per reduced row the full rows of N^T's row
  std::vector<std::pair<PetscInt, double>> weights;
  std::vector<PetscInt> reduced;
  for (PetscInt row : coupling.coupled_rows) {
    condensation_->reduced_weights(row, &weights);
    for (const auto& [j, w] : weights) reduced.push_back(j);
  }
  std::sort(reduced.begin(), reduced.end());
  reduced.erase(std::unique(reduced.begin(), reduced.end()), reduced.end());
  local_ = reduced;  // reduced numbering of the block
  reduced_rows_.assign(reduced.size(), {});
  std::vector<PetscInt> full;
  for (size_t p = 0; p < reduced.size(); ++p) {
    condensation_->full_rows(reduced[p], &full);
    for (PetscInt row : full) {
      condensation_->reduced_weights(row, &weights);
      for (const auto& [j, w] : weights)
        if (j == reduced[p]) reduced_rows_[p].emplace_back(row, w);
    }
  }
  const int mk = static_cast<int>(reduced.size());
  PetscCall(lay_out(mk));

  // Y = N' Jr^-1 P_R, one reduced solve per interface unknown of this rank, kept at the
  // unknowns other ranks' entries reach (row-major): all S needs. The correction's own solve
  // with Y is one more reduced solve (correct), not a product with Y kept whole, which would
  // hold n x |R| numbers (a net's interface is hundreds of unknowns).
  Y_.resize(0, 0);
  PetscCall(VecDestroy(&work_));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, n, &work_));
  std::vector<PetscInt> reached(coupling.referenced.size()), all_reached;
  std::vector<double> Y_reached(coupling.referenced.size() * static_cast<size_t>(mk)), all_Y;
  for (size_t k = 0; k < coupling.referenced.size(); ++k) reached[k] = lo_ + coupling.referenced[k];
  for (int j = 0; j < mk; ++j) {
    PetscCall(condensation_->solve_reduced_unit(reduced[static_cast<size_t>(j)], work_));
    const PetscScalar* a = nullptr;
    PetscCall(VecGetArrayRead(work_, &a));
    for (size_t k = 0; k < coupling.referenced.size(); ++k)
      Y_reached[k * static_cast<size_t>(mk) + static_cast<size_t>(j)] = PetscRealPart(a[coupling.referenced[k]]);
    PetscCall(VecRestoreArrayRead(work_, &a));
  }
  PetscCall(allgather(comm_, reached, MPIU_INT, &all_reached));
  PetscCall(allgather(comm_, Y_reached, MPI_DOUBLE, &all_Y));
  const PetscInt* ranges = nullptr;
  PetscCall(MatGetOwnershipRanges(A, &ranges));
  std::map<PetscInt, std::pair<int, size_t>> where;  // global unknown -> (owner, offset of its row in all_Y)
  {
    size_t offset = 0;
    for (PetscInt g : all_reached) {
      const int r = static_cast<int>(std::upper_bound(ranges, ranges + counts_.size() + 1, g) - ranges) - 1;
      where[g] = {r, offset};
      offset += static_cast<size_t>(counts_[static_cast<size_t>(r)]);
    }
  }

  // this rank's rows of S, then all of S on every rank
  std::map<PetscInt, std::vector<std::pair<PetscInt, double>>> entries;  // local row -> (global column, value)
  for (size_t t = 0; t < coupling.rows.size(); ++t)
    entries[coupling.rows[t] - lo_].emplace_back(coupling.cols[t], coupling.values[t]);
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm_, &rank));
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows_mine =
      Eigen::MatrixXd::Zero(mk, m_);
  for (int p = 0; p < mk; ++p) {
    rows_mine(p, displs_[static_cast<size_t>(rank)] + p) = 1.0;
    for (const auto& [row, w] : reduced_rows_[static_cast<size_t>(p)]) {
      const auto e = entries.find(row);
      if (e == entries.end()) continue;
      for (const auto& [col, value] : e->second) {
        const auto [r, offset] = where.at(col);
        const int c = counts_[static_cast<size_t>(r)];
        rows_mine.row(p).segment(displs_[static_cast<size_t>(r)], c) +=
            w * value * Eigen::Map<const Eigen::RowVectorXd>(all_Y.data() + offset, c);
      }
    }
  }
  std::vector<double> mine(rows_mine.data(), rows_mine.data() + rows_mine.size()), all;
  PetscCall(allgather(comm_, mine, MPI_DOUBLE, &all));
  S_.compute(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(all.data(), m_, m_));
  valid_ = true;
  PetscCall(PetscInfo(nullptr, "coupling correction (reduced): %d interface unknowns, %d on this rank\n",
                      static_cast<int>(m_), mk));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::setup(KSP ksp, Mat A) {
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(setup_event(), 0, 0, 0, 0));
  Coupling coupling;
  PetscCall(find_coupling(A, &coupling));
  if (condensation_) PetscCall(setup_reduced(A, coupling));
  else PetscCall(setup_full(ksp, A, coupling));
  r_local_.resize(local_.size());
  r_all_.resize(static_cast<size_t>(m_));
  coupled_rows_ = coupling.coupled_rows;
  coupled_residual_.resize(coupled_rows_.size());
  // y's values at the columns of A's off-diagonal block (in its compressed order)
  Mat Ad = nullptr, Ao = nullptr;
  const PetscInt* colmap = nullptr;
  PetscCall(MatMPIAIJGetSeqAIJ(A, &Ad, &Ao, &colmap));
  PetscInt ghosts = 0;
  PetscCall(MatGetSize(Ao, nullptr, &ghosts));
  PetscCall(VecScatterDestroy(&ghost_scatter_));
  PetscCall(VecDestroy(&ghosts_));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, ghosts, &ghosts_));
  Vec x = nullptr;
  PetscCall(MatCreateVecs(A, &x, nullptr));
  IS from = nullptr;
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, ghosts, colmap, PETSC_COPY_VALUES, &from));
  PetscCall(VecScatterCreate(x, from, ghosts_, nullptr, &ghost_scatter_));
  PetscCall(ISDestroy(&from));
  PetscCall(VecDestroy(&x));
  PetscCall(PetscLogEventEnd(setup_event(), 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::setup_full(KSP ksp, Mat A, const Coupling& coupling) {
  PetscFunctionBeginUser;
  PetscMPIInt size = 1;
  PetscCallMPI(MPI_Comm_size(comm_, &size));
  PetscInt hi = 0;
  PetscCall(MatGetOwnershipRange(A, &lo_, &hi));
  const PetscInt n = hi - lo_;
  local_ = coupling.interface;
  const std::vector<PetscInt>& rows = coupling.rows;
  const std::vector<PetscInt>& cols = coupling.cols;
  const std::vector<double>& values = coupling.values;

  // I, rank after rank (and so sorted, ranks owning consecutive ranges)
  std::vector<PetscInt> mine_global(local_.size()), I;
  for (size_t k = 0; k < local_.size(); ++k) mine_global[k] = lo_ + local_[k];
  PetscCall(allgather(comm_, mine_global, MPIU_INT, &I));
  const int mk = static_cast<int>(local_.size());
  PetscCall(lay_out(mk));

  // Y = D^-1 P_I: one solve with the rank's block per interface unknown it owns
  PC pc = nullptr;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscInt nblocks = 0, first = 0;
  KSP* sub = nullptr;
  PetscCall(PCBJacobiGetSubKSP(pc, &nblocks, &first, &sub));
  PetscCheck(nblocks == 1, comm_, PETSC_ERR_SUP, "the coupling correction needs one block Jacobi block per rank, not %d",
             static_cast<int>(nblocks));
  Mat block = nullptr;
  PetscCall(KSPGetOperators(sub[0], &block, nullptr));
  Vec e = nullptr, y = nullptr;
  PetscCall(MatCreateVecs(block, &e, &y));
  Y_.resize(n, mk);
  int failed = 0;
  for (int j = 0; j < mk && !failed; ++j) {
    PetscCall(VecZeroEntries(e));
    PetscCall(VecSetValue(e, local_[static_cast<size_t>(j)], 1.0, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(e));
    PetscCall(VecAssemblyEnd(e));
    PetscCall(KSPSolve(sub[0], e, y));
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    PetscCall(KSPGetConvergedReason(sub[0], &reason));
    failed = reason < 0 ? 1 : 0;
    const PetscScalar* a = nullptr;
    PetscCall(VecGetArrayRead(y, &a));
    for (PetscInt i = 0; i < n; ++i) Y_(i, j) = PetscRealPart(a[i]);
    PetscCall(VecRestoreArrayRead(y, &a));
  }
  PetscCall(VecDestroy(&e));
  PetscCall(VecDestroy(&y));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, comm_));
  valid_ = !failed;
  if (failed) {
    PetscCall(PetscInfo(nullptr, "coupling correction: a block solve failed in the set-up\n"));
    PetscFunctionReturn(0);
  }

  // G_r = (D_r^-1)_II of every rank r (column-major), and every rank's coupling entries
  std::vector<double> G_mine(static_cast<size_t>(mk) * static_cast<size_t>(mk)), G_all;
  for (int j = 0; j < mk; ++j)
    for (int i = 0; i < mk; ++i) G_mine[static_cast<size_t>(j * mk + i)] = Y_(local_[static_cast<size_t>(i)], j);
  PetscCall(allgather(comm_, G_mine, MPI_DOUBLE, &G_all));
  std::vector<PetscInt> all_rows, all_cols;
  std::vector<double> all_values;
  PetscCall(allgather(comm_, rows, MPIU_INT, &all_rows));
  PetscCall(allgather(comm_, cols, MPIU_INT, &all_cols));
  PetscCall(allgather(comm_, values, MPI_DOUBLE, &all_values));
  std::vector<size_t> G_offset(static_cast<size_t>(size), 0);
  for (int r = 1; r < size; ++r) {
    const auto c = static_cast<size_t>(counts_[static_cast<size_t>(r - 1)]);
    G_offset[static_cast<size_t>(r)] = G_offset[static_cast<size_t>(r - 1)] + c * c;
  }

  // S = I + E_II (D^-1)_II, the same on every rank; (D^-1)_II is block diagonal by rank
  auto position = [&](PetscInt g) { return static_cast<int>(std::lower_bound(I.begin(), I.end(), g) - I.begin()); };
  auto owner = [&](int p) {
    return static_cast<int>(std::upper_bound(displs_.begin(), displs_.end(), p) - displs_.begin()) - 1;
  };
  Eigen::MatrixXd S = Eigen::MatrixXd::Identity(m_, m_);
  for (size_t t = 0; t < all_rows.size(); ++t) {
    const int pb = position(all_rows[t]);
    const int pc = position(all_cols[t]);
    const int r = owner(pc);  // the last rank whose part starts at or before pc: its owner
    const int off = displs_[static_cast<size_t>(r)], c = counts_[static_cast<size_t>(r)];
    const Eigen::Map<const Eigen::MatrixXd> G(G_all.data() + G_offset[static_cast<size_t>(r)], c, c);
    S.row(pb).segment(off, c) += all_values[t] * G.row(pc - off);
  }
  S_.compute(S);
  PetscCall(PetscInfo(nullptr, "coupling correction: %d interface unknowns, %d on this rank\n", static_cast<int>(m_), mk));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCorrection::correct(Mat A, Vec x) {
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(apply_event(), 0, 0, 0, 0));
  // (b - A y)_I with y = D^-1 b, the block solve's result in x: the blocks' solves are exact
  // (b - D y = 0 on each rank, in N^T's rows when condensed), so it is -(E y)_I, the coupling
  // entries times y's values on the other ranks: no product with the whole of A.
  PetscCall(VecScatterBegin(ghost_scatter_, x, ghosts_, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(ghost_scatter_, x, ghosts_, INSERT_VALUES, SCATTER_FORWARD));
  {
    Mat Ad = nullptr, Ao = nullptr;
    const PetscInt* colmap = nullptr;
    PetscCall(MatMPIAIJGetSeqAIJ(A, &Ad, &Ao, &colmap));
    const PetscScalar* g = nullptr;
    PetscCall(VecGetArrayRead(ghosts_, &g));
    for (size_t k = 0; k < coupled_rows_.size(); ++k) {
      PetscInt nc = 0;
      const PetscInt* cols = nullptr;
      const PetscScalar* v = nullptr;
      PetscCall(MatGetRow(Ao, coupled_rows_[k], &nc, &cols, &v));
      double Ey = 0.0;
      for (PetscInt j = 0; j < nc; ++j) Ey += PetscRealPart(v[j] * g[cols[j]]);
      coupled_residual_[k] = -Ey;
      PetscCall(MatRestoreRow(Ao, coupled_rows_[k], &nc, &cols, &v));
    }
    PetscCall(VecRestoreArrayRead(ghosts_, &g));
  }
  auto residual = [&](PetscInt row) {  // zero on rows without coupling entries
    const auto at = std::lower_bound(coupled_rows_.begin(), coupled_rows_.end(), row);
    return at != coupled_rows_.end() && *at == row ? coupled_residual_[static_cast<size_t>(at - coupled_rows_.begin())]
                                                   : 0.0;
  };
  if (condensation_) {  // N^T's rows
    for (size_t k = 0; k < local_.size(); ++k) {
      r_local_[k] = 0.0;
      for (const auto& [row, w] : reduced_rows_[k]) r_local_[k] += w * residual(row);
    }
  } else {
    for (size_t k = 0; k < local_.size(); ++k) r_local_[k] = residual(local_[k]);
  }
  PetscMPIInt rank = 0;
  PetscCallMPI(MPI_Comm_rank(comm_, &rank));
  PetscCallMPI(MPI_Allgatherv(r_local_.data(), static_cast<int>(r_local_.size()), MPI_DOUBLE, r_all_.data(),
                              counts_.data(), displs_.data(), MPI_DOUBLE, comm_));
  const Eigen::VectorXd w = S_.solve(Eigen::Map<const Eigen::VectorXd>(r_all_.data(), m_));
  // x = y + D^-1 P_I w, this rank's part
  if (condensation_ && !local_.empty()) {  // one more reduced solve, N' Jr^-1 P_R w
    const auto w_mine = w.segment(displs_[static_cast<size_t>(rank)], counts_[static_cast<size_t>(rank)]);
    std::vector<PetscScalar> values(w_mine.data(), w_mine.data() + w_mine.size());
    PetscCall(condensation_->solve_reduced(local_, values, work_));
    PetscScalar* xa = nullptr;
    const PetscScalar* ya = nullptr;
    PetscCall(VecGetArray(x, &xa));
    PetscCall(VecGetArrayRead(work_, &ya));
    PetscInt n = 0;
    PetscCall(VecGetLocalSize(work_, &n));
    for (PetscInt i = 0; i < n; ++i) xa[i] += ya[i];
    PetscCall(VecRestoreArrayRead(work_, &ya));
    PetscCall(VecRestoreArray(x, &xa));
  } else if (!local_.empty()) {
    PetscScalar* xa = nullptr;
    PetscCall(VecGetArray(x, &xa));
    Eigen::Map<Eigen::VectorXd> xl(reinterpret_cast<double*>(xa), Y_.rows());
    xl.noalias() += Y_ * w.segment(displs_[static_cast<size_t>(rank)], counts_[static_cast<size_t>(rank)]);
    PetscCall(VecRestoreArray(x, &xa));
  }
  PetscCall(PetscLogEventEnd(apply_event(), 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

}  // namespace slidebeam
