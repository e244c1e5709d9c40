// SPDX-License-Identifier: MIT
#pragma once
/// @file Error handling at the boundary between PETSc (error codes) and the C++/Python API
/// (exceptions). Inside PETSc callbacks use PetscCall; at API boundaries use SB_CHECK. Every
/// callback handed to PETSc is registered as guarded<&callback>: an exception must not unwind
/// through PETSc's C frames (it would skip their error handling and leave PETSc's state, its
/// function stack and the objects in use, inconsistent). It becomes a PETSc error carrying its
/// message, and the SB_CHECK on the solve that called back throws it again as a PetscFailure:
/// Python gets an exception with the message, never a crash.

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
  char* specific = nullptr;  // the message of the error's origin (SETERRQ, an exception in a callback)
  PetscErrorMessage(ierr, &text, &specific);
  const std::string detail = specific && *specific ? std::string(": ") + specific : "";
  throw PetscFailure(std::string("PETSc error ") + std::to_string(static_cast<int>(ierr)) + " (" +
                     (text ? text : "?") + detail + ") in " + call + " at " + file + ":" + std::to_string(line));
}

/// The PETSc error the exception being handled becomes (call it in a catch block); ``context``
/// (an effect's label, or "") goes before the exception's message.
inline PetscErrorCode current_exception_to_petsc(const char* context) noexcept {
  const char* what = "unknown C++ exception";
  try {
    throw;
  } catch (const std::exception& e) {
    what = e.what();
  } catch (...) {
  }
  const char* sep = context && *context ? ": " : "";
  return PetscError(PETSC_COMM_SELF, __LINE__, "slidebeam callback", __FILE__, PETSC_ERR_LIB, PETSC_ERROR_INITIAL,
                    "%s%s%s", context ? context : "", sep, what);
}

template <auto Callback>
struct Guarded;

/// A PETSc callback with the same signature that returns a PETSc error instead of throwing.
template <class... Args, PetscErrorCode (*Callback)(Args...)>
struct Guarded<Callback> {
  static PetscErrorCode call(Args... args) noexcept {
    try {
      return Callback(args...);
    } catch (...) {
      return current_exception_to_petsc("");
    }
  }
};

/// ``guarded<&Class::callback>``: what to register with PETSc in place of ``&Class::callback``.
template <auto Callback>
inline constexpr auto guarded = &Guarded<Callback>::call;

}  // namespace slidebeam

#define SB_CHECK(call) ::slidebeam::check_petsc((call), #call, __FILE__, __LINE__)
