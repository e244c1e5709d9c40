// SPDX-License-Identifier: MIT
// The assembled, distributed Jacobian equals the finite-difference derivative of the assembled
// residual, with every effect active and any number of ranks (run at np = 1 and 2).
#include "model/model.hpp"
#include "util/petsc_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <utility>

using namespace slidebeam;

namespace {
BeamSpec straight_beam(const std::string& name, int spans, double L, const Eigen::Vector3d& X0,
                       kernels::StrainMeasure m, kernels::Quadrature q) {
  BeamSpec s;
  s.name = name;
  s.n_spans = spans;
  s.length = L;
  s.section = {5e3, 2e3, 2.5e3, 40.0, 60.0, 80.0, 1.0, 0.1, 0.2};
  s.strain = m;
  s.quadrature = q;
  for (int a = 0; a < spans + 2; ++a) {
    const double xi = bspline::greville(spans, a);
    const double v[12] = {X0(0) + xi * L, X0(1), X0(2), 1, 0, 0, 0, 1, 0, 0, 0, 1};
    s.q_ref.insert(s.q_ref.end(), v, v + 12);
  }
  return s;
}

// A beam along +y from X0, its triad (d1, d2, d3) = (e_y, -e_x, e_z).
BeamSpec turned_beam(const std::string& name, int spans, double L, const Eigen::Vector3d& X0) {
  BeamSpec s = straight_beam(name, spans, L, X0, kernels::StrainMeasure::SimoReissner, kernels::Quadrature::Full);
  s.q_ref.clear();
  for (int a = 0; a < spans + 2; ++a) {
    const double xi = bspline::greville(spans, a);
    const double v[12] = {X0(0), X0(1) + xi * L, X0(2), 0, 1, 0, -1, 0, 0, 0, 0, 1};
    s.q_ref.insert(s.q_ref.end(), v, v + 12);
  }
  return s;
}

// Deterministic value per global index, the same on every rank.
double pseudo_random(PetscInt i, double scale) { return scale * std::sin(12.9898 * (i + 1) + 78.233); }

void set_by_index(Vec v, double scale, const std::vector<PetscInt>& zero_rows, bool add) {
  PetscInt lo, hi;
  SB_CHECK(VecGetOwnershipRange(v, &lo, &hi));
  PetscScalar* a;
  SB_CHECK(VecGetArray(v, &a));
  for (PetscInt i = lo; i < hi; ++i) a[i - lo] = (add ? a[i - lo] : 0.0) + pseudo_random(i, scale);
  for (PetscInt r : zero_rows) a[r - lo] = add ? a[r - lo] : 0.0;
  SB_CHECK(VecRestoreArray(v, &a));
}

/// (|J v|, |(F(x + h v) - F(x - h v)) / (2 h) - J v|) in `norm`, h = 1e-6; F(state, out) is the
/// residual. x is left as it is.
std::pair<PetscReal, PetscReal> central_difference_error(const std::function<PetscErrorCode(Vec, Vec)>& F, Vec x,
                                                         Vec v, Vec Jv, NormType norm) {
  const double h = 1e-6;
  Vec y, F1, F2;
  for (Vec* w : {&y, &F1, &F2}) SB_CHECK(VecDuplicate(x, w));
  SB_CHECK(VecWAXPY(y, h, v, x));
  SB_CHECK(F(y, F1));
  SB_CHECK(VecWAXPY(y, -h, v, x));
  SB_CHECK(F(y, F2));
  SB_CHECK(VecAXPY(F1, -1.0, F2));
  SB_CHECK(VecScale(F1, 1.0 / (2 * h)));
  PetscReal nJv = 0, nerr = 0;
  SB_CHECK(VecNorm(Jv, norm, &nJv));
  SB_CHECK(VecAXPY(F1, -1.0, Jv));
  SB_CHECK(VecNorm(F1, norm, &nerr));
  for (Vec* w : {&y, &F1, &F2}) VecDestroy(w);
  return {nJv, nerr};
}
}  // namespace

TEST(Model, AssembledJacobianMatchesFiniteDifferences) {
  Model m(PETSC_COMM_WORLD);
  m.add_beam(straight_beam("A", 5, 3.0, {0, 0, 0}, kernels::StrainMeasure::Seed, kernels::Quadrature::Reduced));
  m.add_beam(straight_beam("B", 4, 2.0, {0, 1, 0}, kernels::StrainMeasure::SimoReissner, kernels::Quadrature::Full));
  m.add_beam(turned_beam("C", 3, 1.5, {2, 1, 0}));  // welded to B's end at a right angle
  // assumed strains: knot values couple neighbouring spans (and ranks); both measures
  m.add_beam(straight_beam("D", 6, 2.4, {0, 3, 0}, kernels::StrainMeasure::SimoReissner, kernels::Quadrature::AssumedStrain));
  m.add_beam(straight_beam("E", 1, 0.8, {0, 4, 0}, kernels::StrainMeasure::Seed, kernels::Quadrature::AssumedStrain));
  auto add = [&](const std::string& type, std::map<std::string, double> num,
                 std::map<std::string, std::vector<double>> vec = {}, std::map<std::string, std::string> str = {}) {
    m.add_effect(type, EffectParams{num, vec, str});
  };
  for (double b : {0.0, 1.0, 2.0, 3.0, 4.0}) {
    add("beam_elastic", {{"beam", b}});
    add("director_constraints", {{"beam", b}});
  }
  add("clamp", {{"beam", 0}, {"s", 0.0}});
  add("moment", {{"beam", 0}, {"s", 3.0}, {"tf_t1", 1.0}}, {{"value", {1.0, -2.0, 3.0}}},
      {{"frame", "material"}, {"tf_type", "ramp"}});
  add("moment", {{"beam", 0}, {"s", 1.7}}, {{"value", {0.5, 0.2, -1.0}}});
  add("force", {{"beam", 0}, {"s", 2.2}}, {{"value", {0.0, 1.0, 4.0}}});
  add("point_mass", {{"beam", 1}, {"s", 2.0}, {"mass", 2.0}});
  add("gravity", {}, {{"g", {0.0, -9.81, 0.0}}});
  add("spherical", {{"beam", 1}, {"s", 0.0}}, {{"position", {0.0, 1.0, 0.0}}});
  add("spherical", {{"beam", 1}, {"s", 1.3}}, {{"position", {1.3, 1.0, 0.0}}});
  add("rigid_joint", {{"beam_a", 1}, {"s_a", 2.0}, {"beam_b", 2}, {"s_b", 0.0}});
  add("clamp", {{"beam", 3}, {"s", 0.0}});
  add("force", {{"beam", 3}, {"s", 2.4}}, {{"value", {0.5, 3.0, -2.0}}});
  m.finalize();

  Vec x = m.x(), v, Jv;
  SB_CHECK(VecDuplicate(x, &v));
  SB_CHECK(VecDuplicate(x, &Jv));
  set_by_index(x, 0.05, m.prescribed_rows(), true);  // deformed, off the constraint manifold, lambda != 0
  set_by_index(v, 1.0, {}, false);  // J is the exact derivative of F, prescribed rows included
  const double t = 0.6;
  SB_CHECK(m.assemble_jacobian(t, x, m.jacobian()));
  SB_CHECK(MatMult(m.jacobian(), v, Jv));
  const auto [nJv, nerr] =
      central_difference_error([&](Vec y, Vec out) { return m.assemble_residual(t, y, out); }, x, v, Jv, NORM_2);
  EXPECT_GT(nJv, 1.0);
  EXPECT_LT(nerr, 1e-6 * nJv);
  for (Vec* w : {&v, &Jv}) VecDestroy(w);
}

TEST(Model, UnknownEffectAndBadParametersAreClearErrors) {
  Model m(PETSC_COMM_WORLD);
  m.add_beam(straight_beam("A", 2, 1.0, {0, 0, 0}, kernels::StrainMeasure::Seed, kernels::Quadrature::Full));
  try {
    m.add_effect("warp_drive", EffectParams{});
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("warp_drive"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("beam_elastic"), std::string::npos);
  }
  EXPECT_THROW(m.add_effect("clamp", EffectParams{{{"beam", 0}, {"s", 1.5}}, {}, {}}), std::invalid_argument);
  EXPECT_THROW(m.add_effect("beam_elastic", EffectParams{{{"beam", 3}}, {}, {}}), std::invalid_argument);
}

TEST(Model, DofMapCoversEveryUnknownOnce) {
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  for (int n_cp : {3, 7, 50}) {
    PetscInt total = 0;
    for (int r = 0; r < size; ++r) {
      DofMap d(std::vector<int>(static_cast<size_t>(n_cp), 12), std::vector<int>(static_cast<size_t>(n_cp), 6), 5, r,
               size);
      total += d.local_size();
      for (PetscInt cp = 0; cp < n_cp; ++cp)
        if (d.owns_cp(cp)) EXPECT_TRUE(d.q(cp, 0) >= d.owned_lo() && d.q(cp, 17) < d.owned_hi());
    }
    EXPECT_EQ(total, 18 * n_cp + 5);
  }
}

TEST(Model, DofMapWithFewerOwnersThanRanks) {
  // owners = 1 (a small model under mpirun): rank 0 holds every unknown, extras included; the
  // other ranks hold nothing; the same numbering as the even split. Checked for 1 to 4 ranks.
  const int n_cp = 7;
  const std::vector<int> nq(n_cp, 12), nl(n_cp, 6);
  for (int size = 1; size <= 4; ++size) {
    for (int owners : {1, 2}) {
      if (owners > size) continue;
      PetscInt total = 0, lo_expected = 0;
      for (int r = 0; r < size; ++r) {
        DofMap d(nq, nl, 5, r, size, {}, owners);
        DofMap even(nq, nl, 5, r, size);
        EXPECT_EQ(d.owners(), owners);
        EXPECT_EQ(d.owned_lo(), lo_expected);  // contiguous, in rank order
        lo_expected = d.owned_hi();
        total += d.local_size();
        if (r >= owners) EXPECT_EQ(d.local_size(), 0);
        for (PetscInt cp = 0; cp < n_cp; ++cp) {
          EXPECT_EQ(d.q(cp, 3), even.q(cp, 3));
          EXPECT_LT(d.cp_owner(cp), owners);
          if (d.owns_cp(cp)) EXPECT_TRUE(d.q(cp, 0) >= d.owned_lo() && d.q(cp, 17) < d.owned_hi());
        }
        if (r == owners - 1) EXPECT_EQ(d.owned_hi(), 18 * n_cp + 5);  // the extras on the last owner
      }
      EXPECT_EQ(total, 18 * n_cp + 5);
    }
  }
}

TEST(Model, DofMapNumbersSlotsInTheGivenOrder) {
  // Slots follow the order; each rank owns a contiguous run of it with about its share of the
  // unknowns; the numbering is the same on any number of ranks.
  const std::vector<int> nq = {12, 12, 12, 6, 6, 12, 12}, nl = {6, 6, 6, 0, 0, 6, 6}, attached = {0, 4, 0, 0, 0, 0, 0};
  const std::vector<PetscInt> order = {3, 0, 5, 1, 6, 4, 2};
  for (int size = 1; size <= 4; ++size) {
    PetscInt next_lo = 0;
    for (int r = 0; r < size; ++r) {
      DofMap d(nq, nl, 5, r, size, attached, 0, order);
      DofMap serial(nq, nl, 5, 0, 1, attached, 0, order);
      EXPECT_EQ(d.owned_lo(), next_lo);
      next_lo = d.owned_hi();
      PetscInt expected = 0;
      int last_owner = 0;
      for (PetscInt cp : order) {
        EXPECT_EQ(d.q(cp, 0), expected);
        EXPECT_EQ(d.q(cp, 0), serial.q(cp, 0));
        expected += d.slot_size(cp);
        EXPECT_GE(d.cp_owner(cp), last_owner);  // owners in order
        last_owner = d.cp_owner(cp);
        if (d.owns_cp(cp)) EXPECT_TRUE(d.q(cp, 0) >= d.owned_lo() && d.q(cp, d.slot_size(cp) - 1) < d.owned_hi());
      }
      EXPECT_EQ(d.slot_size(1), 22);
      EXPECT_EQ(d.extra(0), expected);
    }
    EXPECT_EQ(next_lo, 5 * 18 + 2 * 6 + 4 + 5);
  }
  // joined positions move a boundary on: positions 1-3 of the order (points 0, 5, 1) stay together
  const std::vector<char> joined = {0, 0, 1, 1, 0, 0, 0};
  for (int size = 2; size <= 3; ++size)
    for (int r = 0; r < size; ++r) {
      DofMap d(nq, nl, 5, r, size, attached, 0, order, joined);
      EXPECT_EQ(d.cp_owner(0), d.cp_owner(5));
      EXPECT_EQ(d.cp_owner(5), d.cp_owner(1));
    }
  EXPECT_THROW(DofMap(nq, nl, 0, 0, 1, {}, 0, {0, 1, 2}), std::invalid_argument);
  EXPECT_THROW(DofMap(nq, nl, 0, 0, 1, {}, 0, {0, 1, 2, 3, 4, 5, 5}), std::invalid_argument);
}

TEST(Model, DofMapMixedBlockSizes) {
  // Director control points (12 + 6) and ANCF nodes (6 + 0) in one numbering: blocks are
  // contiguous, multipliers follow the coordinates, extras follow all blocks.
  const std::vector<int> nq = {12, 12, 6, 6, 6, 12}, nl = {6, 6, 0, 0, 0, 6};
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  PetscInt total = 0, next = 0;
  for (int r = 0; r < size; ++r) {
    DofMap d(nq, nl, 4, r, size);
    total += d.local_size();
    if (r == 0) {
      for (PetscInt cp = 0; cp < 6; ++cp) {
        EXPECT_EQ(d.q(cp, 0), next);
        EXPECT_EQ(d.n_coordinates(cp), nq[static_cast<size_t>(cp)]);
        if (nl[static_cast<size_t>(cp)] > 0) EXPECT_EQ(d.lambda(cp, 0), next + nq[static_cast<size_t>(cp)]);
        next += d.block_size(cp);
      }
      EXPECT_EQ(d.extra(0), next);
    }
    for (PetscInt cp = 0; cp < 6; ++cp)
      if (d.owns_cp(cp))
        EXPECT_TRUE(d.q(cp, 0) >= d.owned_lo() && d.q(cp, d.block_size(cp) - 1) < d.owned_hi());
  }
  EXPECT_EQ(total, 18 * 3 + 6 * 3 + 4);
}

namespace {
// x[rows] = values (owned rows only; the same on every rank).
void set_rows(Vec x, const std::vector<PetscInt>& rows, const std::vector<double>& values) {
  PetscInt lo, hi;
  SB_CHECK(VecGetOwnershipRange(x, &lo, &hi));
  for (size_t k = 0; k < rows.size(); ++k)
    if (rows[k] >= lo && rows[k] < hi) SB_CHECK(VecSetValue(x, rows[k], values[k], INSERT_VALUES));
  SB_CHECK(VecAssemblyBegin(x));
  SB_CHECK(VecAssemblyEnd(x));
}
double dot(Vec a, Vec b) {
  PetscScalar d;
  SB_CHECK(VecDot(a, b, &d));
  return d;
}
}  // namespace

// The sliding joint alone (no beam terms), with the slider's s moved across two knots within the
// step and every state off the constraint manifold: for every step rule the joint's Jacobian is
// the derivative of its residual, and under energy-momentum its force G* does exactly the work
// Phi_n+1 - Phi_n (lambda . Delta Phi). The frame form's step force also has no resultant and no
// moment about the mid-step configuration; the spatial form's has a moment (issue 21).
TEST(SlidingJoint, StepForcesJacobianEnergyAndMoment) {
  for (const std::string form : {"frame", "spatial"})
  for (const double at : {0.0, 0.3}) {  // the slider's end (one control point), a point inside it (three)
    SCOPED_TRACE(form + " at " + std::to_string(at));
    Model m(PETSC_COMM_WORLD);
    m.add_beam(straight_beam("carrier", 6, 3.0, {0, 0, 0}, kernels::StrainMeasure::SimoReissner, kernels::Quadrature::Full));
    m.add_beam(turned_beam("slider", 2, 1.0, {1.1, -at, 0}));  // its point at arc length `at` sits on the carrier at s = 1.1
    m.add_effect("sliding_joint", EffectParams{{{"slider", 1.0}, {"slider_s", at}, {"carrier", 0.0}}, {}, {{"form", form}}});
    m.finalize();
    const PetscInt e0 = part_of<ExtraUnknowns>(*m.effects()[0])->extra_offset();
    const std::vector<PetscInt> extras = {e0, e0 + 1, e0 + 2, e0 + 3};  // lambda, s
    Vec x0, x1, xm, v, F, F1, F2, Jv, state;
    SB_CHECK(VecDuplicate(m.x(), &x0));
    SB_CHECK(VecCopy(m.x(), x0));
    for (Vec* w : {&x1, &xm, &v, &F, &F1, &F2, &Jv, &state}) SB_CHECK(VecDuplicate(x0, w));
    set_by_index(x0, 0.05, {}, true);
    SB_CHECK(VecCopy(x0, x1));
    set_by_index(x1, 0.03, {}, true);
    set_rows(x0, extras, {0.7, -1.3, 2.1, 1.1});
    set_rows(x1, extras, {-0.4, 1.9, 0.8, 2.07});  // s from 1.1 to 2.07: across the knots at 1.5 and 2.0
    SB_CHECK(VecWAXPY(xm, 1.0, x0, x1));
    SB_CHECK(VecScale(xm, 0.5));
    SB_CHECK(VecWAXPY(state, 1.0, m.coordinate_mask(), m.sliding_mask()));
    SB_CHECK(m.set_step_start(x0));
    set_by_index(v, 1.0, {}, false);
    for (const StepEval ev : {StepEval{StepRule::EnergyMomentum, 0.0, 0.5}, StepEval{StepRule::Theta, 0.0, 0.5},
                              StepEval{StepRule::Endpoint, 0.0, 1.0}}) {
      SCOPED_TRACE(static_cast<int>(ev.rule));
      CooAssembly coo;
      SB_CHECK(m.assemble_effects_jacobian(ev, x1, m.jacobian(), &coo));
      SB_CHECK(MatMult(m.jacobian(), v, Jv));
      const auto [nJv, nerr] = central_difference_error(
          [&](Vec y, Vec out) { return m.assemble_effects_residual(ev, y, out); }, x1, v, Jv, NORM_INFINITY);
      EXPECT_GT(nJv, 0.1);
      EXPECT_LT(nerr, 1e-8 * nJv);
    }
    // the energy-momentum force's work over the step, against lambda . (Phi(x1) - Phi(x0))
    SB_CHECK(m.assemble_effects_residual(StepEval{StepRule::EnergyMomentum, 0.0, 0.5}, x1, F));
    SB_CHECK(VecPointwiseMult(F, F, state));
    SB_CHECK(VecWAXPY(v, -1.0, x0, x1));
    const double work = dot(F, v);
    SB_CHECK(m.assemble_effects_residual(StepEval{StepRule::Endpoint, 0.0, 1.0}, x1, F1));
    SB_CHECK(m.assemble_effects_residual(StepEval{StepRule::Endpoint, 0.0, 1.0}, x0, F2));
    SB_CHECK(VecAXPY(F1, -1.0, F2));
    const std::vector<double> lam = m.extra_values(0, x1);
    const std::vector<double> dphi = m.extra_values(0, F1);
    const double dPhi = lam[0] * dphi[0] + lam[1] * dphi[1] + lam[2] * dphi[2];
    EXPECT_GT(std::abs(dPhi), 1e-3);
    EXPECT_NEAR(work, dPhi, 1e-13 * (1.0 + std::abs(dPhi)));
    // resultant and moment about the mid-step state of the step forces on the coordinates
    for (const StepEval ev : {StepEval{StepRule::EnergyMomentum, 0.0, 0.5}, StepEval{StepRule::Theta, 0.0, 0.5}}) {
      SCOPED_TRACE(static_cast<int>(ev.rule));
      SB_CHECK(m.assemble_effects_residual(ev, x1, F));
      SB_CHECK(VecPointwiseMult(F, F, m.coordinate_mask()));
      const Momenta p = m.momenta(xm, F);
      const Eigen::Vector3d force(p.linear.data()), moment(p.angular.data());
      PetscReal nF;
      SB_CHECK(VecNorm(F, NORM_INFINITY, &nF));
      EXPECT_GT(nF, 0.1);
      EXPECT_LT(force.norm(), 1e-14 * nF);
      if (form == "frame") EXPECT_LT(moment.norm(), 1e-14 * nF);
      else EXPECT_GT(moment.norm(), 1e-4 * nF);
    }
    for (Vec* w : {&x0, &x1, &xm, &v, &F, &F1, &F2, &Jv, &state}) VecDestroy(w);
  }
}
