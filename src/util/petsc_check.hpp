// SPDX-License-Identifier: MIT
#pragma once
/// @file Error handling at the boundary between PETSc (error codes) and the C++/Python API
/// (exceptions). Inside PETSc callbacks use PetscCall; at API boundaries use SB_CHECK.

#include <petscsys.h>

#include <stdexcept>
#include <string>

namespace slidebeam {

/// A PETSc call failed; what() carries PETSc's message and the failing call.
class PetscFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A solve could not be done (e.g. a singular system): a property of the input, not a bug.
class SolverFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline void check_petsc(PetscErrorCode ierr, const char* call, const char* file, int line) {
  if (ierr == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(ierr, &text, nullptr);
  throw PetscFailure(std::string("PETSc error ") + std::to_string(static_cast<int>(ierr)) + " (" +
                     (text ? text : "?") + ") in " + call + " at " + file + ":" + std::to_string(line));
}

}  // namespace slidebeam

#define SB_CHECK(call) ::slidebeam::check_petsc((call), #call, __FILE__, __LINE__)
