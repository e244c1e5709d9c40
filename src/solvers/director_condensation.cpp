// SPDX-License-Identifier: MIT
#include "solvers/director_condensation.hpp"

#include "kernels/beam_kernels.hpp"
#include "solvers/newton.hpp"
#include "util/petsc_check.hpp"

#include <algorithm>
#include <limits>
#include <cmath>

namespace slidebeam {

namespace {
constexpr int kQ = 12;      // coordinates of a triad
constexpr int kBlock = 18;  // coordinates and multipliers

// -[a]x: the variation of a director a under a small rotation w is w x a = -[a]x w.
Eigen::Matrix3d minus_skew(const double* a) {
  Eigen::Matrix3d S;
  S << 0.0, a[2], -a[1], -a[2], 0.0, a[0], a[1], -a[0], 0.0;
  return S;
}
}  // namespace

DirectorCondensation::DirectorCondensation(const Model& model, const std::vector<PetscInt>& order)
    : DirectorCondensation(model, order, Mode::Manifold) {}

DirectorCondensation::DirectorCondensation(const Model& model, const std::vector<PetscInt>& elimination_order,
                                           Mode mode)
    : mode_(mode) {
  const DofMap& map = model.dof_map();
  // Manifold mode works on the whole (serial) system, Exact mode on this rank's diagonal block
  // and Update mode on this rank's unknowns: numbered from the first owned one.
  const PetscInt lo = mode == Mode::Manifold ? 0 : map.owned_lo();
  n_ = mode == Mode::Manifold ? map.global_size() : map.local_size();
  std::vector<PetscInt> order;
  for (PetscInt i : elimination_order)
    if (i >= lo && i < lo + n_) order.push_back(i - lo);
  // triads with the expected block layout and no prescribed director or multiplier
  std::vector<char> prescribed(static_cast<size_t>(n_), 0);
  for (PetscInt r : model.prescribed_rows())
    if (r >= lo && r < lo + n_) prescribed[static_cast<size_t>(r - lo)] = 1;
  for (PetscInt cp : model.director_triads()) {
    if (map.n_coordinates(cp) != kQ || map.block_size(cp) < kBlock) continue;
    const PetscInt q0 = map.q(cp, 0) - lo;
    if (q0 < 0 || q0 + kBlock > n_) continue;
    // A prescribed position (a spherical support at an end) keeps its identity rows through
    // N; prescribed directors or multipliers (a clamp) leave the triad to the full system.
    bool free = true;
    for (int k = 3; k < kBlock; ++k) free = free && !prescribed[static_cast<size_t>(q0 + k)];
    if (free) triads_.push_back(q0);
  }
  if (mode_ == Mode::Update) return;  // no reduced system
  if (triads_.empty() && mode_ == Mode::Manifold) return;  // Exact: still the block's solver (plain LU)
  // Groups in elimination order: a triad where its first unknown is eliminated, then one group
  // per other unknown. Reduced unknowns are numbered in that order, so the reduced matrix is
  // factored in its natural order. A triad's multipliers belong to no group (-1).
  group_of_.assign(static_cast<size_t>(n_), -1);
  std::vector<int> triad_of(static_cast<size_t>(n_), -1);
  for (size_t t = 0; t < triads_.size(); ++t)
    for (int k = 0; k < kBlock; ++k) triad_of[static_cast<size_t>(triads_[t] + k)] = static_cast<int>(t);
  std::vector<char> placed(triads_.size(), 0);
  for (PetscInt i : order) {
    const int t = triad_of[static_cast<size_t>(i)];
    if (t >= 0) {
      if (placed[static_cast<size_t>(t)]) continue;
      placed[static_cast<size_t>(t)] = 1;
      const int g = static_cast<int>(groups_.size());
      groups_.push_back({triads_[static_cast<size_t>(t)], kQ, t, n_red_});
      n_red_ += 6;
      for (int k = 0; k < kQ; ++k) group_of_[static_cast<size_t>(triads_[static_cast<size_t>(t)] + k)] = g;
      continue;
    }
    const int g = static_cast<int>(groups_.size());
    groups_.push_back({i, 1, -1, n_red_});
    ++n_red_;
    group_of_[static_cast<size_t>(i)] = g;
  }
  S_.assign(triads_.size(), Mat9x3::Zero());
  Sp_.assign(triads_.size(), Mat9x3::Zero());
  triad_at_setup_.assign(triads_.size(), Eigen::Matrix3d::Identity());
  if (mode_ == Mode::Exact) {
    Cpinv_.assign(triads_.size(), Eigen::Matrix<double, 9, 6>::Zero());
    Gpinv_.assign(triads_.size(), Eigen::Matrix<double, 6, 9>::Zero());
  }
}

DirectorCondensation::~DirectorCondensation() {
  MatDestroy(&F_);
  MatDestroy(&Jr_);
  VecDestroy(&rr_);
  VecDestroy(&a_);
  VecDestroy(&p_);
  VecDestroy(&t_);
  VecDestroy(&f_best_);
}

PetscErrorCode DirectorCondensation::attach(SNES snes) {
  PetscFunctionBeginUser;
  PetscCall(read_options());
  PetscCall(reattach(snes));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::reattach(SNES snes) {
  PetscFunctionBeginUser;
  PC pc = nullptr;
  PetscCall(set_preonly(snes, PCSHELL, &pc));
  PetscCall(PCShellSetContext(pc, this));
  PetscCall(PCShellSetSetUp(pc, guarded<&DirectorCondensation::pc_setup>));
  PetscCall(PCShellSetApply(pc, guarded<&DirectorCondensation::pc_apply>));
  PetscCall(PCShellSetName(pc, "director triads condensed to 6 unknowns per control point, then LU"));
  PetscCall(install_line_search(snes));
  snes_ = snes;
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::attach_update(SNES snes) {
  PetscFunctionBeginUser;
  PetscCall(read_options());
  PetscCall(install_line_search(snes));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::read_options() {
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-sb_corotate_jacobian", &corotate_, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::install_line_search(SNES snes) {
  PetscFunctionBeginUser;
  SNESLineSearch ls = nullptr;
  PetscCall(SNESGetLineSearch(snes, &ls));
  PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHSHELL));
  PetscCall(SNESLineSearchShellSetUserFunc(ls, guarded<&DirectorCondensation::line_search>, this));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::attach_to_block(PC pc) {
  PetscFunctionBeginUser;
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, this));
  PetscCall(PCShellSetSetUp(pc, guarded<&DirectorCondensation::pc_setup>));
  PetscCall(PCShellSetApply(pc, guarded<&DirectorCondensation::pc_apply>));
  PetscCall(PCShellSetName(pc, "exact block solve, director triads condensed to 6 unknowns per control point"));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::pc_setup(PC pc) {
  PetscFunctionBeginUser;
  void* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  Mat A = nullptr, P = nullptr;
  PetscCall(PCGetOperators(pc, &A, &P));
  bool ok = true;
  PetscCall(static_cast<DirectorCondensation*>(ctx)->setup(P, &ok));
  // A zero pivot or a triad whose constraint Jacobian is not of the expected form fails the
  // linear solve; the time integrator then retries the step with a pivoting LU. A set-up that
  // succeeds clears the reason: the PC keeps it otherwise, and the solves of a retried step
  // failed on it at once.
  if (!ok) PetscCall(PetscInfo(pc, "Director condensation failed (zero pivot or a triad block of unexpected form)\n"));
  PetscCall(PCSetFailedReason(pc, ok ? PC_NOERROR : PC_FACTOR_NUMERIC_ZEROPIVOT));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::pc_apply(PC pc, Vec b, Vec y) {
  PetscFunctionBeginUser;
  void* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  auto* self = static_cast<DirectorCondensation*>(ctx);
  if (self->mode_ == Mode::Exact && !self->manifold_apply_) PetscCall(self->apply_exact(self->block_, b, y));
  else PetscCall(self->apply(b, y));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::line_search(SNESLineSearch ls, void* ctx) {
  return static_cast<DirectorCondensation*>(ctx)->search(ls);
}

PetscErrorCode DirectorCondensation::build_pattern(Mat J) {
  PetscFunctionBeginUser;
  PetscInt n = 0;
  const PetscInt *ia = nullptr, *ja = nullptr;
  PetscBool done = PETSC_FALSE;
  PetscCall(MatGetRowIJ(J, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCheck(done && n == n_, PETSC_COMM_SELF, PETSC_ERR_SUP, "director condensation needs a serial AIJ Jacobian");
  const size_t ng = groups_.size();
  adj_.assign(ng, {});
  col_offset_.assign(ng, {});
  std::vector<int> mark(ng, -1);
  for (size_t g = 0; g < ng; ++g) {
    const Group& G = groups_[g];
    for (int r = 0; r < G.size; ++r) {
      const PetscInt i = G.first + r;
      for (PetscInt p = ia[i]; p < ia[i + 1]; ++p) {
        const int h = group_of_[static_cast<size_t>(ja[p])];
        if (h < 0 || mark[static_cast<size_t>(h)] == static_cast<int>(g)) continue;
        mark[static_cast<size_t>(h)] = static_cast<int>(g);
        adj_[g].push_back(h);
      }
    }
    std::sort(adj_[g].begin(), adj_[g].end(),
              [&](int a, int b) { return groups_[static_cast<size_t>(a)].base < groups_[static_cast<size_t>(b)].base; });
  }
  PetscCall(MatRestoreRowIJ(J, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  // CSR of the reduced matrix: every reduced row of a group has the same columns
  row_ptr_.assign(static_cast<size_t>(n_red_) + 1, 0);
  std::vector<PetscInt> cols;
  for (size_t g = 0; g < ng; ++g) {
    PetscInt len = 0;
    for (int h : adj_[g]) {
      col_offset_[g].push_back(len);
      len += red_size(groups_[static_cast<size_t>(h)]);
    }
    for (int r = 0; r < red_size(groups_[g]); ++r) {
      const PetscInt row = groups_[g].base + r;
      row_ptr_[static_cast<size_t>(row) + 1] = len;
    }
  }
  for (PetscInt r = 0; r < n_red_; ++r) row_ptr_[static_cast<size_t>(r) + 1] += row_ptr_[static_cast<size_t>(r)];
  cols.resize(static_cast<size_t>(row_ptr_.back()));
  for (size_t g = 0; g < ng; ++g)
    for (int r = 0; r < red_size(groups_[g]); ++r) {
      PetscInt p = row_ptr_[static_cast<size_t>(groups_[g].base + r)];
      for (int h : adj_[g])
        for (int c = 0; c < red_size(groups_[static_cast<size_t>(h)]); ++c)
          cols[static_cast<size_t>(p++)] = groups_[static_cast<size_t>(h)].base + c;
    }
  PetscCall(MatDestroy(&F_));
  PetscCall(MatDestroy(&Jr_));
  PetscCall(MatCreate(PETSC_COMM_SELF, &Jr_));
  PetscCall(MatSetSizes(Jr_, n_red_, n_red_, n_red_, n_red_));
  // Only triads (a beam's points, no extras): 6 x 6 blocks, whose LU and triangular solves
  // PETSc has unrolled (BAIJ, bs 6; about twice as fast as AIJ here)
  blocked_ = std::all_of(groups_.begin(), groups_.end(), [](const Group& G) { return G.triad >= 0; });
  if (blocked_) {
    std::vector<PetscInt> bptr(ng + 1, 0), bcols;
    for (size_t g = 0; g < ng; ++g) {
      for (int h : adj_[g]) bcols.push_back(groups_[static_cast<size_t>(h)].base / 6);
      bptr[g + 1] = static_cast<PetscInt>(bcols.size());
    }
    PetscCall(MatSetType(Jr_, MATSEQBAIJ));
    PetscCall(MatSeqBAIJSetPreallocationCSR(Jr_, 6, bptr.data(), bcols.data(), nullptr));
  } else {
    PetscCall(MatSetType(Jr_, MATSEQAIJ));
    PetscCall(MatSeqAIJSetPreallocationCSR(Jr_, row_ptr_.data(), cols.data(), nullptr));
  }
  if (!rr_) {
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, n_red_, &rr_));
    PetscCall(VecDuplicate(rr_, &a_));
  }
  symbolic_done_ = false;
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::setup(Mat J, bool* ok) {
  PetscFunctionBeginUser;
  *ok = true;
  factored_ = false;
  block_ = J;
  PetscObjectState state = 0;
  PetscObjectId id = 0;
  PetscCall(MatGetNonzeroState(J, &state));
  PetscCall(PetscObjectGetId(reinterpret_cast<PetscObject>(J), &id));
  if (!Jr_ || state != pattern_state_ || id != pattern_id_) {
    PetscCall(build_pattern(J));
    pattern_state_ = state;
    pattern_id_ = id;
  }
  PetscInt n = 0;
  const PetscInt *ia = nullptr, *ja = nullptr;
  PetscBool done = PETSC_FALSE;
  const PetscScalar* v = nullptr;
  PetscCall(MatGetRowIJ(J, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCall(MatSeqAIJGetArrayRead(J, &v));
  // J(i, j0 .. j0 + len - 1) into out (0 where not stored); rows are sorted
  auto row_segment = [&](PetscInt i, PetscInt j0, int len, double* dst) {
    for (int k = 0; k < len; ++k) dst[k] = 0.0;
    const PetscInt* e = ja + ia[i + 1];
    for (const PetscInt* it = std::lower_bound(ja + ia[i], e, j0); it != e && *it < j0 + len; ++it)
      dst[*it - j0] = v[it - ja];
  };
  // Null-space bases from the multiplier columns (G(x_f)^T: force state) and the constraint
  // rows (C(x): end state). Column k < 3 of G^T holds d_k on its own director: 1/2 d.d - 1/2.
  // Both carry the residual's scale s (HHT: 1 + alpha on every row, the constraints' included),
  // so the end-state triad of the co-rotation is C's d_k / s: with s left in, R = D_now D_then^T
  // was s times a rotation, and every co-rotated Newton step came out (1 + alpha)^2 too short on
  // positions and (1 + alpha) on rotations (HHT converged linearly, at 0.19 per iteration).
  scale_at_setup_ = scale_;
  for (size_t t = 0; t < triads_.size(); ++t) {
    const PetscInt q0 = triads_[t];
    Eigen::Matrix<double, kQ, 6, Eigen::RowMajor> Gt;
    Eigen::Matrix<double, 6, kQ, Eigen::RowMajor> C;
    for (int r = 0; r < kQ; ++r) row_segment(q0 + r, q0 + kQ, 6, Gt.row(r).data());
    for (int l = 0; l < 6; ++l) row_segment(q0 + kQ + l, q0, kQ, C.row(l).data());
    if (mode_ == Mode::Exact && !manifold_apply_) {  // for the particular solution and the multipliers
      const Eigen::Matrix<double, 6, 9> Cd = C.rightCols<9>(), Gd = Gt.bottomRows<9>().transpose();
      Cpinv_[t] = Cd.transpose() * (Cd * Cd.transpose()).ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
      Gpinv_[t] = (Gd * Gd.transpose()).ldlt().solve(Gd);
    }
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d a = Gt.block<3, 1>(3 + 3 * i, i), c = C.block<1, 3>(i, 3 + 3 * i).transpose();
      S_[t].block<3, 3>(3 * i, 0) = minus_skew(a.data());
      Sp_[t].block<3, 3>(3 * i, 0) = minus_skew(c.data());
      triad_at_setup_[t].col(i) = c / scale_at_setup_;
    }
    // N^T G^T = 0 and C N' = 0 must hold to roundoff, or this is not an orthonormal triad's block
    const double gn = Gt.cwiseAbs().maxCoeff() + 1e-300, cn = C.cwiseAbs().maxCoeff() + 1e-300;
    const double e1 = (S_[t].transpose() * Gt.bottomRows<9>()).cwiseAbs().maxCoeff() / gn;
    const double e2 = (C.rightCols<9>() * Sp_[t]).cwiseAbs().maxCoeff() / cn;
    if (!(e1 < 1e-10 && e2 < 1e-10) || Gt.topRows<3>().cwiseAbs().maxCoeff() != 0.0 ||
        C.leftCols<3>().cwiseAbs().maxCoeff() != 0.0) {
      PetscCall(PetscInfo(J, "Triad at unknown %" PetscInt_FMT ": not an orthonormality block (|N^T G^T| %g, |C N'| %g)\n",
                          q0, e1, e2));
      *ok = false;
    }
  }
  // Reduced matrix, group by group: gather each coupled 12 x 12 (or 12 x 1, 1 x 12, 1 x 1)
  // block of J, then N_g^T J_gh N'_h.
  PetscScalar* out = nullptr;
  if (!blocked_) PetscCall(MatSeqAIJGetArrayWrite(Jr_, &out));
  const size_t ng = groups_.size();
  std::vector<int> slot(ng, -1);
  std::vector<double> buf;
  std::vector<size_t> buf_off;
  for (size_t g = 0; g < ng && *ok; ++g) {
    const Group& G = groups_[g];
    buf_off.assign(adj_[g].size() + 1, 0);
    for (size_t k = 0; k < adj_[g].size(); ++k) {
      slot[static_cast<size_t>(adj_[g][k])] = static_cast<int>(k);
      buf_off[k + 1] = buf_off[k] + static_cast<size_t>(G.size * groups_[static_cast<size_t>(adj_[g][k])].size);
    }
    buf.assign(buf_off.back(), 0.0);
    for (int r = 0; r < G.size; ++r) {
      const PetscInt i = G.first + r;
      for (PetscInt p = ia[i]; p < ia[i + 1];) {
        const int h = group_of_[static_cast<size_t>(ja[p])];
        if (h < 0) {  // a multiplier of a triad: cancelled by N^T
          ++p;
          continue;
        }
        PetscCheck(slot[static_cast<size_t>(h)] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                   "director condensation: row %" PetscInt_FMT " has a column outside the cached pattern", i);
        const Group& H = groups_[static_cast<size_t>(h)];
        double* dst = buf.data() + buf_off[static_cast<size_t>(slot[static_cast<size_t>(h)])] + static_cast<size_t>(r * H.size);
        // a run of stored columns of group h: usually all of them (a copy), else entry by entry
        const PetscInt end = ia[i + 1], last = H.first + H.size - 1;
        if (ja[p] == H.first && p + H.size - 1 < end && ja[p + H.size - 1] == last) {
          std::copy(v + p, v + p + H.size, dst);
          p += H.size;
          continue;
        }
        for (; p < end && ja[p] >= H.first && ja[p] <= last; ++p) dst[ja[p] - H.first] = v[p];
      }
    }
    for (size_t k = 0; k < adj_[g].size(); ++k) {
      const Group& H = groups_[static_cast<size_t>(adj_[g][k])];
      const double* B = buf.data() + buf_off[k];  // row-major G.size x H.size
      Eigen::Matrix<double, 6, 6> R6;
      int rows = 1, cols = 1;
      if (G.triad >= 0 && H.triad >= 0) {
        const Eigen::Map<const Eigen::Matrix<double, kQ, kQ, Eigen::RowMajor>> Jb(B);
        const Mat9x3& Sg = S_[static_cast<size_t>(G.triad)];
        const Mat9x3& Sh = Sp_[static_cast<size_t>(H.triad)];
        R6.topLeftCorner<3, 3>() = Jb.topLeftCorner<3, 3>();
        R6.topRightCorner<3, 3>() = Jb.topRightCorner<3, 9>() * Sh;
        R6.bottomLeftCorner<3, 3>() = Sg.transpose() * Jb.bottomLeftCorner<9, 3>();
        R6.bottomRightCorner<3, 3>() = Sg.transpose() * (Jb.bottomRightCorner<9, 9>() * Sh);
        rows = cols = 6;
      } else if (G.triad >= 0) {
        const Eigen::Map<const Eigen::Matrix<double, kQ, 1>> Jb(B);
        R6.block<3, 1>(0, 0) = Jb.head<3>();
        R6.block<3, 1>(3, 0) = S_[static_cast<size_t>(G.triad)].transpose() * Jb.tail<9>();
        rows = 6;
      } else if (H.triad >= 0) {
        const Eigen::Map<const Eigen::Matrix<double, 1, kQ>> Jb(B);
        R6.block<1, 3>(0, 0) = Jb.head<3>();
        R6.block<1, 3>(0, 3) = Jb.tail<9>() * Sp_[static_cast<size_t>(H.triad)];
        cols = 6;
      } else {
        R6(0, 0) = B[0];
      }
      if (blocked_) {
        const Eigen::Matrix<double, 6, 6, Eigen::RowMajor> B6 = R6;
        const PetscInt bi = G.base / 6, bj = H.base / 6;
        PetscCall(MatSetValuesBlocked(Jr_, 1, &bi, 1, &bj, B6.data(), INSERT_VALUES));
        continue;
      }
      for (int r = 0; r < rows; ++r) {
        PetscScalar* dst = out + row_ptr_[static_cast<size_t>(G.base + r)] + col_offset_[g][k];
        for (int c = 0; c < cols; ++c) dst[c] = R6(r, c);
      }
    }
    for (int h : adj_[g]) slot[static_cast<size_t>(h)] = -1;
  }
  if (!blocked_) PetscCall(MatSeqAIJRestoreArrayWrite(Jr_, &out));
  PetscCall(MatSeqAIJRestoreArrayRead(J, &v));
  PetscCall(MatRestoreRowIJ(J, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  if (!*ok) PetscFunctionReturn(0);
  PetscCall(MatAssemblyBegin(Jr_, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(Jr_, MAT_FINAL_ASSEMBLY));
  MatFactorInfo info;
  PetscCall(MatFactorInfoInitialize(&info));
  info.fill = 3.0;
  info.zeropivot = 100.0 * PETSC_MACHINE_EPSILON;  // PCLU's default: report, do not divide by ~0
  if (!symbolic_done_) {
    PetscCall(MatDestroy(&F_));
    PetscCall(MatGetFactor(Jr_, MATSOLVERPETSC, MAT_FACTOR_LU, &F_));
    IS perm = nullptr;
    // (BAIJ orders block rows)
    PetscCall(ISCreateStride(PETSC_COMM_SELF, blocked_ ? n_red_ / 6 : n_red_, 0, 1, &perm));
    PetscCall(ISSetPermutation(perm));
    PetscCall(MatLUFactorSymbolic(F_, Jr_, perm, perm, &info));
    PetscCall(ISDestroy(&perm));
    symbolic_done_ = true;
  }
  PetscCall(MatLUFactorNumeric(F_, Jr_, &info));
  MatFactorError err = MAT_FACTOR_NOERROR;
  PetscCall(MatFactorGetError(F_, &err));
  if (err != MAT_FACTOR_NOERROR) {
    PetscReal pivot = 0;
    PetscInt row = -1;
    PetscCall(MatFactorGetErrorZeroPivot(F_, &pivot, &row));
    PetscCall(PetscInfo(J, "Condensed LU: zero pivot %g at reduced row %" PetscInt_FMT " (error %d)\n", (double)pivot,
                        row, static_cast<int>(err)));
    *ok = false;
    // A factor keeps its error through later numeric factorisations: once reported it is
    // cleared, or every later set-up would report this pivot again (the time steps' return to
    // the fast LU after a fall-back included).
    PetscCall(MatFactorClearError(F_));
  }
  factored_ = *ok;
  PetscFunctionReturn(0);
}

void DirectorCondensation::expand(const Group& G, const PetscScalar* a, PetscScalar* yy) const {
  if (G.triad < 0) {
    yy[G.first] = a[G.base];
    return;
  }
  const auto t = static_cast<size_t>(G.triad);
  for (int k = 0; k < 3; ++k) yy[G.first + k] = a[G.base + k];
  Eigen::Map<Eigen::Matrix<double, 9, 1>>(yy + G.first + 3) = Sp_[t] * Eigen::Map<const Eigen::Vector3d>(a + G.base + 3);
  for (int l = 0; l < 6; ++l) yy[G.first + kQ + l] = 0.0;  // set by the line search
}

void DirectorCondensation::reduced_weights(PetscInt row, std::vector<std::pair<PetscInt, double>>* out) const {
  out->clear();
  const int g = group_of_[static_cast<size_t>(row)];
  if (g < 0) return;  // a triad's multiplier
  const Group& G = groups_[static_cast<size_t>(g)];
  const PetscInt o = row - G.first;
  if (G.triad < 0 || o < 3) {
    out->emplace_back(G.base + o, 1.0);  // a plain unknown, or a triad's position (u)
    return;
  }
  // a director row: N^T's rotation rows are S^T (force state)
  const auto& S = S_[static_cast<size_t>(G.triad)];
  for (int c = 0; c < 3; ++c) out->emplace_back(G.base + 3 + c, S(o - 3, c));
}

void DirectorCondensation::full_rows(PetscInt reduced, std::vector<PetscInt>* out) const {
  out->clear();
  // groups are numbered in reduced order: the last one starting at or before `reduced`
  const auto after = std::upper_bound(groups_.begin(), groups_.end(), reduced,
                                      [](PetscInt j, const Group& g) { return j < g.base; });
  if (after == groups_.begin()) return;
  const Group& G = *(after - 1);
  const PetscInt o = reduced - G.base;
  if (G.triad < 0 || o < 3) {
    out->push_back(G.first + o);
    return;
  }
  for (PetscInt k = 3; k < G.size; ++k) out->push_back(G.first + k);  // a rotation row: S^T over d1, d2, d3
}

PetscErrorCode DirectorCondensation::solve_reduced_unit(PetscInt j, Vec y) {
  PetscFunctionBeginUser;
  PetscCall(solve_reduced({j}, {1.0}, y));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::solve_reduced(const std::vector<PetscInt>& rows,
                                                   const std::vector<PetscScalar>& values, Vec y) {
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(rr_));
  {
    PetscScalar* r = nullptr;
    PetscCall(VecGetArray(rr_, &r));
    for (size_t k = 0; k < rows.size(); ++k) r[rows[k]] = values[k];
    PetscCall(VecRestoreArray(rr_, &r));
  }
  PetscCall(MatSolve(F_, rr_, a_));
  const PetscScalar* a = nullptr;
  PetscScalar* yy = nullptr;
  PetscCall(VecGetArrayRead(a_, &a));
  PetscCall(VecGetArrayWrite(y, &yy));
  for (const Group& G : groups_) expand(G, a, yy);
  PetscCall(VecRestoreArrayWrite(y, &yy));
  PetscCall(VecRestoreArrayRead(a_, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::apply(Vec b, Vec y) {
  PetscFunctionBeginUser;
  if (!factored_) {
    // The set-up failed (its PC says so): a NaN step, which fails the Newton step cleanly. The
    // factors may be missing altogether (a failed set-up after a new pattern).
    PetscCall(VecSet(y, std::numeric_limits<PetscScalar>::quiet_NaN()));
    PetscFunctionReturn(0);
  }
  // Co-rotated factors (Manifold mode, an iterate away from the factored one): a rigid rotation
  // R of a triad's neighbourhood maps the reduced Jacobian to R6 Jr R6^T, R6 = diag(R, R) (the
  // strains are frame-indifferent and c0 M is isotropic), so Jr(now)^-1 ~ R6 Jr(then)^-1 R6^T
  // with R = D_now D_then^T per triad, and N, N' come from the current directors. An old
  // Jacobian then loses only to deformation, not to the rotation since it was built: the stiff
  // pendulum's first iteration contracts 1e-4 instead of 5e-2.
  // The factors' rows and columns carry the residual's scale s of the set-up (N from G^T, N'
  // from C; HHT: 1 + alpha): N^T b has it on the rotation rows, and the rotation of N' a is
  // s a_w. With a fresh Jacobian R = I and this is the plain path's exact Newton step.
  const bool rotate = corotate_ && snes_;
  const PetscScalar *xx = nullptr, *xo = nullptr;
  Vec X = nullptr;
  if (rotate) {
    PetscCall(SNESGetSolution(snes_, &X));
    PetscCall(VecGetArrayRead(X, &xx));
    if (theta_ != 1.0) PetscCall(VecGetArrayRead(x_old_, &xo));
  }
  std::vector<Eigen::Matrix3d>& Rs = rotation_;
  if (rotate) Rs.resize(triads_.size());
  const PetscScalar* bb = nullptr;
  PetscScalar *r = nullptr, *yy = nullptr;
  PetscCall(VecGetArrayRead(b, &bb));
  PetscCall(VecGetArrayWrite(rr_, &r));
  // reduced right-hand side N^T b (the constraint rows are at roundoff on the manifold)
  for (const Group& G : groups_) {
    if (G.triad < 0) {
      r[G.base] = bb[G.first];
      continue;
    }
    const auto t = static_cast<size_t>(G.triad);
    if (!rotate) {
      for (int k = 0; k < 3; ++k) r[G.base + k] = bb[G.first + k];
      const Eigen::Map<const Eigen::Matrix<double, 9, 1>> bd(bb + G.first + 3);
      Eigen::Map<Eigen::Vector3d>(r + G.base + 3) = S_[t].transpose() * bd;
      continue;
    }
    // N^T b with the force-state directors d_f: (b_phi, s sum_i d_f,i x b_i), then R^T
    Eigen::Vector3d rw = Eigen::Vector3d::Zero();
    Eigen::Matrix3d D;
    for (int i = 0; i < 3; ++i) {
      const PetscInt j = G.first + 3 + 3 * i;
      D.col(i) = Eigen::Map<const Eigen::Vector3d>(xx + j);
      const Eigen::Vector3d df = theta_ == 1.0 ? Eigen::Vector3d(D.col(i))
                                               : Eigen::Vector3d(theta_ * D.col(i) + (1.0 - theta_) * Eigen::Map<const Eigen::Vector3d>(xo + j));
      rw += df.cross(Eigen::Map<const Eigen::Vector3d>(bb + j));
    }
    Rs[t] = D * triad_at_setup_[t].transpose();
    Eigen::Map<Eigen::Vector3d>(r + G.base) = Rs[t].transpose() * Eigen::Map<const Eigen::Vector3d>(bb + G.first);
    // (J's multiplier columns, and so N, carry the residual's scale s: HHT's 1 + alpha)
    Eigen::Map<Eigen::Vector3d>(r + G.base + 3) = scale_at_setup_ * (Rs[t].transpose() * rw);
  }
  PetscCall(VecRestoreArrayWrite(rr_, &r));
  PetscCall(MatSolve(F_, rr_, a_));
  const PetscScalar* a = nullptr;
  PetscCall(VecGetArrayRead(a_, &a));
  PetscCall(VecGetArrayWrite(y, &yy));
  for (const Group& G : groups_) {
    if (G.triad < 0 || !rotate) {
      expand(G, a, yy);
      continue;
    }
    // R a, then N' with the current directors: (a_u, s a_w x d_i)
    const auto t = static_cast<size_t>(G.triad);
    Eigen::Map<Eigen::Vector3d>(yy + G.first) = Rs[t] * Eigen::Map<const Eigen::Vector3d>(a + G.base);
    const Eigen::Vector3d w = scale_at_setup_ * (Rs[t] * Eigen::Map<const Eigen::Vector3d>(a + G.base + 3));
    for (int i = 0; i < 3; ++i) {
      const PetscInt j = G.first + 3 + 3 * i;
      Eigen::Map<Eigen::Vector3d>(yy + j) = w.cross(Eigen::Map<const Eigen::Vector3d>(xx + j));
    }
    for (int l = 0; l < 6; ++l) yy[G.first + kQ + l] = 0.0;  // set by the line search
  }
  PetscCall(VecRestoreArrayWrite(y, &yy));
  PetscCall(VecRestoreArrayRead(a_, &a));
  PetscCall(VecRestoreArrayRead(b, &bb));
  if (rotate) {
    PetscCall(VecRestoreArrayRead(X, &xx));
    if (theta_ != 1.0) PetscCall(VecRestoreArrayRead(x_old_, &xo));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::apply_exact(Mat A, Vec b, Vec y) {
  PetscFunctionBeginUser;
  if (!p_) {
    PetscCall(VecDuplicate(b, &p_));
    PetscCall(VecDuplicate(b, &t_));
  }
  // particular solution of the constraint rows on the triads' directors, t = b - A p (p = 0
  // where b has no constraint rows: the coupling correction's unit vectors on coordinates)
  bool constrained = false;
  {
    const PetscScalar* bb = nullptr;
    PetscScalar* pp = nullptr;
    PetscCall(VecGetArrayRead(b, &bb));
    PetscCall(VecGetArrayWrite(p_, &pp));
    std::fill(pp, pp + n_, 0.0);
    for (size_t t = 0; t < triads_.size(); ++t) {
      const PetscInt q0 = triads_[t];
      const Eigen::Map<const kernels::Vec6> bl(bb + q0 + kQ);
      if (bl.isZero(0.0)) continue;
      constrained = true;
      Eigen::Map<Eigen::Matrix<double, 9, 1>>(pp + q0 + 3) = Cpinv_[t] * bl;
    }
    PetscCall(VecRestoreArrayWrite(p_, &pp));
    PetscCall(VecRestoreArrayRead(b, &bb));
  }
  if (constrained) {
    PetscCall(MatMult(A, p_, t_));
    PetscCall(VecAYPX(t_, -1.0, b));
  } else {
    PetscCall(VecCopy(b, t_));
  }
  // reduced solve: y = N' a on the triads' coordinates, a elsewhere, 0 on their multipliers
  PetscCall(apply(t_, y));
  if (constrained) PetscCall(VecAXPY(y, 1.0, p_));
  // multipliers: G^T dlambda = b_q - (A y)_q on each triad's force rows
  PetscCall(MatMult(A, y, t_));
  {
    const PetscScalar *bb = nullptr, *tt = nullptr;
    PetscScalar* yy = nullptr;
    PetscCall(VecGetArrayRead(b, &bb));
    PetscCall(VecGetArrayRead(t_, &tt));
    PetscCall(VecGetArray(y, &yy));
    for (size_t t = 0; t < triads_.size(); ++t) {
      const PetscInt q0 = triads_[t];
      Eigen::Matrix<double, 9, 1> r;
      for (int k = 0; k < 9; ++k) r(k) = bb[q0 + 3 + k] - tt[q0 + 3 + k];
      Eigen::Map<kernels::Vec6>(yy + q0 + kQ) = Gpinv_[t] * r;
    }
    PetscCall(VecRestoreArray(y, &yy));
    PetscCall(VecRestoreArrayRead(t_, &tt));
    PetscCall(VecRestoreArrayRead(b, &bb));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::project(Vec x) const {
  PetscFunctionBeginUser;
  PetscScalar* xa = nullptr;
  PetscCall(VecGetArray(x, &xa));
  for (PetscInt q0 : triads_) kernels::closest_orthonormal_frame(xa + q0 + 3);
  PetscCall(VecRestoreArray(x, &xa));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::search(SNESLineSearch ls) {
  PetscFunctionBeginUser;
  SNES snes = nullptr;
  Vec X = nullptr, F = nullptr, Y = nullptr, W = nullptr, G = nullptr;
  PetscCall(SNESLineSearchGetSNES(ls, &snes));
  PetscCall(SNESLineSearchGetVecs(ls, &X, &F, &Y, &W, &G));
  PetscReal fnorm0 = 0.0, unused = 0.0;
  PetscCall(SNESLineSearchGetNorms(ls, &unused, &fnorm0, &unused));
  // The full step first. Where it makes |F| grow (Newton far from the solution: a rope's axial
  // waves after a jerk sent it from 1e5 to 1e48), shorter steps along it, halving up to
  // kBacktracks times, and the first that lowers |F| is taken (else the one of least |F|).
  // Not at roundoff: a step below kRoundoffStep of the state only moves |F| about its floor
  // (the stiff pendulum's last iteration grows |F| in one step of five), and shortening it
  // costs residuals and gains nothing. G holds the best trial so far; F is F(W) of the trial in W.
  constexpr int kBacktracks = 6;
  constexpr double kRoundoffStep = 1e-7;  // the convergence test's (TimeIntegrator::converged)
  PetscReal norms[3] = {0.0, 0.0, 0.0};  // |F|, |W|, |W - X|
  PetscCall(trial(snes, X, Y, 1.0, W, F, norms));
  // With an old Jacobian (modified Newton) growth asks for a fresh one instead (the time
  // integrator's convergence test), not for a shorter step along a stale direction.
  const bool fresh = rebuilds_ != rebuilds_seen_;
  rebuilds_seen_ = rebuilds_;
  if (backtrack_ && fresh && !(norms[0] <= fnorm0) && fnorm0 > 0.0 && !(norms[2] <= kRoundoffStep * norms[1])) {
    PetscReal best[3] = {norms[0], norms[1], norms[2]};
    if (!f_best_) PetscCall(VecDuplicate(F, &f_best_));
    Vec Fbest = f_best_;
    PetscCall(VecCopy(W, G));
    PetscCall(VecCopy(F, Fbest));
    double lambda = 1.0;
    for (int k = 0; k < kBacktracks; ++k) {
      lambda *= 0.5;
      PetscCall(trial(snes, X, Y, lambda, W, F, norms));
      if (norms[0] < best[0] || !std::isfinite(best[0])) {
        std::copy(norms, norms + 3, best);
        PetscCall(VecCopy(W, G));
        PetscCall(VecCopy(F, Fbest));
      }
      if (norms[0] < fnorm0) break;
    }
    PetscCall(PetscInfo(snes, "Backtracked: |F| %g -> %g at step length %g\n", (double)fnorm0, (double)best[0], lambda));
    PetscCall(VecCopy(G, W));
    PetscCall(VecCopy(Fbest, F));
    std::copy(best, best + 3, norms);
  }
  PetscCall(VecCopy(W, X));
  PetscCall(SNESLineSearchSetNorms(ls, norms[1], norms[0], norms[2]));
  if (!std::isfinite(norms[0])) PetscCall(SNESLineSearchSetReason(ls, SNES_LINESEARCH_FAILED_DOMAIN));
  PetscFunctionReturn(0);
}

PetscErrorCode DirectorCondensation::trial(SNES snes, Vec X, Vec Y, double lambda, Vec W, Vec F, PetscReal* norms) {
  PetscFunctionBeginUser;
  PetscCall(VecWAXPY(W, -lambda, Y, X));
  if (exponential_) {
    // The step's director part is w x d_i (C dq = 0 on the manifold): w = 1/2 sum_i d_i x dd_i,
    // and the triad turns by exp([w]x) (the closest frame of d + w x d turns by atan|w| only).
    PetscScalar* w = nullptr;
    const PetscScalar* x = nullptr;
    PetscCall(VecGetArray(W, &w));
    PetscCall(VecGetArrayRead(X, &x));
    for (PetscInt q0 : triads_) {
      Eigen::Vector3d rot = Eigen::Vector3d::Zero();
      for (int i = 0; i < 3; ++i) {
        const Eigen::Map<const Eigen::Vector3d> d(x + q0 + 3 + 3 * i), dn(w + q0 + 3 + 3 * i);
        rot += 0.5 * d.cross(dn - d);
      }
      const double angle = rot.norm();
      if (!(angle > 0.0) || !std::isfinite(angle)) continue;  // (NaN: the line search reports it)
      const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, rot / angle).toRotationMatrix();
      for (int i = 0; i < 3; ++i)
        Eigen::Map<Eigen::Vector3d>(w + q0 + 3 + 3 * i) = R * Eigen::Map<const Eigen::Vector3d>(x + q0 + 3 + 3 * i);
    }
    PetscCall(VecRestoreArrayRead(X, &x));
    PetscCall(VecRestoreArray(W, &w));
  }
  PetscCall(project(W));
  PetscCall(SNESComputeFunction(snes, W, F));
  // Multipliers: the residual is linear in them (forces s G(x_f)^T lambda), so the choice that
  // leaves no force along G^T is a 6 x 6 least-squares problem per triad (unless the step's
  // own, Newton's, are kept: set_newton_multipliers).
  {
    PetscScalar *w = nullptr, *f = nullptr;
    const PetscScalar* xo = nullptr;
    PetscCall(VecGetArray(W, &w));
    PetscCall(VecGetArray(F, &f));
    if (theta_ != 1.0) PetscCall(VecGetArrayRead(x_old_, &xo));
    for (PetscInt q0 : triads_) {
      if (newton_multipliers_) break;
      double d[3][3];  // directors at the force state
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
          const PetscInt j = q0 + 3 + 3 * i + k;
          d[i][k] = theta_ == 1.0 ? w[j] : theta_ * w[j] + (1.0 - theta_) * xo[j];
        }
      double* fd[3] = {f + q0 + 3, f + q0 + 6, f + q0 + 9};
      kernels::orthonormality_multiplier_update(d, fd, w + q0 + kQ, scale_);
    }
    if (theta_ != 1.0) PetscCall(VecRestoreArrayRead(x_old_, &xo));
    // |F|, |W| and the step actually taken |W - X|, in one pass over this rank's entries
    const PetscScalar* x = nullptr;
    PetscCall(VecGetArrayRead(X, &x));
    PetscInt n = 0;
    PetscCall(VecGetLocalSize(X, &n));
    double sums[3] = {0.0, 0.0, 0.0};  // |F|^2, |W|^2, |W - X|^2
    for (PetscInt i = 0; i < n; ++i) {
      sums[0] += f[i] * f[i];
      sums[1] += w[i] * w[i];
      sums[2] += (w[i] - x[i]) * (w[i] - x[i]);
    }
    MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(X));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, comm));
    for (int k = 0; k < 3; ++k) norms[k] = std::sqrt(sums[k]);
    PetscCall(VecRestoreArrayRead(X, &x));
    PetscCall(VecRestoreArray(F, &f));
    PetscCall(VecRestoreArray(W, &w));
  }
  PetscFunctionReturn(0);
}

}  // namespace slidebeam
