// SPDX-License-Identifier: MIT
// An exception thrown by an effect inside a solve (a PETSc callback) comes back from the solve as
// a PetscFailure naming the effect and carrying the message; PETSc stays usable afterwards.
#include "model/model.hpp"
#include "solvers/static_solver.hpp"
#include "util/petsc_check.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace slidebeam;

namespace {
/// A term that fails in its residual or its Jacobian, as a kernel with a bug would.
class FailingTerm final : public Effect {
 public:
  FailingTerm(const Model&, const EffectParams& p) : in_jacobian_(p.number("in_jacobian") != 0.0) {}
  std::string type() const override { return "failing_term"; }
  std::string label() const override { return "failing_term[test]"; }
  void distribute(const Model&) override {}
  void needed_dofs(const Model&, std::vector<PetscInt>&) const override {}
  PetscErrorCode pattern(const Model&, const MatSink&) const override { return 0; }
  PetscErrorCode residual(const EvalContext&, const LocalValues&) const override {
    if (!in_jacobian_) throw std::runtime_error("the kernel met a NaN");
    return 0;
  }
  PetscErrorCode jacobian(const EvalContext&, const MatSink&) const override {
    if (in_jacobian_) throw std::out_of_range("a row outside the local block");
    return 0;
  }

 private:
  bool in_jacobian_;
};

void register_failing_term() {
  static const bool once = [] {
    EffectSpec spec;
    spec.type = "failing_term";
    spec.meaning = "a term that throws (test)";
    EffectRegistry::instance().add(spec, [](const Model& m, const EffectParams& p) {
      return std::make_unique<FailingTerm>(m, p);
    });
    return true;
  }();
  (void)once;
}

BeamSpec cantilever() {
  BeamSpec s;
  s.name = "rod";
  s.n_spans = 3;
  s.length = 1.0;
  s.section = {5e3, 2e3, 2.5e3, 40.0, 60.0, 80.0, 1.0, 0.1, 0.2};
  for (int a = 0; a < s.n_spans + 2; ++a) {
    const double xi = bspline::greville(s.n_spans, a);
    const double v[12] = {xi * s.length, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    s.q_ref.insert(s.q_ref.end(), v, v + 12);
  }
  return s;
}

std::string failure_of_a_solve(bool in_jacobian) {
  register_failing_term();
  Model m(PETSC_COMM_WORLD);
  m.add_beam(cantilever());
  m.add_effect("beam_elastic", EffectParams{{{"beam", 0.0}}, {}, {}});
  m.add_effect("director_constraints", EffectParams{{{"beam", 0.0}}, {}, {}});
  m.add_effect("clamp", EffectParams{{{"beam", 0.0}, {"s", 0.0}}, {}, {}});
  m.add_effect("force", EffectParams{{{"beam", 0.0}, {"s", 1.0}}, {{"value", {0.0, 0.0, 1.0}}}, {}});  // Newton iterates
  m.add_effect("failing_term", EffectParams{{{"in_jacobian", in_jacobian ? 1.0 : 0.0}}, {}, {}});
  m.finalize();
  StaticSolver solver(m);
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);  // no traceback print in the test log
  struct PopHandler {
    ~PopHandler() { PetscPopErrorHandler(); }
  } pop;
  try {
    solver.solve(1.0);
  } catch (const PetscFailure& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Callbacks, AnExceptionInAResidualComesBackNamingTheEffect) {
  const std::string what = failure_of_a_solve(false);
  EXPECT_NE(what.find("failing_term[test]: the kernel met a NaN"), std::string::npos) << what;
  EXPECT_NE(what.find("SNESSolve"), std::string::npos) << what;
}

TEST(Callbacks, AnExceptionInAJacobianComesBackNamingTheEffect) {
  const std::string what = failure_of_a_solve(true);
  EXPECT_NE(what.find("failing_term[test]: a row outside the local block"), std::string::npos) << what;
  // PETSc is in order after the failure: a further solve fails the same way, cleanly
  EXPECT_EQ(failure_of_a_solve(true), what);
}

namespace {
PetscErrorCode doubling(int a, double* b) {
  *b = 2.0 * a;
  return 0;
}
PetscErrorCode throwing(int, double*) { throw std::runtime_error("boom"); }
}  // namespace

TEST(Callbacks, GuardedKeepsTheCallbacksSignatureAndResult) {
  double out = 0.0;
  EXPECT_EQ(guarded<&doubling>(3, &out), 0);
  EXPECT_EQ(out, 6.0);
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);  // no traceback print in the test log
  EXPECT_EQ(guarded<&throwing>(3, &out), PETSC_ERR_LIB);
  PetscPopErrorHandler();
}
