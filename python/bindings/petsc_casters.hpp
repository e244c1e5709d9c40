// SPDX-License-Identifier: MIT
#pragma once
/// @file pybind11 type casters: PETSc handles <-> petsc4py objects, sharing the same handle
/// (no copy). PyPetscXxx_New takes its own reference, so a getter of a handle the C++ side
/// keeps returns an object that stays valid even after the C++ owner is gone.

#include <petsc4py/petsc4py.h>
#include <pybind11/pybind11.h>

#include <stdexcept>

#define SB_VERIFY_PETSC4PY(func)                                                     \
  if (!func) {                                                                       \
    if (import_petsc4py() != 0) throw std::runtime_error("could not import petsc4py"); \
  }

#define SB_PETSC_CASTER(TYPE, P4PYTYPE, NAME)                                                     \
  template <>                                                                                     \
  class type_caster<_p_##TYPE> {                                                                  \
   public:                                                                                        \
    PYBIND11_TYPE_CASTER(TYPE, const_name(#NAME));                                                \
    bool load(handle src, bool) {                                                                 \
      SB_VERIFY_PETSC4PY(PyPetsc##P4PYTYPE##_Get);                                                \
      if (PyObject_TypeCheck(src.ptr(), &PyPetsc##P4PYTYPE##_Type) != 0) {                        \
        value = PyPetsc##P4PYTYPE##_Get(src.ptr());                                               \
        return true;                                                                              \
      }                                                                                           \
      return false;                                                                               \
    }                                                                                             \
    static handle cast(TYPE src, return_value_policy policy, handle) {                            \
      SB_VERIFY_PETSC4PY(PyPetsc##P4PYTYPE##_New);                                                \
      PyObject* obj = PyPetsc##P4PYTYPE##_New(src);                                               \
      if (policy == return_value_policy::take_ownership) PetscObjectDereference((PetscObject)src); \
      return handle(obj);                                                                         \
    }                                                                                             \
    operator TYPE() { return value; }                                                             \
  }

namespace pybind11::detail {
SB_PETSC_CASTER(Vec, Vec, vec);
SB_PETSC_CASTER(Mat, Mat, mat);
SB_PETSC_CASTER(SNES, SNES, snes);
}  // namespace pybind11::detail
