// SPDX-License-Identifier: MIT
#include "solvers/time_integrator.hpp"

#include <algorithm>

#include "solvers/block_solve_path.hpp"
#include "solvers/solver_options.hpp"

#include "util/petsc_check.hpp"

#include <cmath>
#include <stdexcept>

namespace slidebeam {

IntegratorKind integrator_from(const std::string& name) {
  if (name == "energy-momentum") return IntegratorKind::EnergyMomentum;
  if (name == "midpoint") return IntegratorKind::Midpoint;
  if (name == "newmark") return IntegratorKind::Newmark;
  if (name == "hht") return IntegratorKind::HHT;
  throw std::invalid_argument("unknown integrator '" + name + "' (energy-momentum, midpoint, newmark, hht)");
}

namespace {
bool is_midpoint_type(IntegratorKind k) { return k == IntegratorKind::EnergyMomentum || k == IntegratorKind::Midpoint; }
}  // namespace

TimeIntegrator::TimeIntegrator(Model& model, const IntegratorParams& params) : model_(model), params_(params) {
  finalize_from_options(model);
  if (!model.has_inertia()) throw std::invalid_argument("a dynamic model needs inertia (beam_inertia or point_mass)");
  if (!(params.dissipation >= 0.0 && params.dissipation <= 1.0))
    throw std::invalid_argument("energy-momentum dissipation must lie in [0, 1]");
  if (!is_midpoint_type(params.kind)) {
    if (!(params.beta > 0)) throw std::invalid_argument("Newmark beta must be > 0");
    if (params.kind == IntegratorKind::HHT && (params.alpha < -1.0 / 3.0 || params.alpha > 0))
      throw std::invalid_argument("HHT alpha must lie in [-1/3, 0]");
  }
  PetscLogEventRegister("SBTimeStep", 0, &ev_step_);
  // The energy-decaying variant's strain force is C (a0 eps_n + a1 eps_n+1), a1 - a0 = xi: over a
  // step it does the strain energy's change plus xi/2 deps C deps. That excess is counted as the
  // strain effect's own dissipation, measured as its work minus its energy's change (the same
  // bookkeeping as a timed potential's), so that the balance stays at the Newton tolerance.
  const bool decaying = params.kind == IntegratorKind::EnergyMomentum && params.dissipation > 0.0;
  for (size_t k = 0; k < model.effects().size(); ++k) {
    const Effect& e = *model.effects()[k];
    const EffectSpec& spec = EffectRegistry::instance().spec(e.type());
    EnergyRole role = spec.role;
    const auto* motion = part_of<PrescribedMotion>(e);
    if (role == EnergyRole::Constraint && motion && motion->drives()) role = EnergyRole::Driving;
    // a dissipative effect that also stores energy (friction's stuck points on a contact): what
    // it dissipates is its work minus its energy's change
    const bool timed = (role == EnergyRole::Stored && e.time_dependent()) ||
                       (role == EnergyRole::Dissipative && !spec.stored.empty());
    const bool decaying_strain = decaying && role == EnergyRole::Stored && spec.stored == "strain";
    if (role == EnergyRole::External || role == EnergyRole::Dissipative || role == EnergyRole::Driving || timed ||
        decaying_strain) {
      if (timed || decaying_strain) timed_.push_back(flows_.size());
      flows_.push_back({k, decaying_strain ? EnergyRole::Dissipative : role, 0.0});
    }
  }
  M_ = model.create_mass_matrix();
  SB_CHECK(VecDuplicate(model.x(), &x_));
  SB_CHECK(VecDuplicate(x_, &v_));
  SB_CHECK(VecDuplicate(x_, &a_));
  SB_CHECK(VecDuplicate(x_, &x1_));
  SB_CHECK(VecDuplicate(x_, &x_start_));
  SB_CHECK(VecDuplicate(x_, &v_prev_));
  if (model.has_configuration_kinetic()) {
    SB_CHECK(VecDuplicate(x_, &v_start_));
    SB_CHECK(VecDuplicate(x_, &a_start_));
  }
  SB_CHECK(VecDuplicate(x_, &xt_));
  SB_CHECK(VecDuplicate(x_, &w_));
  SB_CHECK(VecDuplicate(x_, &f_hist_));
  SB_CHECK(VecDuplicate(x_, &work_));
  SB_CHECK(VecDuplicate(x_, &sdot_));
  SB_CHECK(VecDuplicate(x_, &state_mask_));
  SB_CHECK(VecWAXPY(state_mask_, 1.0, model.coordinate_mask(), model.sliding_mask()));
  SB_CHECK(VecCopy(model.x(), x_));
  SB_CHECK(VecZeroEntries(v_));
  SB_CHECK(VecZeroEntries(a_));

  SB_CHECK(MatDuplicate(model.jacobian(), MAT_DO_NOT_COPY_VALUES, &J_));
  SB_CHECK(SNESCreate(model.comm(), &snes_));
  SB_CHECK(set_solver_prefix(snes_, kStepPrefix));  // -sb_ts_snes_rtol, or plain -snes_rtol
  SB_CHECK(SNESSetFunction(snes_, model.residual_vector(), guarded<&TimeIntegrator::form_function>, this));
  SB_CHECK(SNESSetJacobian(snes_, J_, J_, guarded<&TimeIntegrator::form_jacobian>, this));
  SB_CHECK(configure_newton(snes_, &test_));
  SB_CHECK(SNESSetConvergenceTest(snes_, guarded<&TimeIntegrator::converged>, this, nullptr));
  // Serial steps: PETSc's own LU in the natural order first. Coordinates come before their
  // multipliers, so c0 M + theta K is eliminated before the constraint rows and their pivots are
  // Schur complements, nonzero as long as the coordinate block is regular: 2-3x faster than
  // SuperLU on these small banded systems. It does not pivot, so a zero pivot (d1 of the seed's
  // strains, which has neither mass nor stiffness) or any failed step retries the step on SuperLU
  // (use_pivoting_lu); the steps after it return to the fast LU (step()). An explicit
  // -pc_factor_mat_solver_type wins over both.
  // An explicit solver or preconditioner (-pc_type asm, -pc_type fieldsplit, ...) from the
  // options database wins.
  const bool user_solver = solver_option_set(kStepPrefix, "-pc_factor_mat_solver_type") ||
                           solver_option_set(kStepPrefix, "-pc_type");
  int size = 1;
  MPI_Comm_size(model.comm(), &size);
  const CoreOptions options = core_options(model.comm());
  if (BlockSolvePath::requested(model.comm(), kStepPrefix)) {
    blocks_ = std::make_unique<BlockSolvePath>(model, snes_, J_, kStepPrefix);
    block_path_ = true;
  } else if (size == 1 && !user_solver) {
    if (options.condense_directors) {
      condensation_ = std::make_unique<DirectorCondensation>(model, model.elimination_order());
      if (condensation_->empty()) condensation_.reset();
    }
    attach_fast_lu();
  }
  backtrack_retry_ = options.backtrack == PETSC_TRUE;
  reuse_ = options.jacobian_reuse;
  // -sb_newton_by_cost without -sb_jacobian_reuse: the Newton variant of each stretch of steps
  // is chosen by its cost (choose_newton)
  auto_reuse_ = options.newton_by_cost && !options.jacobian_reuse_set;
  if (auto_reuse_) reset_newton_choice();
  reuse_rate_ = options.jacobian_reuse_rate;
  full_newton_after_rebuild_ = options.full_newton_after_rebuild;
  floor_stop_ = options.floor_stop;
  if (reuse_) SB_CHECK(SNESSetLagJacobian(snes_, -2));
  SB_CHECK(SNESSetFromOptions(snes_));
}

TimeIntegrator::~TimeIntegrator() {
  SNESDestroy(&snes_);
  MatDestroy(&M_);
  MatDestroy(&J_);
  for (Vec* v : {&x_, &v_, &a_, &x1_, &x_start_, &v_start_, &a_start_, &v_prev_, &xt_, &w_, &f_hist_, &work_, &sdot_, &state_mask_,
                 &flow_dq_, &flow_r_, &flow_r0_})
    VecDestroy(v);
}

StepEval TimeIntegrator::step_eval() const {
  switch (params_.kind) {
    case IntegratorKind::EnergyMomentum:
      return {StepRule::EnergyMomentum, 0.5 * (clock_.time() + next_time(h_)), 0.5, params_.dissipation, clock_.time(), next_time(h_), h_,
              StepScheme::EnergyMomentum};
    case IntegratorKind::Midpoint:
      return {StepRule::Theta, 0.5 * (clock_.time() + next_time(h_)), 0.5, 0.0, clock_.time(), next_time(h_), h_, StepScheme::Midpoint};
    default: {
      StepEval ev{StepRule::Endpoint, next_time(h_), 1.0, 0.0, clock_.time(), next_time(h_), h_,
                  params_.kind == IntegratorKind::HHT ? StepScheme::HHT : StepScheme::Newmark};
      if (params_.kind == IntegratorKind::HHT) ev.rate_weight = 1.0 / (1.0 + params_.alpha);
      return ev;
    }
  }
}

void TimeIntegrator::initialize(double t, Vec x, Vec v) {
  clock_.start(t);
  model_.set_prescribed_time(t);
  for (EnergyFlow& f : flows_) f.work = 0.0;
  model_.clear_effect_history();
  SB_CHECK(VecCopy(x, x_));
  model_.apply_prescribed(x_);
  SB_CHECK(VecPointwiseMult(v_, v, model_.coordinate_mask()));
  SB_CHECK(VecZeroEntries(a_));
  SB_CHECK(VecZeroEntries(sdot_));
  h_prev_ = 0.0;
  timed_energy_.clear();
  stepped_ = false;
  projection_ = {};
  PetscReal speed = 0.0;
  SB_CHECK(VecNorm(v_, NORM_INFINITY, &speed));
  // -sb_project_velocity false: the velocity as given, sliding rates 0
  if (!core_options(model_.comm()).project_velocity) speed = 0.0;
  const bool newmark = !is_midpoint_type(params_.kind);
  if (speed == 0.0 && !newmark) return;
  KSP ksp = constrained_mass_solver();
  if (speed > 0.0) project_velocity(ksp);
  if (newmark) consistent_acceleration(ksp);
  SB_CHECK(KSPDestroy(&ksp));
  jac_solve_ = -1;  // J_ holds the constrained mass system now: the first step must rebuild it
  if (reuse_) SB_CHECK(SNESSetLagJacobian(snes_, -2));
}

void TimeIntegrator::set_energy_flows(const std::vector<double>& work) {
  if (work.size() != flows_.size())
    throw std::invalid_argument("energy flows: " + std::to_string(work.size()) + " values for " +
                                std::to_string(flows_.size()) + " counted effects");
  for (size_t i = 0; i < work.size(); ++i) flows_[i].work = work[i];
  timed_energy_.clear();
}

void TimeIntegrator::account_energy_flows() {
  if (flows_.empty()) return;
  if (!flow_dq_) {
    SB_CHECK(VecDuplicate(x_, &flow_dq_));
    SB_CHECK(VecDuplicate(x_, &flow_r_));
    SB_CHECK(VecDuplicate(x_, &flow_r0_));
  }
  // the work of the step's own force of each effect along the step: -r_e . (q_n+1 - q_n), on
  // the state rows (coordinates and sliding coordinates; multipliers do no work)
  SB_CHECK(VecWAXPY(flow_dq_, -1.0, x_, x1_));
  SB_CHECK(VecPointwiseMult(flow_dq_, flow_dq_, state_mask_));
  const StepEval ev = step_eval();
  // A driven support that prescribes unknowns: its force there is the step's residual before the
  // rows are replaced (inertia included), which does the work R . dq on them. A support that
  // held its unknowns over the step did no work: no residual is needed then (a drive that
  // has stopped, the common case after a ramp).
  std::vector<std::vector<PetscInt>> driven(flows_.size());
  bool moved = false;
  {
    const PetscScalar* dq = nullptr;
    PetscInt lo = 0, hi = 0;
    SB_CHECK(VecGetOwnershipRange(flow_dq_, &lo, &hi));
    SB_CHECK(VecGetArrayRead(flow_dq_, &dq));
    for (size_t i = 0; i < flows_.size(); ++i) {
      if (flows_[i].role != EnergyRole::Driving) continue;
      std::vector<PetscScalar> vals;
      const auto* motion = part_of<PrescribedMotion>(*model_.effects()[flows_[i].effect]);
      if (motion) motion->prescribed_at(model_, next_time(h_), driven[i], vals);
      for (PetscInt r : driven[i])
        if (r >= lo && r < hi && dq[r - lo] != 0.0) moved = true;
    }
    SB_CHECK(VecRestoreArrayRead(flow_dq_, &dq));
  }
  MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_CXX_BOOL, MPI_LOR, model_.comm());
  if (moved) {
    SB_CHECK(step_forces(x1_, flow_r0_));  // collective: on every rank
    const PetscScalar *raw = nullptr, *dq = nullptr;
    PetscInt lo = 0, hi = 0;
    SB_CHECK(VecGetOwnershipRange(flow_r0_, &lo, &hi));
    SB_CHECK(VecGetArrayRead(flow_r0_, &raw));
    SB_CHECK(VecGetArrayRead(flow_dq_, &dq));
    std::vector<double> w(flows_.size(), 0.0);
    for (size_t i = 0; i < flows_.size(); ++i)
      for (PetscInt r : driven[i])
        if (r >= lo && r < hi) w[i] += raw[r - lo] * dq[r - lo];
    SB_CHECK(VecRestoreArrayRead(flow_dq_, &dq));
    SB_CHECK(VecRestoreArrayRead(flow_r0_, &raw));
    MPI_Allreduce(MPI_IN_PLACE, w.data(), static_cast<int>(w.size()), MPI_DOUBLE, MPI_SUM, model_.comm());
    for (size_t i = 0; i < flows_.size(); ++i) flows_[i].work += w[i];
  }
  for (EnergyFlow& f : flows_) {
    SB_CHECK(model_.effect_residual(f.effect, ev, x1_, flow_r_));
    if (scale_ != 1.0) SB_CHECK(VecScale(flow_r_, scale_));
    if (has_history_force_) {  // HHT: (1 + alpha) F(x_n+1) - alpha F(x_n)
      SB_CHECK(model_.effect_residual(f.effect, StepEval{StepRule::Endpoint, clock_.time(), 1.0}, x_, flow_r0_));
      SB_CHECK(VecAXPY(flow_r_, -params_.alpha, flow_r0_));
    }
    PetscScalar d = 0.0;
    SB_CHECK(VecDot(flow_r_, flow_dq_, &d));
    f.work -= d;
  }
  if (!timed_.empty()) {
    // a time-dependent potential: its change over the step minus the work of its force is the
    // work its explicit time dependence put in
    remember_start_energies();
    const std::vector<double> e1 = model_.effect_energies(next_time(h_), x1_, timed_effects());
    for (size_t j = 0; j < timed_.size(); ++j) flows_[timed_[j]].work += e1[j] - timed_energy_[j];
    timed_energy_ = e1;
  }
}

std::vector<size_t> TimeIntegrator::timed_effects() const {
  std::vector<size_t> which;
  for (size_t i : timed_) which.push_back(flows_[i].effect);
  return which;
}

void TimeIntegrator::remember_start_energies() {
  if (timed_.empty() || !timed_energy_.empty()) return;
  timed_energy_ = model_.effect_energies(clock_.time(), x_, timed_effects());
}

KSP TimeIntegrator::constrained_mass_solver() {
  SB_CHECK(model_.set_step_start(x_));
  StepEval ev{StepRule::Theta, clock_.time(), 0.0};
  ev.configuration_mass = true;
  SB_CHECK(model_.assemble_effects_jacobian(ev, x_, J_, &coo_, 1.0, 1.0));
  SB_CHECK(model_.set_prescribed_jacobian_rows(J_));
  // Its own pivoting LU: M has no entries on multipliers (and on d1 with the seed's strains).
  KSP ksp = nullptr;
  PC pc = nullptr;
  int size = 1;
  MPI_Comm_size(model_.comm(), &size);
  SB_CHECK(KSPCreate(model_.comm(), &ksp));
  SB_CHECK(KSPSetOptionsPrefix(ksp, kMassPrefix));  // -sb_mass_ksp_type ... (plain options do not apply)
  SB_CHECK(default_mumps_workspace(kMassPrefix));
  SB_CHECK(KSPSetType(ksp, KSPPREONLY));
  SB_CHECK(KSPGetPC(ksp, &pc));
  SB_CHECK(PCSetType(pc, PCLU));
  SB_CHECK(PCFactorSetMatSolverType(pc, size == 1 ? MATSOLVERSUPERLU : MATSOLVERMUMPS));
  SB_CHECK(KSPSetOperators(ksp, J_, J_));
  SB_CHECK(KSPSetFromOptions(ksp));
  return ksp;
}

/// The velocity's projection onto the constraints' tangent space in the mass metric, from the
/// saddle-point system of the constrained mass matrix (theta = 0 keeps exactly the constraint
/// terms: the force rows' G^T and the constraint rows' G, the sliding coordinates' columns
/// included):
///   [ M    0    G_q^T ] [ v'   ]   [ M v ]
///   [ 0    0    G_s^T ] [ sdot ] = [ 0   ]
///   [ G_q  G_s  0     ] [ mu   ]   [ 0   ]
/// Prescribed rows are identity rows with 0 on the right: supports do not move.
void TimeIntegrator::project_velocity(KSP ksp) {
  Vec rhs = work_, y = x1_, dv = w_, Mv = xt_;  // scratch (a step recomputes them)
  SB_CHECK(MatMult(M_, v_, rhs));
  {
    PetscScalar* r = nullptr;
    PetscInt lo = 0, hi = 0;
    SB_CHECK(VecGetOwnershipRange(rhs, &lo, &hi));
    SB_CHECK(VecGetArray(rhs, &r));
    for (PetscInt row : model_.prescribed_rows()) r[row - lo] = 0.0;
    SB_CHECK(VecRestoreArray(rhs, &r));
  }
  SB_CHECK(KSPSolve(ksp, rhs, y));
  KSPConvergedReason reason;
  SB_CHECK(KSPGetConvergedReason(ksp, &reason));
  PetscReal ynorm = 0.0;
  SB_CHECK(VecNorm(y, NORM_INFINITY, &ynorm));
  VelocityProjection& p = projection_;
  p.solved = true;
  PetscScalar vMv = 0.0;
  SB_CHECK(MatMult(M_, v_, Mv));
  SB_CHECK(VecDot(v_, Mv, &vMv));
  p.size = std::sqrt(std::max(0.0, vMv));
  p.kinetic_before = p.kinetic_after = 0.5 * vMv;
  if (reason < 0 || !std::isfinite(ynorm)) {
    p.failed = true;
    return;
  }
  SB_CHECK(VecPointwiseMult(sdot_, y, model_.sliding_mask()));
  SB_CHECK(VecPointwiseMult(y, y, model_.coordinate_mask()));
  SB_CHECK(VecWAXPY(dv, -1.0, v_, y));
  PetscScalar dMd = 0.0, yMy = 0.0;
  SB_CHECK(MatMult(M_, dv, Mv));
  SB_CHECK(VecDot(dv, Mv, &dMd));
  SB_CHECK(MatMult(M_, y, Mv));
  SB_CHECK(VecDot(y, Mv, &yMy));
  PetscReal largest = 0.0;
  SB_CHECK(VecNorm(dv, NORM_INFINITY, &largest));
  p.change = std::sqrt(std::max(0.0, dMd));
  p.largest = largest;
  // a consistent velocity comes back changed by roundoff only: keep it as given
  if (p.change <= 1e-10 * p.size) return;
  p.projected = true;
  p.kinetic_after = 0.5 * yMy;
  SB_CHECK(VecCopy(y, v_));
}

/// Newmark and HHT need a_0. M is singular on d1 (and on multipliers), so a_0 and the initial
/// multipliers come from the constrained system at t_0:
///   [ M  G^T ] [a_0]      [ -(f_int - f_ext)(q_0) ]
///   [ G   0  ] [lam_0] =  [ -w^T Phi'' w          ]
/// with w = (v, sdot). The curvature term is the second difference of the constraint rows,
/// Phi(q + e w) + Phi(q - e w) - 2 Phi(q) = e^2 w^T Phi'' w + e^4 c: exact with e = 1 for the
/// quadratic (or linear) constraints in q. With sliding rates the frame-projected joint is quartic
/// (N(s) quadratic in s within a span times the bilinear e_i . x_A): e = 1e-3 keeps s within a
/// span, and Richardson's (4 D(e/2) - D(e)) / 3 removes the e^2 c term exactly.
void TimeIntegrator::consistent_acceleration(KSP ksp) {
  Vec mask = model_.coordinate_mask();
  Vec xz = xt_, f0 = w_, fp = f_hist_, rhs = work_, wv = a_;  // scratch (the step recomputes them)
  SB_CHECK(VecPointwiseMult(xz, x_, state_mask_));   // multipliers 0, sliding coordinates kept
  const StepEval ev{StepRule::Endpoint, clock_.time(), 1.0};
  SB_CHECK(model_.assemble_effects_residual(ev, xz, f0));
  SB_CHECK(VecPointwiseMult(rhs, f0, mask));
  SB_CHECK(VecScale(rhs, -1.0));
  // constraint rows: -(F(x+w) + F(x-w) - 2 F(x)), with rhs = -f0 on coordinate rows kept
  PetscReal rate = 0.0;
  SB_CHECK(VecNorm(sdot_, NORM_INFINITY, &rate));
  Vec curv = x1_, second = nullptr;
  SB_CHECK(VecDuplicate(x_, &second));
  const std::vector<double> eps = rate > 0.0 ? std::vector<double>{1e-3, 0.5e-3} : std::vector<double>{1.0};
  for (size_t k = 0; k < eps.size(); ++k) {
    Vec d = k == 0 ? curv : second;
    SB_CHECK(VecWAXPY(wv, 1.0, v_, sdot_));
    SB_CHECK(VecAYPX(wv, eps[k], xz));  // x + e w
    SB_CHECK(model_.assemble_effects_residual(ev, wv, fp));
    SB_CHECK(VecCopy(fp, d));
    SB_CHECK(VecWAXPY(wv, 1.0, v_, sdot_));
    SB_CHECK(VecAYPX(wv, -eps[k], xz));  // x - e w
    SB_CHECK(model_.assemble_effects_residual(ev, wv, fp));
    SB_CHECK(VecAXPY(d, 1.0, fp));
    SB_CHECK(VecAXPY(d, -2.0, f0));
    SB_CHECK(VecScale(d, 1.0 / (eps[k] * eps[k])));
  }
  if (eps.size() == 2) SB_CHECK(VecAXPBY(curv, 4.0 / 3.0, -1.0 / 3.0, second));
  SB_CHECK(VecDestroy(&second));
  {
    PetscScalar *r = nullptr, *c = nullptr;
    const PetscScalar* mk = nullptr;
    PetscInt lo = 0, hi = 0;
    SB_CHECK(VecGetOwnershipRange(rhs, &lo, &hi));
    SB_CHECK(VecGetArray(rhs, &r));
    SB_CHECK(VecGetArray(curv, &c));
    SB_CHECK(VecGetArrayRead(mask, &mk));
    for (PetscInt i = 0; i < hi - lo; ++i)
      if (mk[i] == 0.0) r[i] = -c[i];
    for (PetscInt row : model_.prescribed_rows()) r[row - lo] = 0.0;
    SB_CHECK(VecRestoreArrayRead(mask, &mk));
    SB_CHECK(VecRestoreArray(curv, &c));
    SB_CHECK(VecRestoreArray(rhs, &r));
  }
  Vec y = x1_;
  SB_CHECK(KSPSolve(ksp, rhs, y));
  KSPConvergedReason reason;
  SB_CHECK(KSPGetConvergedReason(ksp, &reason));
  if (reason < 0)
    throw SolverFailure(std::string("initial acceleration: the constrained mass system could not be solved (") +
                        KSPConvergedReasons[reason] + "); is every part of the structure given mass?");
  SB_CHECK(VecPointwiseMult(a_, y, mask));
  // x_ = state_mask * x_ + (1 - state_mask) * y: the consistent initial multipliers (y holds the
  // sliding coordinates' second derivatives at their rows: dropped)
  SB_CHECK(VecPointwiseMult(w_, y, state_mask_));
  SB_CHECK(VecAXPY(y, -1.0, w_));      // y: multipliers only
  SB_CHECK(VecPointwiseMult(x_, x_, state_mask_));
  SB_CHECK(VecAXPY(x_, 1.0, y));
  model_.apply_prescribed(x_);
}

void TimeIntegrator::prepare_step(double h) {
  h_ = h;
  model_.set_prescribed_time(next_time(h));  // driven supports at the step's end
  SB_CHECK(model_.set_step_start(x_));
  if (v_start_) {  // copies: reactions and records of the step read them after v_ and a_ moved on
    SB_CHECK(VecCopy(v_, v_start_));
    SB_CHECK(VecCopy(a_, a_start_));
    SB_CHECK(model_.set_step_rates(v_start_, a_start_, params_.beta, params_.gamma));
  }
  SB_CHECK(VecWAXPY(xt_, h, v_, x_));
  scale_ = 1.0;
  has_history_force_ = false;
  if (is_midpoint_type(params_.kind)) {
    c0_ = 2.0 / (h * h);
  } else {
    c0_ = 1.0 / (params_.beta * h * h);
    SB_CHECK(VecAXPY(xt_, h * h * (0.5 - params_.beta), a_));
    if (params_.kind == IntegratorKind::HHT && params_.alpha != 0.0) {
      // -alpha F(x_n; t_n) on force rows: coordinates and sliding coordinates (whose row,
      // G_s . mu = 0, is the force balance of a massless coordinate and must be averaged like
      // the others, or the joint does work); constraint rows hold at t_{n+1} only
      scale_ = 1.0 + params_.alpha;
      has_history_force_ = true;
      SB_CHECK(model_.assemble_effects_residual(StepEval{StepRule::Endpoint, clock_.time(), 1.0}, x_, f_hist_));
      SB_CHECK(VecPointwiseMult(f_hist_, f_hist_, state_mask_));
      SB_CHECK(VecScale(f_hist_, -params_.alpha));
    }
  }
  if (condensation_) condensation_->set_force_state(x_, step_eval().theta, scale_);
  if (blocks_ && blocks_->update()) blocks_->update()->set_force_state(x_, step_eval().theta, scale_);
}

PetscErrorCode TimeIntegrator::step_forces(Vec x1, Vec F) { return step_forces(x1, F, step_eval()); }

PetscErrorCode TimeIntegrator::step_forces(Vec x1, Vec F, const StepEval& eval) {
  PetscFunctionBeginUser;
  PetscCall(model_.assemble_effects_residual(eval, x1, F));
  if (scale_ != 1.0) PetscCall(VecScale(F, scale_));
  PetscCall(VecWAXPY(w_, -1.0, xt_, x1));
  PetscCall(VecScale(w_, c0_));
  PetscCall(MatMultAdd(M_, w_, F, F));
  if (has_history_force_) PetscCall(VecAXPY(F, 1.0, f_hist_));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::step_residual(Vec x1, Vec F) {
  PetscFunctionBeginUser;
  PetscCall(step_forces(x1, F));
  PetscCall(model_.set_prescribed_residual_rows(x1, F));
  PetscFunctionReturn(0);
}

void TimeIntegrator::last_step_residual(Vec F) {
  if (!stepped_) throw std::logic_error("no time step taken since the start (or a restart): no step residual yet");
  SB_CHECK(model_.set_step_start(x_start_));  // as in reactions()
  SB_CHECK(step_forces(x_, F, last_eval_));
  SB_CHECK(model_.set_prescribed_residual_rows(x_, F));
  SB_CHECK(model_.set_step_start(x_));  // the next step's start again (a prepared step reads it)
}

std::vector<std::pair<int, Reaction>> TimeIntegrator::reactions() {
  // the last step's context (prepare_step) with its start state again: x_, which the model
  // references as the step start, holds the step's end now
  SB_CHECK(model_.set_step_start(x_start_));
  Vec F = nullptr;
  SB_CHECK(VecDuplicate(x_, &F));
  // the last step's own times: step_eval() has moved on to the next step with the clock
  const StepEval eval = stepped_ ? last_eval_ : step_eval();
  SB_CHECK(step_forces(x_, F, eval));
  auto r = model_.reactions(eval, x_, F, scale_);
  SB_CHECK(VecDestroy(&F));
  SB_CHECK(model_.set_step_start(x_));  // the next step's start again (a prepared step reads it)
  return r;
}

std::vector<double> TimeIntegrator::effect_outputs() {
  if (stepped_) {
    SB_CHECK(model_.set_step_start(x_start_));  // as in reactions()
    auto v = model_.effect_outputs(last_eval_, x_);
    SB_CHECK(model_.set_step_start(x_));
    return v;
  }
  const double t = clock_.time();
  SB_CHECK(VecWAXPY(work_, -1.0, sdot_, x_));  // the start of a unit step at the rates sdot_
  SB_CHECK(model_.set_step_start(work_));
  StepEval ev{StepRule::Endpoint, t, 1.0};
  ev.t_start = t - 1.0, ev.t_end = t, ev.h = 1.0;
  auto v = model_.effect_outputs(ev, x_);
  SB_CHECK(model_.set_step_start(x_));
  return v;
}

PetscErrorCode TimeIntegrator::step_jacobian(Vec x1, Mat J) {
  PetscFunctionBeginUser;
  if (J == J_) {  // fast path: one COO pass with the mass terms
    PetscCall(model_.assemble_effects_jacobian(step_eval(), x1, J, &coo_, scale_, c0_));
  } else {
    PetscCall(model_.assemble_effects_jacobian(step_eval(), x1, J, nullptr, scale_));
    PetscCall(MatAXPY(J, c0_, M_, SUBSET_NONZERO_PATTERN));
  }
  PetscCall(model_.set_prescribed_jacobian_rows(J));
  PetscFunctionReturn(0);
}

PetscErrorCode TimeIntegrator::form_function(SNES, Vec x, Vec F, void* ctx) {
  return static_cast<TimeIntegrator*>(ctx)->step_residual(x, F);
}

PetscErrorCode TimeIntegrator::form_jacobian(SNES snes, Vec x, Mat J, Mat, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<TimeIntegrator*>(ctx);
  PetscCall(self->step_jacobian(x, J));
  const int seen = self->pattern_seen_;
  PetscCall(reset_factorization_on_pattern_change(snes, self->coo_.generation(), &self->pattern_seen_));
  if (self->blocks_) PetscCall(self->blocks_->prepare(J, seen != self->pattern_seen_));
  PetscCall(SNESGetIterationNumber(snes, &self->jac_iter_));
  self->jac_solve_ = self->solve_count_;
  self->jac_c0_ = self->c0_;
  ++self->jac_evals_;
  // the line search may shorten this Jacobian's steps (not an old one's)
  if (DirectorCondensation* c = self->manifold_line_search()) c->jacobian_rebuilt();
  PetscFunctionReturn(0);
}

/// The roundoff-aware test of static solves, plus modified-Newton control: an iteration made
/// with an old Jacobian that reduced |F| by less than the reuse rate asks SNES for a fresh
/// Jacobian at the next iteration, unless |F| is already below 1e-8 of the initial residual
/// (the roundoff floor's zone); stagnation counts as convergence below 1e-6 of the initial
/// residual with a fresh Jacobian, below 1e-8 with an old one.
namespace {
// |F| within this factor of the floor measured on earlier steps counts as converged (the floor
// wanders by about 1.5x from step to step; 2x let the drift of the pendulum's energy grow 20x).
constexpr double kFloorMargin = 3.0;
// ... if the part of |F| that is not roundoff, estimated from the contraction so far, is below this
// share of the floor
constexpr double kFloorShare = 0.1;
// Steps between measurements of the floor (such a step runs on to stagnation).
constexpr int kFloorRemeasure = 8;
}  // namespace

double TimeIntegrator::rounding_level(SNES snes) {
  if (level_jacobian_ != jac_evals_) {  // |J| |x| changes little while one Jacobian serves
    SB_CHECK(test_.rounding_level(snes, &level_));
    level_jacobian_ = jac_evals_;
  }
  return level_;
}

PetscErrorCode TimeIntegrator::converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                         SNESConvergedReason* reason, void* ctx) {
  PetscFunctionBeginUser;
  auto* self = static_cast<TimeIntegrator*>(ctx);
  RoundoffTest& rt = self->test_;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (it == 1) rt.xnorm1 = xnorm;
  if (it == 0) {
    rt.fnorm0 = rt.fnorm_prev = fnorm;
    self->rate_prev_ = 1.0;
    PetscFunctionReturn(0);
  }
  if (*reason == SNES_CONVERGED_ITERATING) {
    const bool fresh = !self->reuse_ || (self->jac_solve_ == self->solve_count_ && self->jac_iter_ == it - 1);
    const double rate = fnorm / rt.fnorm_prev;
    // At roundoff the residual stagnates whatever the Jacobian: with a fresh one below 1e-6 of
    // the initial residual, with an old one (slower contraction) below 1e-8.
    // Small steps scale the residual by c0 M ~ 1/h^2, which lifts its roundoff floor above any
    // fixed fraction of the initial residual: a Newton step at 1e-9 of the state is roundoff too.
    const bool stagnates = it > 1 && rate >= 0.5;
    // below this fraction of the initial residual an old Jacobian's iterate may be at roundoff
    constexpr double kOldJacobianFloor = 1e-8;
    const double relative_floor = (fresh ? 1e-6 : kOldJacobianFloor) * rt.fnorm0;
    if (stagnates && ((fnorm <= relative_floor && snorm <= 1e-7 * xnorm) || snorm <= 1e-9 * xnorm)) {
      PetscCall(PetscInfo(snes, "Converged at roundoff: ||F|| %g stagnates (initial %g)\n", (double)fnorm,
                          (double)rt.fnorm0));
      *reason = SNES_CONVERGED_FNORM_RELATIVE;
      self->floor_sample_ = fnorm;
    } else if (stagnates && fnorm > relative_floor && !rt.ran_away(xnorm, fnorm) &&
               self->rounding_level(snes) > 1e-6 * rt.fnorm0 && fnorm <= self->rounding_level(snes)) {
      // (at small steps the residual's own roundoff, c0 M |x| eps, lies above the fraction of a
      // large initial residual that the test above asks for even of a fresh Jacobian, and the
      // multipliers' noise keeps the Newton step above 1e-9: a fresh Jacobian would only confirm
      // the floor. Not so for an iterate that ran away: its |x|, and with it the roundoff level,
      // grow without bound, and |F| with them)
      PetscCall(PetscInfo(snes, "Converged at roundoff: ||F|| %g stagnates at eps || |J| |x| ||\n", (double)fnorm));
      *reason = SNES_CONVERGED_FNORM_ABS;
      self->floor_sample_ = fnorm;
    } else if (self->use_floor_ && fnorm <= kFloorMargin * self->floor_ && snorm <= 1e-7 * xnorm &&
               rt.fnorm_prev * self->rate_prev_ <= kFloorShare * self->floor_) {
      // (|F| at the floor is mostly roundoff; what the iterate still lacks is about the previous
      // |F| times the previous contraction, and that must be well below the floor too)
      PetscCall(PetscInfo(snes, "Converged at roundoff: ||F|| %g within %g of the floor %g measured before\n",
                          (double)fnorm, kFloorMargin, self->floor_));
      *reason = SNES_CONVERGED_FNORM_RELATIVE;
    } else if (!fresh && rate > self->reuse_rate_ && fnorm > kOldJacobianFloor * rt.fnorm0) {
      // (Below that fraction of the initial residual a weak contraction is mostly the roundoff floor:
      // the old Jacobian goes on, and the stagnation test above ends the step. Rebuilding there
      // was half of all rebuilds on the stiff pendulum, each only confirming the floor.)
      PetscCall(PetscInfo(snes, "Old Jacobian reduced |F| by only %g: rebuilding it%s\n", rate,
                          self->full_newton_after_rebuild_ ? " (full Newton for this step)" : ""));
      PetscCall(SNESSetLagJacobian(snes, self->full_newton_after_rebuild_ ? 1 : -2));
    } else if (fresh && self->reuse_ && rate > 1.0) {
      // Far from the solution, reusing even a fresh Jacobian can diverge: full Newton for the
      // rest of this step.
      PetscCall(PetscInfo(snes, "|F| grew by %g with a fresh Jacobian: full Newton for this step\n", rate));
      PetscCall(SNESSetLagJacobian(snes, 1));
    }
  }
  self->rate_prev_ = fnorm / std::max(rt.fnorm_prev, 1e-300);
  rt.fnorm_prev = fnorm;
  PetscFunctionReturn(0);
}

SolveResult TimeIntegrator::step(double h) {
  SB_CHECK(PetscLogEventBegin(ev_step_, 0, 0, 0, 0));
  // After a fall-back, the fast LU again once the pivoting one has taken 1, 2, 4, ... 64 steps
  // (doubling while the fast one keeps failing at once: the seed's strains on the full system
  // meet their zero pivot at every step).
  if (fell_back_ && pivoted_since_ >= (1L << std::min(fast_failures_ - 1, 6))) {
    SB_CHECK(PetscInfo(snes_, "Back to the fast solve after %ld steps on the pivoting LU\n", pivoted_since_));
    if (block_path_) attach_block_path();
    else attach_fast_lu();
    fell_back_ = false;
  }
  if (auto_reuse_) choose_newton();
  prepare_step(h);
  ++solve_count_;
  // The floor scales with the step size (c0 M ~ 1/h^2 in F): a measurement holds for one size.
  if (h != floor_h_) floor_ = 0.0, floor_count_ = 0;
  use_floor_ = floor_stop_ && floor_ > 0.0 && ++floor_age_ % kFloorRemeasure != 0;
  floor_sample_ = 0.0;
  // Reuse the last Jacobian (lag -1) unless the step size changed (c0 M is part of it) or the
  // last step failed; then build a fresh one first (lag -2).
  if (reuse_) SB_CHECK(SNESSetLagJacobian(snes_, (jac_solve_ < 0 || c0_ != jac_c0_ || last_failed_) ? -2 : -1));
  SolveResult r;
  const int jac_before = jac_evals_;
  bool tried_full_newton = !reuse_;
  bool tried_backtracking = !backtrack_retry_ || !manifold_line_search();
  for (int attempt = 0;; ++attempt) {
    // After a failure, from the same predictor: first full Newton whose line search halves the
    // steps that make |F| grow (on the manifold), then a pivoting LU (if the fast one was in
    // use), then full Newton (if old Jacobians were in use); then give up (the caller cuts dt).
    // Backtracking only on a retry: a converging step's first iterate often grows |F| a
    // hundredfold on stiff terms and then converges quadratically (the rail at dt = 0.1), and a
    // shortened step there fails. Not after a linear solve that failed on the predictor's
    // Jacobian (a zero pivot there is the pivoting LU's to retry); after one that failed on a
    // later iterate, yes: Newton diverged into a singular matrix (D3 at dt = 0.25).
    if (attempt > 0) {
      if (!tried_backtracking && (r.reason != SNES_DIVERGED_LINEAR_SOLVE || r.iterations > 1)) {
        set_backtracking(true);
        tried_backtracking = true;
        if (reuse_) SB_CHECK(SNESSetLagJacobian(snes_, 1));
        tried_full_newton = true;
      } else if (fast_lu_ || blocks_) {
        fell_back_ = true;
        ++fast_failures_;
        pivoted_since_ = 0;
        use_pivoting_lu();
      } else if (!tried_full_newton) {
        SB_CHECK(SNESSetLagJacobian(snes_, 1));
        tried_full_newton = true;
      } else {
        break;
      }
    }
    // Predictor: x_n + h v_n + h^2/2 a_n, multipliers of t_n; midpoint-type schemes estimate
    // a_n = (v_n - v_{n-1}) / h_{n-1}. Saves about one Newton iteration per step.
    SB_CHECK(VecWAXPY(x1_, h, v_, x_));
    if (!is_midpoint_type(params_.kind)) SB_CHECK(VecAXPY(x1_, 0.5 * h * h, a_));
    else if (h_prev_ > 0) SB_CHECK(VecAXPBYPCZ(x1_, 0.5 * h * h / h_prev_, -0.5 * h * h / h_prev_, 1.0, v_, v_prev_));
    if (model_.has_sliding_state()) SB_CHECK(VecAXPY(x1_, h, sdot_));  // s: linear extrapolation
    model_.apply_prescribed(x1_);
    if (condensation_) SB_CHECK(condensation_->project(x1_));  // Newton stays on the manifold
    if (blocks_ && blocks_->update()) SB_CHECK(blocks_->update()->project(x1_));
    SB_CHECK(SNESSolve(snes_, nullptr, x1_));
    const int its_before = r.iterations;
    r = solve_result(snes_);
    r.iterations += its_before;
    PetscReal norm = 0;
    SB_CHECK(VecNorm(x1_, NORM_2, &norm));
    if (r.converged() && !std::isfinite(norm)) r.reason = SNES_DIVERGED_FNORM_NAN;
    if (r.converged()) break;
  }
  if (backtrack_retry_) set_backtracking(false);
  last_failed_ = !r.converged();
  if (auto_reuse_) {
    ++choice_.steps;
    choice_.cost += r.iterations + kJacobianCost * (jac_evals_ - jac_before);
  }
  if (r.converged() && fell_back_) ++pivoting_steps_, ++pivoted_since_;
  if (r.converged() && (fast_lu_ || blocks_)) fast_failures_ = 0;
  if (r.converged() && floor_sample_ > 0.0) {
    floor_samples_[floor_count_++ % kFloorSamples] = floor_sample_;
    const int n = std::min(floor_count_, kFloorSamples);
    floor_ = 0.0;
    for (int k = 0; k < n; ++k) floor_ += floor_samples_[k] / n;
    floor_h_ = h;
    floor_age_ = 0;
  }
  if (r.converged()) {
    // The effects' history (friction's anchors) moves to the step's end, which the energies
    // there read; the energies of the step's start read the history as it was.
    if (model_.has_effect_history()) {
      remember_start_energies();
      model_.commit_effect_history(step_eval(), x1_);
    }
    account_energy_flows();
    Vec mask = model_.coordinate_mask();
    SB_CHECK(VecCopy(v_, v_prev_));
    last_eval_ = step_eval();  // (before the time segment moves on)
    const double t_next = next_time(h);
    h_prev_ = h;
    if (is_midpoint_type(params_.kind)) {
      // v_{n+1} = 2 (q_{n+1} - q_n) / h - v_n
      SB_CHECK(VecAXPBYPCZ(v_, 2.0 / h, -2.0 / h, -1.0, x1_, x_));
      SB_CHECK(VecPointwiseMult(v_, v_, mask));
    } else {
      // a_{n+1} = c0 (x_{n+1} - x~),  v_{n+1} = v_n + h ((1 - gamma) a_n + gamma a_{n+1})
      SB_CHECK(VecWAXPY(w_, -1.0, xt_, x1_));
      SB_CHECK(VecPointwiseMult(w_, w_, mask));
      SB_CHECK(VecScale(w_, c0_));
      SB_CHECK(VecAXPBYPCZ(v_, h * (1.0 - params_.gamma), h * params_.gamma, 1.0, a_, w_));
      SB_CHECK(VecCopy(w_, a_));
    }
    if (model_.has_sliding_state()) {
      SB_CHECK(VecWAXPY(sdot_, -1.0, x_, x1_));
      SB_CHECK(VecPointwiseMult(sdot_, sdot_, model_.sliding_mask()));
      SB_CHECK(VecScale(sdot_, 1.0 / h));
    }
    SB_CHECK(VecCopy(x_, x_start_));
    SB_CHECK(VecCopy(x1_, x_));
    stepped_ = true;
    clock_.advance(h, t_next);
  }
  SB_CHECK(PetscLogEventEnd(ev_step_, 0, 0, 0, 0));
  return r;
}

DirectorCondensation* TimeIntegrator::manifold_line_search() const {
  if (condensation_) return condensation_.get();
  return blocks_ ? blocks_->update() : nullptr;
}

void TimeIntegrator::set_backtracking(bool on) {
  if (DirectorCondensation* c = manifold_line_search()) c->set_backtrack(on);
}

void TimeIntegrator::reset_newton_choice() {
  choice_ = NewtonChoice{};
  set_reuse(true);
}

void TimeIntegrator::set_reuse(bool on) {
  reuse_ = on ? PETSC_TRUE : PETSC_FALSE;
  jac_solve_ = -1;  // a fresh Jacobian at the next step either way
  SB_CHECK(SNESSetLagJacobian(snes_, on ? -2 : 1));
}

void TimeIntegrator::choose_newton() {
  NewtonChoice& c = choice_;
  if (c.steps < c.budget) return;
  (reuse_ ? c.reuse_cost : c.full_cost) = c.cost / std::max(1L, c.steps);
  bool reuse = reuse_ == PETSC_TRUE;
  if (!c.probing || c.reuse_cost < 0.0 || c.full_cost < 0.0) {
    // a period is over, or the other variant has no measurement yet: measure it, briefly
    reuse = !reuse;
    c.probing = true;
    c.budget = reuse ? kReuseWindow : kFullNewtonWindow;
  } else {
    // both measured: the cheaper one runs for a period
    reuse = c.reuse_cost <= c.full_cost;
    c.probing = false;
    c.budget = kChoicePeriod;
  }
  c.steps = 0;
  c.cost = 0.0;
  if (reuse != (reuse_ == PETSC_TRUE)) {
    SB_CHECK(PetscInfo(snes_, "Newton cost per step: modified %g, full %g (iterations + %g per Jacobian): %s\n",
                       c.reuse_cost, c.full_cost, kJacobianCost, reuse ? "modified Newton" : "full Newton"));
    set_reuse(reuse);
  }
}

void TimeIntegrator::restore(double t, double h_prev, bool pivoting_lu, double segment_start, long segment_steps) {
  clock_.restore(t, h_prev, segment_start, segment_steps);
  model_.set_prescribed_time(t);
  h_prev_ = h_prev;
  timed_energy_.clear();
  last_failed_ = false;
  stepped_ = false;
  jac_solve_ = -1;  // build a fresh Jacobian at the next step
  if (auto_reuse_) reset_newton_choice();
  if (pivoting_lu && (fast_lu_ || blocks_)) {  // as after a fall-back: the fast solve again after a step
    fell_back_ = true;
    fast_failures_ = 1;
    pivoted_since_ = 0;
    use_pivoting_lu();
  }
}

void TimeIntegrator::attach_fast_lu() {
  PC pc = nullptr;
  SB_CHECK(reset_snes_pc(snes_));
  SB_CHECK(set_preonly(snes_, PCLU, &pc));
  SB_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERPETSC));
  // The model's elimination order: the natural order with every multiplier next to the
  // coordinates it constrains, sliders before their carriers (Model::elimination_order).
  const std::vector<PetscInt>& order = model_.elimination_order();
  SB_CHECK(attach_elimination_order(J_, order));
  SB_CHECK(PCFactorSetMatOrderingType(pc, kModelOrdering));
  fast_lu_ = true;
  if (parked_condensation_) {  // the return after a fall-back
    condensation_ = std::move(parked_condensation_);
    SB_CHECK(condensation_->reattach(snes_));
  } else if (condensation_) {  // the first time
    SB_CHECK(condensation_->attach(snes_));
  }
  if (!condensation_) {  // the plain Newton update on the full system
    SNESLineSearch ls = nullptr;
    SB_CHECK(SNESGetLineSearch(snes_, &ls));
    SB_CHECK(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  }
  if (reuse_) SB_CHECK(SNESSetLagJacobian(snes_, -2));  // factor the current Jacobian anew
}

void TimeIntegrator::attach_block_path() {
  // as the constructor built it, its options included (the pivoting LU's PC is replaced)
  blocks_ = std::make_unique<BlockSolvePath>(model_, snes_, J_, kStepPrefix);
  KSP ksp = nullptr;
  SB_CHECK(SNESGetKSP(snes_, &ksp));
  SB_CHECK(KSPSetFromOptions(ksp));
  if (reuse_) SB_CHECK(SNESSetLagJacobian(snes_, -2));  // factor the current Jacobian anew
}

void TimeIntegrator::use_pivoting_lu() {
  KSP ksp = nullptr;
  PC pc = nullptr;
  SB_CHECK(SNESGetKSP(snes_, &ksp));
  SB_CHECK(KSPGetPC(ksp, &pc));
  int size = 1;
  MPI_Comm_size(model_.comm(), &size);
  SB_CHECK(PetscInfo(snes_, "Step failed with the non-pivoting LU or the Schwarz preconditioner: a pivoting direct "
                            "LU (SuperLU, MUMPS in parallel) from now on\n"));
  if (blocks_) {
    SB_CHECK(blocks_->detach());
    solves_before_ = parallel_solves();
  }
  SB_CHECK(PCReset(pc));
  SB_CHECK(KSPSetType(ksp, KSPPREONLY));
  SB_CHECK(PCSetType(pc, PCLU));
  if (condensation_) {  // the full saddle-point system and plain Newton updates until the return
    SNESLineSearch ls = nullptr;
    SB_CHECK(SNESGetLineSearch(snes_, &ls));
    SB_CHECK(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
    parked_condensation_ = std::move(condensation_);  // until the return (attach_fast_lu)
  }
  SB_CHECK(PCFactorSetMatSolverType(pc, size == 1 ? MATSOLVERSUPERLU : MATSOLVERMUMPS));
  if (size == 1) SB_CHECK(PCFactorSetMatOrderingType(pc, MATORDERINGND));
  fast_lu_ = false;
  blocks_.reset();
  if (reuse_) SB_CHECK(SNESSetLagJacobian(snes_, -2));  // factor the current Jacobian anew
}

TimeIntegrator::Motion TimeIntegrator::motion() const {
  SB_CHECK(MatMult(M_, v_, work_));
  SB_CHECK(model_.add_configuration_momentum(x_, v_, work_));  // the fluid's added mass
  PetscScalar e = 0;
  SB_CHECK(VecDot(v_, work_, &e));
  return Motion{0.5 * e, model_.momenta(x_, work_)};
}

double TimeIntegrator::constraint_residual() const {
  SB_CHECK(model_.assemble_effects_residual(StepEval{StepRule::Endpoint, clock_.time(), 1.0}, x_, work_));
  const PetscScalar *f = nullptr, *mk = nullptr;
  PetscInt n = 0;
  SB_CHECK(VecGetLocalSize(work_, &n));
  SB_CHECK(VecGetArrayRead(work_, &f));
  SB_CHECK(VecGetArrayRead(state_mask_, &mk));
  double m = 0.0;
  for (PetscInt i = 0; i < n; ++i)  // multiplier rows: the constraints
    if (mk[i] == 0.0) m = std::max(m, std::abs(f[i]));
  SB_CHECK(VecRestoreArrayRead(state_mask_, &mk));
  SB_CHECK(VecRestoreArrayRead(work_, &f));
  MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, model_.comm());
  return m;
}

}  // namespace slidebeam
