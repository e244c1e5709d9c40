// SPDX-License-Identifier: MIT
#pragma once
/// @file The model: beams, effects, numbering, and assembly of the residual and Jacobian into
/// distributed PETSc objects. Knows nothing about time stepping or Newton.

#include "model/beam.hpp"
#include "model/dof_map.hpp"
#include "model/effect.hpp"
#include "model/partition_policy.hpp"

#include <petscmat.h>
#include <petscvec.h>

#include <array>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace slidebeam {

/// Which rule and load time effects use in one evaluation (see StepRule).
struct StepEval {
  StepRule rule = StepRule::Endpoint;
  double t = 0.0;      ///< load time
  double theta = 1.0;  ///< Theta rule: forces at (1 - theta) x_old + theta x
  double dissipation = 0.0;  ///< EnergyMomentum: xi of the energy-decaying variant
  /// The time step (EvalContext): from t_start to t_end = t_start + h; h = 0 outside steps.
  double t_start = 0.0, t_end = 0.0, h = 0.0;
  StepScheme scheme = StepScheme::Static;
  /// Factor on rate forces (EffectSpec::rate_force) relative to the other effects: HHT scales the
  /// assembled forces by 1 + alpha and its rate forces by 1 / (1 + alpha) here, so that they
  /// count once.
  double rate_weight = 1.0;
  /// An assembly with a mass (mass_scale != 0) adds the ConfigurationKinetic effects' mass at the
  /// state too: the mass system of the initial acceleration.
  bool configuration_mass = false;
};

/// Linear and angular momentum (about the origin) of a state.
struct Momenta {
  std::array<double, 3> linear{};
  std::array<double, 3> angular{};
};

class Model {
 public:
  explicit Model(MPI_Comm comm);
  ~Model();
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;

  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }

  /// Add a beam; returns its index. Only before finalize().
  int add_beam(const BeamSpec& spec);
  /// Create an effect by registered type name; returns its index. Only before finalize().
  int add_effect(const std::string& type, const EffectParams& params);

  /// Number unknowns, distribute effects, build ghost scatter, vectors and the preallocated Jacobian.
  void finalize(const PartitionPolicy& partition = {});
  bool finalized() const { return finalized_; }

  const std::vector<Beam>& beams() const { return beams_; }
  const Beam& beam(int i) const { return beams_.at(static_cast<size_t>(i)); }
  const std::vector<std::unique_ptr<Effect>>& effects() const { return effects_; }
  const DofMap& dof_map() const { return map_; }
  PetscInt n_cp_total() const { return n_cp_total_; }

  /// Global unknowns (coordinates, multipliers, extras), residual vector and Jacobian owned by the model.
  Vec x() const { return x_; }
  Vec residual_vector() const { return r_; }
  Mat jacobian() const { return J_; }
  /// Pattern generation of J_ (see CooAssembly::generation).
  int jacobian_pattern_generation() const { return coo_.generation(); }

  /// Reset x to the reference configuration (multipliers zero, prescribed values applied).
  void set_reference_state(Vec x) const;
  /// Apply prescribed values to x.
  void apply_prescribed(Vec x) const;
  /// Prescribed values at time t (supports that move); without moving supports nothing changes.
  void set_prescribed_time(double t) const;
  /// Replace each control point's director triad by the nearest rotation (polar decomposition).
  /// Used after extrapolating a state: a linear extrapolation of rotating directors errs mostly
  /// off the constraint manifold, and projecting removes that part.
  void project_directors(Vec x) const;
  /// The load-step predictor: x = x_last + alpha (x_last - x_prev) on every unknown but the
  /// director triads, which turn on by alpha times the rotation from x_prev to x_last,
  /// D = exp(alpha log(D_last D_prev^T)) D_last; then the prescribed values. A body turning at a
  /// steady rate is extrapolated exactly, where the linear extrapolation of its directors,
  /// projected back onto rotations, falls short by O(angle^3) (at the roll-up's 18 degrees per
  /// step a tenth of the increment: two Newton iterations more per step).
  void extrapolate(Vec x, Vec x_last, Vec x_prev, double alpha) const;

  /// Assemble the static F(x) at time t (Dirichlet rows: x_i - xbar_i).
  PetscErrorCode assemble_residual(double t, Vec x, Vec F) const;
  /// Assemble the static J(x) at time t (Dirichlet rows: identity).
  PetscErrorCode assemble_jacobian(double t, Vec x, Mat J) const;

  /// Start state x_old of a time step, read by the Theta and EnergyMomentum rules (collective).
  PetscErrorCode set_step_start(Vec x_old);
  /// Some effect's kinetic energy changes with the configuration (ConfigurationKinetic): its
  /// steps read the start's rates (set_step_rates) and momenta count it (add_configuration_momentum).
  bool has_configuration_kinetic() const { return !kinetic_of_.empty(); }
  /// The step start's velocity v and acceleration a (Newmark's beta and gamma), read by
  /// ConfigurationKinetic effects within steps; kept (referenced) until the next call. Nothing
  /// happens without such effects (collective).
  PetscErrorCode set_step_rates(Vec v, Vec a, double beta, double gamma);
  /// p += the ConfigurationKinetic effects' momenta dT/dv at the state (x, v) (collective).
  PetscErrorCode add_configuration_momentum(Vec x, Vec v, Vec p) const;
  /// F = sum of the effects' residuals under a step rule; prescribed rows are NOT overwritten.
  PetscErrorCode assemble_effects_residual(const StepEval& ev, Vec x, Vec F) const;
  /// J = scale * sum of the effects' tangents d F / d x + mass_scale * M (assembled); prescribed
  /// rows NOT overwritten. With coo (the assembly record of J), values go through PETSc's COO
  /// interface; without, through MatSetValues (any J with the model's sparsity pattern).
  PetscErrorCode assemble_effects_jacobian(const StepEval& ev, Vec x, Mat J, CooAssembly* coo = nullptr,
                                           double scale = 1.0, double mass_scale = 0.0) const;
  /// Prescribed rows of F become x_i - xbar_i.
  PetscErrorCode set_prescribed_residual_rows(Vec x, Vec F) const;
  /// Prescribed rows of J become identity rows (columns kept: J stays the exact derivative).
  PetscErrorCode set_prescribed_jacobian_rows(Mat J) const;

  /// True when some effect contributes inertia (a dynamic model).
  bool has_inertia() const { return has_inertia_; }
  /// A beam's translational mass: its own (rho A L) and the point masses on it, from the
  /// inertia effects' mass matrices (the sum of M over its position unknowns of one direction).
  double beam_mass(int beam) const { return beam_mass_.at(static_cast<size_t>(beam)); }
  /// New constant mass matrix with the Jacobian's sparsity pattern (so M and J add cheaply).
  Mat create_mass_matrix() const;
  /// 1 at coordinate unknowns (phi, d_i; ANCF: r, r'), 0 at multipliers and extras.
  Vec coordinate_mask() const { return q_mask_; }
  /// 1 at extras that are state without mass (sliding coordinates), 0 elsewhere.
  Vec sliding_mask() const { return s_mask_; }
  /// True when some effect has state extras (sliding coordinates).
  bool has_sliding_state() const { return has_sliding_state_; }
  /// Values of effect k's extra unknowns at x, on every rank (collective).
  std::vector<double> extra_values(int effect, Vec x) const;
  /// Linear and angular momentum of the state x with momentum vector p = M v (collective).
  Momenta momenta(Vec x, Vec p) const;
  /// Potential energy of each effect at x (collective); same order as effects().
  std::vector<double> effect_energies(double t, Vec x) const;
  /// The energies of the effects `which` only (collective).
  std::vector<double> effect_energies(double t, Vec x, const std::vector<size_t>& which) const;
  /// Reactions of the effects that have one (ReactionSource), as (effect index, reaction),
  /// in the state x under the step rule ev; F_raw: the residual of all effects (and the step's
  /// inertia) before prescribed rows are replaced; scale multiplies the effects' own residuals as
  /// it does theirs in F_raw (HHT's 1 + alpha). Collective.
  std::vector<std::pair<int, Reaction>> reactions(const StepEval& ev, Vec x, Vec F_raw, double scale = 1.0) const;
  /// The residual of effect k alone (collective).
  PetscErrorCode effect_residual(size_t k, const StepEval& ev, Vec x, Vec F) const;
  /// Static: reactions(Endpoint at t, x, the effects' residual at x).
  std::vector<std::pair<int, Reaction>> static_reactions(double t, Vec x) const;

  /// The OutputSource effects' values at x (collective), in effect order and each effect's
  /// order of names; output_names() says whose (effect index) and which. Static (Endpoint at t);
  /// under the rule ev, the step start as set_step_start left it, rates over ev's step.
  std::vector<double> effect_outputs(double t, Vec x) const;
  std::vector<double> effect_outputs(const StepEval& ev, Vec x) const;
  std::vector<std::pair<int, std::string>> output_names() const;

  /// True when some effect keeps a history besides the unknowns (StepHistory).
  bool has_effect_history() const { return !history_.empty(); }
  /// The StepHistory effects' values, concatenated in effect order, as this rank holds them
  /// (its own entries current): what a snapshot keeps.
  std::vector<double> effect_history() const;
  /// The same with every entry from the rank that owns it, on every rank (collective): what a
  /// checkpoint keeps.
  std::vector<double> gathered_effect_history() const;
  /// Replace the values (from effect_history or gathered_effect_history).
  void set_effect_history(const std::vector<double>& values);
  /// Every StepHistory effect's values 0: nothing kept (a run's start).
  void clear_effect_history();
  /// The step under ev from the step start (set_step_start) to x was accepted: every
  /// StepHistory effect commits it (collective).
  void commit_effect_history(const StepEval& ev, Vec x) const;
  /// The history prefix of effect k's outputs (OutputSource::output_prefix; "": its label).
  std::string output_prefix(int k) const;
  /// ExtraUnknowns::bounds of every effect (rows, lo, hi), leaving out the rows in `except`.
  std::tuple<std::vector<PetscInt>, std::vector<double>, std::vector<double>> unknown_bounds(
      const std::vector<PetscInt>& except = {}) const;
  /// ExtraUnknowns::held_at_start of every effect.
  std::vector<PetscInt> held_at_start() const;
  /// EventSource::event_message and event_action of effect k's indicator i.
  std::string event_message(int k, int i, double g, const std::string& when) const;
  bool event_fails_run(int k, int i) const;

  /// Coordinates (n_cp x coordinates_per_cp, row-major) of a beam's control points at x, on every
  /// rank (collective).
  std::vector<double> beam_coordinates(int beam, Vec x) const;

  /// A permutation of all unknowns (new position -> old index) for a factorisation without
  /// pivoting: beams in an order where every slider comes before its carrier, each control
  /// point's 12 coordinates before its 6 multipliers, and every effect's extras right after its
  /// elimination anchor. Each multiplier then meets its pivot as a Schur complement of the
  /// coordinates before it, and every joint fills only a window of its carrier's band, so the
  /// factorisation's cost grows linearly with the scene (the natural order, with all extras at
  /// the end, fills every carrier from its joints to its last point). Same on every rank;
  /// computed once, at finalize (a net's minimum-degree order is not free, and the solvers ask
  /// again at every new Jacobian pattern).
  const std::vector<PetscInt>& elimination_order() const { return elimination_order_; }
  /// The control points in the order the DofMap numbers them: each connected structure (beams
  /// joined through joints, NumberingHints::reference_couplings) in reverse Cuthill-McKee order, which
  /// keeps a beam in its own order and slots a beam hanging from another among the points it
  /// hangs from; structures in the order of their first point. Splitting this order into
  /// contiguous parts then cuts each structure across few points. Empty when no effect couples
  /// two points (index order). Depends on the scene alone, not on the number of ranks.
  std::vector<PetscInt> numbering_order() const;
  /// The beam holding control point cp.
  int beam_of_cp(PetscInt cp) const;
  /// The most control points a rank holds next to another rank's (map_'s split).
  PetscInt largest_cut() const;
  /// Sort control points by their reference position along the axis of the points' largest
  /// extent (stable): the numbering of a structure with loops, so that its split is a straight cut.
  void order_along_longest_axis(std::vector<PetscInt>& cps) const;
  /// Per beam, the index of the structure whose beams are joined into loops (a net) it belongs
  /// to, or -1; links_out (optional): the links between beams that hold for the whole run.
  std::vector<int> loop_structures(std::vector<std::pair<PetscInt, PetscInt>>* links_out = nullptr) const;
  /// The structures whose beams are joined into loops (a net), each as its control points in a
  /// fill-reducing (minimum-degree) order of their graph, for elimination_order.
  std::vector<std::vector<PetscInt>> loop_structure_orders() const;
  /// Choose each effect's anchor among its ExtraUnknowns::anchor_choices (ExtraUnknowns::set_anchor).
  void resolve_anchors();
  /// Link every JointLink effect to its joint (before the anchors: they sit with the joint's).
  void link_effects();
  /// Per position of a numbering order (empty: index order): 1 where no rank boundary may fall
  /// right before it, between the first and last of an effect's anchor points
  /// (ExtraUnknowns::anchor_points), so that its extras find their pivots on their own rank.
  std::vector<char> joined_positions(const std::vector<PetscInt>& order) const;
  /// Owned control points that are orthonormality-constrained director triads (sorted).
  std::vector<PetscInt> director_triads() const;

  /// Unknowns ghosted on this rank (owned ones included).
  PetscInt ghost_count() const { return ghost_dofs_.size(); }
  /// How often the ghost set was rebuilt because an effect moved (sliding joints).
  int ghost_rebuilds() const { return ghost_rebuilds_; }
  /// The most control points a rank would hold next to another rank's, in the split over all
  /// ranks (0 when the model was owned by one rank from the start, -sb_serial_below). Above
  /// -sb_serial_above_cut rank 0 owns the model alone.
  PetscInt cut_points() const { return cut_points_; }

  /// Prescribed rows owned by this rank and their values.
  const std::vector<PetscInt>& prescribed_rows() const { return bc_rows_; }

 private:
  /// beam_mass() of every beam (collective).
  void compute_beam_masses();
  /// elimination_order()'s permutation, from the finalized DofMap.
  std::vector<PetscInt> compute_elimination_order() const;
  /// Scatter the global x into a ghosted local vector (default: x_local_).
  PetscErrorCode update_ghosts(Vec x, Vec local = nullptr) const;
  /// The effects' closest-point queries, answered by one parallel search (collective).
  void locate_points();
  /// Ghost set and scatter from the effects' needed_dofs() (collective).
  PetscErrorCode build_ghosts() const;
  /// Ghost x (and, for two-state rules, the step start); if an effect's unknowns moved out of
  /// its ghosts (refresh_needed_dofs), rebuild the ghosts on all ranks and ghost again.
  PetscErrorCode prepare_ghosts(const StepEval& ev, Vec x) const;
  /// The residual of all effects (only < 0) or of effect `only` alone.
  PetscErrorCode assemble_residual_of(const StepEval& ev, Vec x, Vec F, long only) const;
  /// Ghost x, build the evaluation context of a step rule (x, x_f, x_old) and call body(ctx).
  template <class Body>
  PetscErrorCode with_context(const StepEval& ev, Vec x, Body&& body) const;

  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  bool finalized_ = false;
  std::vector<Beam> beams_;
  std::vector<std::unique_ptr<Effect>> effects_;
  PetscInt n_cp_total_ = 0;
  DofMap map_;

  // ghosting: sorted global indices needed on this rank, scatter global -> local work vector;
  // rebuilt when a moving effect needs other unknowns (hence mutable)
  mutable GhostIndex ghost_dofs_;
  mutable VecScatter scatter_ = nullptr;
  mutable Vec x_local_ = nullptr, r_local_ = nullptr;
  mutable Vec x_old_local_ = nullptr, xf_local_ = nullptr;
  Vec x_old_ = nullptr;  // the step start last given to set_step_start (not owned)
  // the step start's rates (set_step_rates), ghosted: only with ConfigurationKinetic effects
  mutable Vec v_old_local_ = nullptr, a_old_local_ = nullptr;
  Vec v_old_ = nullptr, a_old_ = nullptr;
  double rate_beta_ = 0.25, rate_gamma_ = 0.5;
  std::vector<const ConfigurationKinetic*> kinetic_of_;
  unsigned long step_starts_ = 0;  // set_step_start calls: EvalContext::step_start
  mutable int ghost_rebuilds_ = 0;
  PetscInt cut_points_ = 0;
  std::vector<PetscInt> elimination_order_;  // elimination_order(), set by finalize
  Vec q_mask_ = nullptr, s_mask_ = nullptr;
  bool has_sliding_state_ = false;
  std::vector<StepHistory*> history_;  // the effects' StepHistory parts, in effect order
  std::vector<PetscInt> init_rows_;  // initial values of extras (owned rows)
  std::vector<PetscScalar> init_values_;
  bool has_inertia_ = false;
  std::vector<char> rate_force_;  ///< per effect: EffectSpec::rate_force
  bool has_rate_force_ = false;
  std::vector<double> beam_mass_;  ///< beam_mass(), summed over ranks at finalize()

  Vec x_ = nullptr, r_ = nullptr;
  Mat J_ = nullptr;

  mutable CooAssembly coo_;  // assembly record of J_
  void collect_prescribed(double t) const;
  bool moving_prescriptions_ = false;
  std::vector<const PrescribedMotion*> prescribers_;  ///< effects with the part, in order
  std::vector<const MovingPoints*> movers_;
  std::vector<const MassSource*> mass_of_;  ///< per effect (nullptr: no mass)
  mutable std::vector<PetscInt> bc_rows_;
  mutable std::vector<PetscScalar> bc_values_;

  std::vector<PetscLogEvent> effect_events_;
  PetscLogEvent ev_residual_ = 0, ev_jacobian_ = 0, ev_ghost_ = 0;
};

}  // namespace slidebeam
