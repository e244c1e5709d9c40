// SPDX-License-Identifier: MIT
#include "solvers/block_solve_path.hpp"

#include "solvers/coupling_correction.hpp"
#include "solvers/newton.hpp"
#include "solvers/schwarz.hpp"
#include "solvers/solver_options.hpp"
#include "util/petsc_check.hpp"

#include <algorithm>

namespace slidebeam {

bool BlockSolvePath::requested(MPI_Comm comm, const char* prefix) { return schwarz_requested(comm, prefix); }

BlockSolvePath::BlockSolvePath(const Model& model, SNES snes, Mat J, const char* prefix) : model_(model), snes_(snes) {
  SB_CHECK(configure_schwarz(snes, model, J));
  const CoreOptions options = core_options(model.comm());
  const bool user_sub = user_sets_schwarz_option(prefix, "-sub_pc_type");
  if (!options.condense_directors || options.schwarz_overlap != 0 || user_sub) return;
  const std::vector<PetscInt>& order = model.elimination_order();
  blocks_ = std::make_unique<DirectorCondensation>(model, order, DirectorCondensation::Mode::Exact);
  int any = blocks_->empty() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, model.comm());
  if (!any) {
    blocks_.reset();
    return;
  }
  update_ = std::make_unique<DirectorCondensation>(model, order, DirectorCondensation::Mode::Update);
  update_->set_newton_multipliers(true);  // GMRES's exact step carries them
  SB_CHECK(update_->attach_update(snes));
}

BlockSolvePath::~BlockSolvePath() = default;

PetscErrorCode BlockSolvePath::prepare(Mat J, bool pattern_changed) {
  PetscFunctionBeginUser;
  KSP ksp = nullptr;
  PetscCall(SNESGetKSP(snes_, &ksp));
  SchwarzSolve solve = SchwarzSolve::Krylov;
  PetscCall(prepare_schwarz(ksp, model_, J, pattern_changed, &solve));
  // A new Jacobian starts without the failure of a block under the last one: block Jacobi keeps
  // its sub-solver's failure as its own, and a retried step's first solve failed on it.
  PC pc = nullptr;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetFailedReason(pc, PC_NOERROR));
  // One application on several ranks reports a block's failure on its rank alone; the
  // post-solves make the step NaN on every rank instead, and Newton fails everywhere
  // (fail_on_every_rank).
  const bool distributed = model_.dof_map().owners() != 1;
  PetscCall(SNESSetMaxLinearSolveFailures(snes_, solve != SchwarzSolve::Krylov && distributed ? PETSC_MAX_INT : 1));
  CouplingCorrection* correction = coupling_correction(ksp);
  if (correction) correction->use_condensation(nullptr);
  ++(solve == SchwarzSolve::Blocks ? counts_.blocks : solve == SchwarzSolve::Corrected ? counts_.corrected : counts_.krylov);
  if (correction) counts_.coupled_rows = std::max<long>(counts_.coupled_rows, correction->coupled_rows());
  if (blocks_) {
    // One application of the blocks' reduced solves is the whole solve where the ranks are
    // not coupled, and with the coupling correction in reduced coordinates where they are:
    // the line search's manifold update and least-squares multipliers do the rest, as
    // serially. GMRES needs the blocks' exact solves, and its step carries Newton's
    // multipliers. (Set before the blocks are set up: the exact solve's extra data is built
    // only if used.)
    const bool reduced = solve == SchwarzSolve::Blocks || solve == SchwarzSolve::Corrected;
    blocks_->set_manifold_apply(reduced);
    update_->set_newton_multipliers(!reduced);
    PetscCall(condense_blocks(J));
    if (correction && solve == SchwarzSolve::Corrected) correction->use_condensation(blocks_.get());
  }
  PetscFunctionReturn(0);
}

/// Set the outer preconditioner up (which creates the block's KSP, not yet factored), then
/// replace the block's PC, unless the user named one (-sub_pc_type) or it is in place already.
PetscErrorCode BlockSolvePath::condense_blocks(Mat J) {
  PetscFunctionBeginUser;
  KSP ksp = nullptr;
  PC pc = nullptr;
  PetscCall(snes_ksp_pc(snes_, &ksp, &pc));
  PetscBool bjacobi = PETSC_FALSE;
  PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCBJACOBI, &bjacobi));
  if (!bjacobi) PetscFunctionReturn(0);
  PetscCall(KSPSetOperators(ksp, J, J));
  PetscCall(KSPSetUp(ksp));
  PetscInt n = 0, first = 0;
  KSP* sub = nullptr;
  PetscCall(PCBJacobiGetSubKSP(pc, &n, &first, &sub));
  if (n != 1) PetscFunctionReturn(0);
  PC subpc = nullptr;
  PetscCall(KSPGetPC(sub[0], &subpc));
  PetscBool shell = PETSC_FALSE;
  PetscCall(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(subpc), PCSHELL, &shell));
  if (!shell) PetscCall(blocks_->attach_to_block(subpc));
  PetscFunctionReturn(0);
}

PetscErrorCode BlockSolvePath::detach() {
  PetscFunctionBeginUser;
  KSP ksp = nullptr;
  PetscCall(reset_snes_pc(snes_, &ksp));
  if (CouplingCorrection* c = coupling_correction(ksp)) PetscCall(c->detach(ksp));
  if (update_) {
    SNESLineSearch ls = nullptr;
    PetscCall(SNESGetLineSearch(snes_, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  }
  update_.reset();
  blocks_.reset();
  PetscFunctionReturn(0);
}

}  // namespace slidebeam
