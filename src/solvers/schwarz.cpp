// SPDX-License-Identifier: MIT
#include "solvers/schwarz.hpp"

#include "solvers/coupling_correction.hpp"
#include "solvers/newton.hpp"
#include "solvers/solver_options.hpp"
#include "util/petsc_check.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

namespace slidebeam {

bool schwarz_requested(MPI_Comm comm, const char* prefix) {
  const CoreOptions options = core_options(comm);
  if (options.schwarz_set) return options.schwarz == PETSC_TRUE;
  // default: on more than one rank, unless the options name another solver
  int size = 1;
  MPI_Comm_size(comm, &size);
  const bool pc = solver_option_set(prefix, "-pc_type");
  const bool solver = solver_option_set(prefix, "-pc_factor_mat_solver_type");
  const bool ksp = solver_option_set(prefix, "-ksp_type");
  return size > 1 && !pc && !solver && !ksp;
}

PetscErrorCode set_schwarz_subdomains(PC pc, const Model& model, Mat J) {
  PetscFunctionBeginUser;
  const std::vector<PetscInt>& order = model.elimination_order();
  std::vector<PetscInt> position(order.size());
  for (size_t k = 0; k < order.size(); ++k) position[static_cast<size_t>(order[k])] = static_cast<PetscInt>(k);
  PetscInt lo = 0, hi = 0, overlap = 1;
  PetscCall(MatGetOwnershipRange(J, &lo, &hi));
  PetscCall(PetscOptionsGetInt(nullptr, nullptr, "-sb_schwarz_overlap", &overlap, nullptr));
  std::vector<PetscInt> local, overlapped;
  for (PetscInt i = lo; i < hi; ++i) {
    local.push_back(i);
    overlapped.push_back(i);
    if (overlap < 1) continue;
    PetscInt ncols = 0;
    const PetscInt* cols = nullptr;
    PetscCall(MatGetRow(J, i, &ncols, &cols, nullptr));
    overlapped.insert(overlapped.end(), cols, cols + ncols);
    PetscCall(MatRestoreRow(J, i, &ncols, &cols, nullptr));
  }
  std::sort(overlapped.begin(), overlapped.end());
  overlapped.erase(std::unique(overlapped.begin(), overlapped.end()), overlapped.end());
  auto by_elimination = [&](PetscInt a, PetscInt b) { return position[static_cast<size_t>(a)] < position[static_cast<size_t>(b)]; };
  std::sort(local.begin(), local.end(), by_elimination);
  std::sort(overlapped.begin(), overlapped.end(), by_elimination);
  IS is = nullptr, is_local = nullptr;
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(overlapped.size()), overlapped.data(), PETSC_COPY_VALUES, &is));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(local.size()), local.data(), PETSC_COPY_VALUES, &is_local));
  PetscCall(PCASMSetSortIndices(pc, PETSC_FALSE));
  PetscCall(PCASMSetOverlap(pc, 0));  // the overlap is in the subdomains already
  PetscCall(PCASMSetLocalSubdomains(pc, 1, &is, &is_local));
  PetscCall(ISDestroy(&is));
  PetscCall(ISDestroy(&is_local));
  PetscFunctionReturn(0);
}

namespace {
PetscInt schwarz_overlap() {
  PetscInt overlap = 0;
  PetscOptionsGetInt(nullptr, nullptr, "-sb_schwarz_overlap", &overlap, nullptr);
  return overlap;
}
}  // namespace

namespace {
PetscErrorCode use_gmres(KSP ksp) {
  PetscFunctionBeginUser;
  PetscCall(KSPSetType(ksp, KSPGMRES));
  PetscCall(KSPGMRESSetRestart(ksp, 100));
  // tight: Newton keeps its quadratic rate and the roundoff tests stay meaningful
  PetscCall(KSPSetTolerances(ksp, 1e-10, 1e-14, PETSC_DEFAULT, 500));
  PetscFunctionReturn(0);
}
}  // namespace

PetscErrorCode ranks_coupled(Mat J, bool* coupled) {
  PetscFunctionBeginUser;
  *coupled = false;
  PetscMPIInt size = 1;
  PetscCall(MPI_Comm_size(PetscObjectComm(reinterpret_cast<PetscObject>(J)), &size));
  if (size == 1) PetscFunctionReturn(0);
  Mat Ad = nullptr, Ao = nullptr;
  const PetscInt* colmap = nullptr;
  PetscCall(MatMPIAIJGetSeqAIJ(J, &Ad, &Ao, &colmap));
  MatInfo info;
  PetscCall(MatGetInfo(Ao, MAT_LOCAL, &info));
  int local = info.nz_used > 0 ? 1 : 0, any = 0;
  PetscCall(MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, PetscObjectComm(reinterpret_cast<PetscObject>(J))));
  *coupled = any != 0;
  PetscFunctionReturn(0);
}

namespace {
constexpr const char* kCorrectionKey = "sb_coupling_correction";

PetscErrorCode destroy_correction(void* p) {
  delete static_cast<CouplingCorrection*>(p);
  return 0;
}

/// The correction composed with ksp, created on first use.
PetscErrorCode correction_of(KSP ksp, CouplingCorrection** c) {
  PetscFunctionBeginUser;
  PetscObject o = nullptr;
  PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(ksp), kCorrectionKey, &o));
  if (!o) {
    const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(ksp));
    const CoreOptions options = core_options(comm);
    auto* made = new CouplingCorrection(comm, options.schwarz_exact == PETSC_TRUE, options.schwarz_exact_max_interface);
    PetscContainer container = nullptr;
    PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
    PetscCall(PetscContainerSetPointer(container, made));
    PetscCall(PetscContainerSetUserDestroy(container, guarded<&destroy_correction>));
    PetscCall(PetscObjectCompose(reinterpret_cast<PetscObject>(ksp), kCorrectionKey,
                                 reinterpret_cast<PetscObject>(container)));
    PetscCall(PetscContainerDestroy(&container));  // ksp holds it
    o = nullptr;
    PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(ksp), kCorrectionKey, &o));
  }
  void* p = nullptr;
  PetscCall(PetscContainerGetPointer(reinterpret_cast<PetscContainer>(o), &p));
  *c = static_cast<CouplingCorrection*>(p);
  PetscFunctionReturn(0);
}
}  // namespace

/// The post-solve of one block application on uncoupled ranks (fail_on_every_rank).
PetscErrorCode fail_together(KSP ksp, Vec, Vec x, void*) {
  PetscFunctionBeginUser;
  PetscCall(fail_on_every_rank(ksp, x));
  PetscFunctionReturn(0);
}

CouplingCorrection* coupling_correction(KSP ksp) {
  PetscObject o = nullptr;
  PetscObjectQuery(reinterpret_cast<PetscObject>(ksp), kCorrectionKey, &o);
  if (!o) return nullptr;
  void* p = nullptr;
  PetscContainerGetPointer(reinterpret_cast<PetscContainer>(o), &p);
  return static_cast<CouplingCorrection*>(p);
}

PetscErrorCode prepare_schwarz(KSP ksp, const Model& model, Mat J, bool pattern_changed, SchwarzSolve* solve) {
  PetscFunctionBeginUser;
  PC pc = nullptr;
  PetscCall(KSPGetPC(ksp, &pc));
  PCType type = nullptr;
  PetscCall(PCGetType(pc, &type));
  if (!type || pattern_changed) {  // new, or PCReset dropped its set-up
    PetscCall(PCSetType(pc, schwarz_overlap() > 0 ? PCASM : PCBJACOBI));
    PetscCall(PCGetType(pc, &type));
    if (std::string(type) == PCASM) PetscCall(set_schwarz_subdomains(pc, model, J));
  }
  SchwarzSolve how = SchwarzSolve::Krylov;
  KSPType kt = nullptr;
  PetscCall(KSPGetType(ksp, &kt));
  bool preonly = kt && std::string(kt) == KSPPREONLY;
  if (std::string(type) != PCBJACOBI) {
    if (solve) *solve = how;
    PetscFunctionReturn(0);
  }
  const char* prefix = nullptr;
  PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
  if (model.dof_map().owners() != 1 && !solver_option_set(prefix, "-ksp_type")) {
    // No entry couples two ranks' unknowns (separate structures, one per rank): block Jacobi
    // with exact blocks is the exact solve. Coupled ranks: the same application made exact by
    // the coupling correction, or GMRES (-sb_schwarz_exact).
    bool coupled = true;
    PetscCall(ranks_coupled(J, &coupled));
    CouplingCorrection* correction = nullptr;
    if (coupled) PetscCall(correction_of(ksp, &correction));
    if (!coupled) {
      how = SchwarzSolve::Blocks;
    } else {
      bool corrected = false;
      PetscCall(correction->applies_to(J, &corrected));
      if (corrected) how = SchwarzSolve::Corrected;
    }
    if (how != SchwarzSolve::Krylov && !preonly) PetscCall(KSPSetType(ksp, KSPPREONLY));
    if (how == SchwarzSolve::Krylov && preonly) PetscCall(use_gmres(ksp));
    if (how == SchwarzSolve::Corrected) {
      PetscCall(correction->attach(ksp));
      correction->invalidate();  // J was assembled anew
    } else if (CouplingCorrection* c = coupling_correction(ksp)) {
      PetscCall(c->detach(ksp));
    }
    if (how == SchwarzSolve::Blocks) PetscCall(KSPSetPostSolve(ksp, guarded<&fail_together>, nullptr));
  } else if (preonly) {
    how = SchwarzSolve::Blocks;  // one rank owns the model (-sb_serial_below), or the user's preonly
    if (model.dof_map().owners() != 1) PetscCall(KSPSetPostSolve(ksp, guarded<&fail_together>, nullptr));
  }
  if (solve) *solve = how;
  // Block Jacobi factors each rank's diagonal block (no copy) in the model's order restricted
  // to the rank: attach it to the block, which a new pattern may have replaced.
  Mat A = nullptr;
  PetscCall(MatGetDiagonalBlock(J, &A));
  PetscObject has = nullptr;
  PetscCall(PetscObjectQuery(reinterpret_cast<PetscObject>(A), "sb_elimination_order", &has));
  if (has) PetscFunctionReturn(0);
  PetscInt lo = 0, hi = 0;
  PetscCall(MatGetOwnershipRange(J, &lo, &hi));
  std::vector<PetscInt> local;
  local.reserve(static_cast<size_t>(hi - lo));
  for (PetscInt i : model.elimination_order())
    if (i >= lo && i < hi) local.push_back(i - lo);
  PetscCall(attach_elimination_order(A, local));
  PetscFunctionReturn(0);
}

namespace {
// Sub-solver options configure_schwarz put into the database itself (not the user's).
std::vector<std::string>& default_keys() {
  static std::vector<std::string> keys;
  return keys;
}
}  // namespace

bool user_sets_schwarz_option(const char* prefix, const char* key) {
  PetscBool has = PETSC_FALSE;
  PetscOptionsHasName(nullptr, prefix, key, &has);
  const std::string name = std::string("-") + (prefix ? prefix : "") + (key + 1);
  const auto& d = default_keys();
  return has && std::find(d.begin(), d.end(), name) == d.end();
}

PetscErrorCode configure_schwarz(SNES snes, const Model& model, Mat J) {
  PetscFunctionBeginUser;
  KSP ksp = nullptr;
  PetscCall(SNESGetKSP(snes, &ksp));
  if (model.dof_map().size() > 1 && model.dof_map().owners() == 1) {
    // a model owned by rank 0 alone (-sb_serial_below): its one block is the whole system,
    // solved exactly: no Krylov iterations
    PetscCall(KSPSetType(ksp, KSPPREONLY));
  } else {
    PetscCall(use_gmres(ksp));
  }
  PetscCall(prepare_schwarz(ksp, model, J, true));
  const bool asm_ = schwarz_overlap() > 0;
  // The blocks' solvers exist only at the first solve: their defaults go into the database,
  // under the solver's prefix (-sb_ts_sub_pc_type lu, ...), unless given.
  const char* prefix = nullptr;
  PetscCall(SNESGetOptionsPrefix(snes, &prefix));
  for (const auto& [key, value] : {std::pair{"-sub_ksp_type", "preonly"}, {"-sub_pc_type", "lu"},
                                   {"-sub_pc_factor_mat_solver_type", "petsc"},
                                   {"-sub_pc_factor_mat_ordering_type", asm_ ? "natural" : kModelOrdering}}) {
    PetscBool has = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, prefix, key, &has));
    if (!has) {
      const std::string name = std::string("-") + (prefix ? prefix : "") + (key + 1);
      PetscCall(PetscOptionsSetValue(nullptr, name.c_str(), value));
      default_keys().emplace_back(name);
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace slidebeam
