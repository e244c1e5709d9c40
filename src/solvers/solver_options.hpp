// SPDX-License-Identifier: MIT
#pragma once
/// @file The PETSc options of the core: the solvers' options prefixes and the -sb_ options.
///
/// Every solver object reads PETSc's options under a prefix of its own:
///   sb_static_  the static load steps (StaticSolver's SNES, its KSP and PC)
///   sb_eq_      the static start of a dynamic run (EquilibriumSolver)
///   sb_ts_      the time steps (TimeIntegrator)
///   sb_mass_    the constrained mass solve for the initial velocities and accelerations (a KSP)
/// A plain solver option (-snes_rtol, -ksp_type, -pc_type, -sub_pc_type, -mat_mumps_icntl_14,
/// ...: the families of kPlainFamilies) applies to the three SNES solvers: when a solver is
/// created it is copied under the solver's prefix, unless the prefixed option is given itself.
/// So -sb_ts_snes_rtol 1e-9 changes the time steps only and wins over -snes_rtol there. The
/// mass solve reads its prefixed options only. The copies follow the plain options: a copy whose
/// plain option was removed (a script's next scene) goes at the next solver creation.
///
/// The defaults are set in code before each object's SetFromOptions; the few that concern
/// objects PETSc creates only at the first solve (MUMPS's workspace, the Schwarz blocks'
/// solvers) go into the database under the solver's prefix, unless given.

#include "model/partition_policy.hpp"

#include <petscsnes.h>

#include <string>
#include <utility>
#include <vector>

namespace slidebeam {

class Model;

inline constexpr const char* kStaticPrefix = "sb_static_";
inline constexpr const char* kEquilibriumPrefix = "sb_eq_";
inline constexpr const char* kStepPrefix = "sb_ts_";
inline constexpr const char* kMassPrefix = "sb_mass_";

/// Option names (without dash) starting with these are solver options that a plain -name
/// passes on to every SNES solver.
inline constexpr const char* kPlainFamilies[] = {"snes_", "ksp_", "pc_", "sub_", "mat_mumps_", "mat_superlu_",
                                                 "mat_umfpack_", "mat_cholmod_", "mat_strumpack_", "mat_mkl_"};

/// Give a solver its prefix, first copying the plain solver options under it (see the file).
PetscErrorCode set_solver_prefix(SNES snes, const char* prefix);

/// Whether option `name` (with dash, e.g. "-pc_type") is set for the solver of `prefix`
/// (the plain option's copy included). Marks it used.
bool solver_option_set(const char* prefix, const char* name);

/// The copies of plain options made so far: (copy, plain option), names without dash.
std::vector<std::pair<std::string, std::string>> plain_option_copies();

/// The core's own options (-sb_...), read through PetscOptionsBegin so that -help lists them.
struct CoreOptions {
  PetscBool condense_directors = PETSC_TRUE;
  PetscBool exponential_update = PETSC_TRUE;
  PetscBool corotate_jacobian = PETSC_TRUE;
  PetscBool jacobian_reuse = PETSC_FALSE;
  PetscBool jacobian_reuse_set = PETSC_FALSE;  // -sb_jacobian_reuse given
  /// time steps without -sb_jacobian_reuse: modified or full Newton chosen by their measured cost
  PetscBool newton_by_cost = PETSC_FALSE;
  PetscReal jacobian_reuse_rate = 0.2;
  /// time steps: the manifold line search halves a step that makes |F| grow (DirectorCondensation::set_backtrack)
  PetscBool backtrack = PETSC_TRUE;
  PetscBool full_newton_after_rebuild = PETSC_FALSE;
  PetscBool floor_stop = PETSC_FALSE;
  PetscBool project_velocity = PETSC_TRUE;
  PetscBool schwarz = PETSC_FALSE;
  PetscBool schwarz_set = PETSC_FALSE;  // -sb_schwarz given (otherwise: the default of schwarz_requested)
  PetscInt schwarz_overlap = 0;
  /// block Jacobi on ranks that are coupled (solvers/coupling_correction.hpp): the exact
  /// coupling correction where no rank has more than schwarz_exact_max_interface rows coupled
  /// to another rank (GMRES otherwise); false: GMRES always
  PetscBool schwarz_exact = PETSC_TRUE;
  PetscInt schwarz_exact_max_interface = 1024;
  /// -sb_serial_below, -sb_serial_above_cut: how the model spreads over the ranks
  PartitionPolicy partition;
  /// static analyses of a distributed run solved on rank 0 alone by the serial solver (the
  /// manifold Newton on the condensed system): `slidebeam run` runs a static analysis there;
  /// Simulation.solve_static hands its state to every rank; false: on all ranks (MUMPS on the
  /// whole system, 2-4x slower on 2 ranks than on one: a rank's block floats without mass)
  PetscBool statics_on_rank_0 = PETSC_TRUE;
  /// the static start of a distributed dynamic run on rank 0 alone by the serial solver, bit for
  /// bit the serial run's; false (default): on all ranks, 1.5-1.9x faster on 2 ranks than on one
  /// (docs/performance.md)
  PetscBool equilibrium_on_rank_0 = PETSC_FALSE;
  /// a distributed static start solves its continuation steps on the time steps' block path
  /// (BlockSolvePath); false: on MUMPS like its polish
  PetscBool equilibrium_blocks = PETSC_TRUE;
  /// error-controlled steps: print each step's estimate and the unknown that set it
  PetscBool adapt_monitor = PETSC_FALSE;
};

/// Read the -sb_ options (collective on comm).
CoreOptions core_options(MPI_Comm comm);
/// Finalize the model, unless it is already, spread over the ranks as -sb_serial_below and
/// -sb_serial_above_cut say (collective).
void finalize_from_options(Model& model);

}  // namespace slidebeam
