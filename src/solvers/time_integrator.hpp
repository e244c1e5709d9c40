// SPDX-License-Identifier: MIT
#pragma once
/// @file One-step time integrators for the constrained beam dynamics (docs/theory.md, "Time integration"):
/// energy-momentum, implicit midpoint, Newmark and HHT-alpha (index 3). Each step is one SNES
/// Newton solve for x_{n+1} = (q, multipliers); the velocity is eliminated:
///
///   R(x1) = M c0 (x1 - x~) + s F(x1; rule, t*) + f_hist = 0
///
///   midpoint / EM:  c0 = 2/h^2,        x~ = x_n + h v_n,                     rule Theta(1/2) / EM, t* = t_n + h/2
///   Newmark/HHT:    c0 = 1/(beta h^2), x~ = x_n + h v_n + h^2 (1/2 - beta) a_n, rule Endpoint,   t* = t_{n+1}
///                   s = 1 + alpha, f_hist = -alpha F(x_n; t_n) on coordinate rows (0 for Newmark)
///
/// M is the constant mass matrix; it has no entries on multipliers, so constraint rows are the
/// effects' constraints at x_{n+1}.
///
/// Newton: full Newton by default (a fresh Jacobian and LU every iteration). Modified Newton
/// (-sb_jacobian_reuse, or sb_jacobian_reuse = true in a scene's [petsc] table) keeps the
/// Jacobian and its LU factors across iterations and steps (SNES lag -1). A fresh one is built
/// first when the step size changed or the last step failed, and when an iteration with an old
/// Jacobian reduced |F| by less than -sb_jacobian_reuse_rate (0.2); -sb_full_newton_after_rebuild
/// then finishes the step with full Newton. A step whose |F| grows even with a fresh Jacobian
/// turns to full Newton, and a failed step is retried once with full Newton from the predictor.
/// The converged solution is the same; only the path to it changes. Measured: modified Newton
/// pays on small steps of stiff beams (pendulum, dt = 1e-3: 2.3x faster) and loses on large
/// steps with large rotations (D3 at dt = 0.25: 4x slower), hence the default.
///
/// Serial steps factor with PETSc's LU in the natural order (no pivoting, multipliers after
/// their coordinates); a failed step is retried on SuperLU (several ranks: the block path and
/// MUMPS), and the steps after it return to the fast solve; see the constructor.
/// With director beams, that LU works on the condensed system of DirectorCondensation (6
/// unknowns per control point instead of 18; -sb_condense_directors false: the full system).

#include "model/model.hpp"
#include "solvers/block_solve_path.hpp"
#include "solvers/director_condensation.hpp"
#include "solvers/newton.hpp"
#include "util/step_clock.hpp"

#include <memory>

#include <string>

namespace slidebeam {

enum class IntegratorKind { EnergyMomentum, Midpoint, Newmark, HHT };

struct IntegratorParams {
  IntegratorKind kind = IntegratorKind::EnergyMomentum;
  double beta = 0.25;   ///< Newmark/HHT
  double gamma = 0.5;   ///< Newmark/HHT
  double alpha = 0.0;   ///< HHT, in [-1/3, 0]
  double dissipation = 0.0;  ///< energy-momentum: xi >= 0 of the energy-decaying variant (0: conserving)
};

IntegratorKind integrator_from(const std::string& name);

class TimeIntegrator {
 public:
  TimeIntegrator(Model& model, const IntegratorParams& params);
  ~TimeIntegrator();
  TimeIntegrator(const TimeIntegrator&) = delete;
  TimeIntegrator& operator=(const TimeIntegrator&) = delete;

  /// Start at time t from x (coordinates, multipliers) and velocity v (multiplier entries are
  /// ignored). A velocity that violates the constraints at velocity level is projected onto them
  /// with the mass metric, and the sliding coordinates' rates follow (velocity_projection()).
  /// Newmark and HHT then solve for a consistent acceleration and initial multipliers.
  void initialize(double t, Vec x, Vec v);

  /// What initialize did to the velocity: v' = argmin 1/2 (v' - v)^T M (v' - v) subject to
  /// G_q(x) v' + G_s(x) sdot = 0 over every constraint (orthonormality, supports, rigid and sliding
  /// joints), the sliding rates sdot free (they have no mass). A change within roundoff of the
  /// given velocity (1e-10 of its mass norm) keeps it as it was; sdot is taken either way.
  struct VelocityProjection {
    bool solved = false;     ///< the projection was computed (a nonzero velocity)
    bool failed = false;     ///< the constrained mass system could not be solved: v kept, sdot = 0
    bool projected = false;  ///< v violated the constraints and was replaced by v'
    double size = 0.0;       ///< sqrt(v^T M v) of the given velocity
    double change = 0.0;     ///< sqrt(dv^T M dv), dv = v' - v
    double largest = 0.0;    ///< max |dv_i| over the coordinates
    double kinetic_before = 0.0, kinetic_after = 0.0;
  };
  const VelocityProjection& velocity_projection() const { return projection_; }

  /// Advance by h. On failure (Newton did not converge, NaN/Inf) the state stays at t_n.
  SolveResult step(double h);

  /// t_n. Within a run of equal steps it is t_0 + n h (from the segment's start), not a sum of
  /// steps, so that t_end and the output times carry no accumulated roundoff.
  double time() const { return clock_.time(); }
  /// The current segment of equal steps: its start time and the number of steps taken in it
  /// (with h_prev its step size); a checkpoint keeps it so that a restart has the same times.
  std::pair<double, long> time_segment() const { return {clock_.run_start(), clock_.run_steps()}; }
  Vec x() const { return x_; }
  Vec v() const { return v_; }
  Vec a() const { return a_; }
  /// Rate of the sliding coordinates over the last step, (s_n - s_n-1) / h (0 elsewhere).
  Vec sliding_rate() const { return sdot_; }
  /// Memory of the midpoint-type predictor: v_{n-1} and the last step size.
  Vec v_prev() const { return v_prev_; }
  double h_prev() const { return h_prev_; }
  /// True while time steps use the pivoting LU (after a failed step, until the return to the
  /// fast one; or when the user chose a solver).
  bool pivoting_lu() const { return !fast_lu_ && !blocks_; }
  /// Converged steps solved on the pivoting LU after a fall-back, serially or on several ranks
  /// (the steps of a solver the user chose are not counted).
  long pivoting_lu_steps() const { return pivoting_steps_; }
  /// Resume from a checkpoint: x, v, a, v_prev and sliding_rate have been loaded into this
  /// integrator's vectors; set the time, the predictor memory and the linear solver state.
  /// segment_steps > 0 continues a segment of equal steps h_prev that started at segment_start.
  void restore(double t, double h_prev, bool pivoting_lu, double segment_start = 0.0, long segment_steps = 0);
  /// Build a fresh step Jacobian at the next step, as a restart does: a run that writes a
  /// checkpoint then goes on exactly as a restart from it.
  void forget_jacobian() {
    jac_solve_ = -1;
    if (auto_reuse_) reset_newton_choice();
  }
  Mat mass() const { return M_; }
  Mat jacobian() const { return J_; }
  SNES snes() const { return snes_; }
  /// Number of step-Jacobian assemblies so far (each followed by a factorisation).
  int jacobian_evaluations() const { return jac_evals_; }
  /// How the step Jacobians were solved on the Schwarz path (several ranks): how many with one
  /// block application (ranks not coupled), one application plus the coupling correction, and
  /// GMRES; and the most rows of a rank coupled to another rank that any of them had.
  using ParallelSolves = BlockSolvePath::Counts;
  /// Over the whole run: the block path is built anew after each fall-back.
  ParallelSolves parallel_solves() const {
    ParallelSolves c = solves_before_;
    if (blocks_) c += blocks_->counts();
    return c;
  }
  const IntegratorParams& params() const { return params_; }

  /// Kinetic energy 1/2 v^T M v and momenta of a state, from one product p = M v.
  struct Motion {
    double kinetic = 0.0;
    Momenta momenta;
  };
  Motion motion() const;
  /// 1/2 v^T M v of the current state.
  double kinetic_energy() const { return motion().kinetic; }
  /// max |constraint residual| at the current state (orthonormality, supports, joints).
  double constraint_residual() const;

  /// The energy flows since initialize(): per effect whose work is counted (External, Driving,
  /// Dissipative, or time-dependent Stored; EffectRegistry spec), the work it did on the
  /// structure, summed over the steps: W = sum of the non-dissipative ones, D = minus the sum of
  /// the dissipative ones, so that H - H_0 = W - D (exactly under energy-momentum).
  struct EnergyFlow {
    size_t effect;      ///< model effect index
    EnergyRole role;
    double work = 0.0;  ///< work done on the structure (negative: energy taken out)
  };
  const std::vector<EnergyFlow>& energy_flows() const { return flows_; }
  /// Restore the sums (a restart), in the order of energy_flows().
  void set_energy_flows(const std::vector<double>& work);

  /// Set up a step of size h from the current state without solving, so that the step's
  /// residual and Jacobian can be evaluated (finite-difference tests).
  void prepare_step(double h);
  PetscErrorCode step_residual(Vec x1, Vec F);
  /// The residual of the last converged time step at its end state x_n (what that step's SNES
  /// solved for: its norm is the step's residual_norm). Throws before the first step.
  void last_step_residual(Vec F);
  /// Reactions of supports and joints over the last converged step (Model::reactions with the
  /// step's residual, inertia included): what they exert on the structure during the step, so
  /// that with the loads they balance the step's change of momentum. HHT: at t_{n+1}, without
  /// its history term.
  std::vector<std::pair<int, Reaction>> reactions();
  PetscErrorCode step_jacobian(Vec x1, Mat J);
  /// Model::effect_outputs over the last step (its rule, from its start state), rates over it;
  /// before a step since initialize or restore, at t_n with the sliding coordinates' rates
  /// sliding_rate() (the outputs then see one step of unit length ending at t_n).
  std::vector<double> effect_outputs();

 private:
  static PetscErrorCode form_function(SNES, Vec x, Vec F, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec x, Mat J, Mat P, void* ctx);
  static PetscErrorCode converged(SNES, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                  SNESConvergedReason* reason, void* ctx);
  StepEval step_eval() const;
  /// t_{n+1} after a step of size h (see time()).
  double next_time(double h) const { return clock_.next(h); }
  /// The step residual before the prescribed rows are replaced: the effects' forces (HHT: scaled,
  /// with the history term) and the inertia c0 M (x1 - x~).
  PetscErrorCode step_forces(Vec x1, Vec F);
  PetscErrorCode step_forces(Vec x1, Vec F, const StepEval& eval);
  /// Leave the fast solve for a pivoting LU (after a failure with it): SuperLU serially, MUMPS on
  /// several ranks.
  void use_pivoting_lu();
  /// Several ranks: the block path again, as the constructor built it (the return after a
  /// fall-back).
  void attach_block_path();
  /// Serial steps: PETSc's LU without pivoting in the model's elimination order, on the
  /// condensed system where there are director triads (the constructor, and the return after
  /// a fall-back).
  void attach_fast_lu();
  /// The director condensation whose line search keeps the iterates on the manifold (the
  /// serial fast path's, or the block path's update), if any.
  DirectorCondensation* manifold_line_search() const;
  /// Its backtracking (DirectorCondensation::set_backtrack): on for the retry of a failed step.
  void set_backtracking(bool on);
  /// Add the converged step's work of every counted effect to flows_ (x_: start, x1_: end).
  void account_energy_flows();
  /// The timed effects' energies at the step's start, unless kept from the last step.
  void remember_start_energies();
  /// The effects (model indices) of the timed flows, in the order of timed_.
  std::vector<size_t> timed_effects() const;
  /// [M G^T; G 0] at x_ (the effects' tangent with the forces frozen, theta = 0; supports'
  /// rows identity) in J_, and a pivoting LU of it: the caller destroys the KSP.
  KSP constrained_mass_solver();
  void project_velocity(KSP ksp);
  void consistent_acceleration(KSP ksp);
  VelocityProjection projection_;

  Model& model_;
  IntegratorParams params_;
  RoundoffTest test_;
  SNES snes_ = nullptr;
  Mat M_ = nullptr;
  Mat J_ = nullptr;  // the step Jacobian (own matrix: its factors are reused across steps)
  CooAssembly coo_;  // assembly record of J_
  Vec x_ = nullptr, v_ = nullptr, a_ = nullptr;   // state at t_n
  Vec x1_ = nullptr;                              // Newton iterate / solution
  Vec x_start_ = nullptr;                         // start of the last converged step (reactions)
  // the rates at the start of the step being taken or last taken (ConfigurationKinetic effects)
  Vec v_start_ = nullptr, a_start_ = nullptr;
  Vec v_prev_ = nullptr;                          // v_{n-1} (predictor of midpoint-type schemes)
  Vec sdot_ = nullptr;                            // (s_n - s_{n-1}) / h on sliding coordinates
  int pattern_seen_ = 0;                          // CooAssembly generation of the factorisation
  Vec state_mask_ = nullptr;                      // coordinates and sliding coordinates
  double h_prev_ = 0.0;                           // 0: no previous step
  StepEval last_eval_{};  // step_eval() of the last converged step
  bool stepped_ = false;                          // a step since initialize/restore (x_start_ holds its start)
  Vec xt_ = nullptr, w_ = nullptr, f_hist_ = nullptr, work_ = nullptr;
  StepClock clock_;  // t_n
  double h_ = 0.0, c0_ = 0.0, scale_ = 1.0;
  std::vector<EnergyFlow> flows_;
  std::vector<size_t> timed_;        // flows_ entries of time-dependent stored effects
  std::vector<double> timed_energy_; // their energies at (t_n, x_n)
  Vec flow_dq_ = nullptr, flow_r_ = nullptr, flow_r0_ = nullptr;
  bool has_history_force_ = false;
  // modified Newton bookkeeping
  /// Without -sb_jacobian_reuse, modified and full Newton are chosen by their cost per step,
  /// iterations + kJacobianCost per Jacobian (each Jacobian is assembled and factored; on a
  /// 40-span cable one costs 15 iterations, on the pendulum 3). Modified Newton first for
  /// kReuseWindow steps, full Newton for kFullNewtonWindow, then the cheaper for kChoicePeriod,
  /// the other measured again for its window, and so on: a function of the iteration counts
  /// alone, so a run is reproducible (docs/performance.md, "Cables").
  static constexpr double kJacobianCost = 4.0;
  static constexpr long kReuseWindow = 32, kFullNewtonWindow = 16, kChoicePeriod = 128;
  struct NewtonChoice {
    long budget = kReuseWindow;  // steps of the current variant before the next choice
    long steps = 0;              // steps taken in it so far
    double cost = 0.0;           // their cost
    double reuse_cost = -1.0, full_cost = -1.0;  // per step, last measured (-1: not yet)
    bool probing = true;         // the current variant is being measured against the other
  };
  NewtonChoice choice_;
  bool auto_reuse_ = false;
  void reset_newton_choice();
  void choose_newton();
  void set_reuse(bool on);
  PetscBool reuse_ = PETSC_FALSE;
  PetscReal reuse_rate_ = 0.2;
  PetscBool full_newton_after_rebuild_ = PETSC_FALSE;
  int jac_evals_ = 0;
  /// eps || |J| |x| ||, the residual's rounding level, for the Jacobian of evaluation number
  /// level_jacobian_ (computed when a solve stagnates).
  double rounding_level(SNES snes);
  double level_ = 0.0;
  int level_jacobian_ = -1;
  ParallelSolves solves_before_;  // the block path's counts when a pivoting LU took over
  long solve_count_ = 0, jac_solve_ = -1;
  PetscInt jac_iter_ = -1;
  double jac_c0_ = 0.0;
  bool last_failed_ = false;
  // Roundoff floor of |F|: the mean of the last kFloorSamples final |F| of steps that ended in
  // stagnation (0: none yet). Later steps of the same size stop once |F| is within kFloorMargin
  // of it, which saves the iteration that only confirms the floor; every kFloorRemeasure-th
  // step measures it again.
  static constexpr int kFloorSamples = 4;
  double floor_samples_[kFloorSamples] = {};
  double floor_ = 0.0, floor_h_ = 0.0, floor_sample_ = 0.0;
  int floor_age_ = 0, floor_count_ = 0;
  double rate_prev_ = 1.0;  // contraction of the previous Newton iteration
  bool use_floor_ = false;
  PetscBool floor_stop_ = PETSC_FALSE;  // -sb_floor_stop
  std::unique_ptr<DirectorCondensation> condensation_;  // serial fast path with director triads
  std::unique_ptr<DirectorCondensation> parked_condensation_;  // ... while a fall-back runs on the pivoting LU
  std::unique_ptr<BlockSolvePath> blocks_;  // -sb_schwarz: the parallel block solve
  bool fast_lu_ = false;  // serial, non-pivoting PETSc LU in the natural order
  bool backtrack_retry_ = false;  // -sb_backtrack: retry a failed step with backtracking first
  bool fell_back_ = false;   // on the pivoting LU after a failure of the fast solve
  bool block_path_ = false;  // the fast solve is the parallel block path (BlockSolvePath)
  int fast_failures_ = 0;    // consecutive fall-backs without a step on the fast LU between them
  long pivoted_since_ = 0;   // converged steps on the pivoting LU since the last fall-back
  long pivoting_steps_ = 0;  // converged steps on the pivoting LU in all
  PetscLogEvent ev_step_ = 0;
};

}  // namespace slidebeam
