// SPDX-License-Identifier: MIT
#pragma once
/// @file A linear solver path for big scenes beyond one direct LU (-sb_schwarz): GMRES
/// preconditioned by restricted additive Schwarz on the model's own subdomains. Each rank's
/// subdomain is its rows plus every unknown they couple to (overlap 1, from the Jacobian's
/// current pattern), listed in the model's elimination order and left unsorted, so that the
/// subdomain's LU in natural order is Model::elimination_order restricted to it: every
/// multiplier after coordinates that give it a pivot, fill local. PETSc's sorted default
/// subdomains would need a pivoting LU (SuperLU) and many more iterations. The default on more
/// than one rank (schwarz_requested).

#include "model/model.hpp"

#include <petscsnes.h>

namespace slidebeam {

/// Whether to use the Schwarz path: -sb_schwarz [true|false] if given; otherwise on more than
/// one rank (where it beats MUMPS on the saddle-point systems, whose zero diagonals make MUMPS
/// delay nearly every multiplier pivot), unless the options name a KSP, PC or factor package.
bool schwarz_requested(MPI_Comm comm);
/// Set snes's KSP to GMRES and its PC to ASM on the model's subdomains (before
/// SNESSetFromOptions, so options still win), with sub-solvers PETSc LU in natural order unless
/// the options database names others.
PetscErrorCode configure_schwarz(SNES snes, const Model& model, Mat J);
/// (Re)build the subdomains from J's pattern: after a PCReset (the pattern moved).
PetscErrorCode set_schwarz_subdomains(PC pc, const Model& model, Mat J);

}  // namespace slidebeam
