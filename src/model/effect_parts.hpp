// SPDX-License-Identifier: MIT
#pragma once
/// @file An effect's opt-in parts. Every effect has the small core of `Effect` (what it is, the
/// unknowns it reads, its residual, tangent and energy); an effect that does more also derives
/// from the parts below, and the model (or the stepper) finds them with part_of<P>(effect). An
/// effect that does not take a part costs nothing for it, and nothing outside the effect's own
/// file needs to know which effect takes which part:
///
///   ExtraUnknowns     unknowns of its own (multipliers, a sliding coordinate) and where they go
///   MassSource        a constant mass matrix (inertia)
///   PrescribedMotion  prescribed unknowns (supports), or state held by its own constraint
///   MovingPoints      points found on beams by the closest-point search, moving over them
///   NumberingHints    how the numbering and elimination order should treat what it couples
///   ReactionSource    the force and moment it exerts (supports, joints)
///   EventSource       indicator functions whose crossing the stepper locates (src/time/stepper.hpp)
///   JointTarget       a joint other effects act through (friction, a drive on a sliding joint)
///   JointLink         an effect acting through a JointTarget, which the model links it to
///   OutputSource      named values at a state (history columns <label>.<name>)

#include "model/dof_map.hpp"
#include "search/closest_point_search.hpp"

#include <petscmat.h>

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace slidebeam {

class Model;
class Effect;
class MatSink;
class LocalValues;
struct EvalContext;

/// The part P of an effect, or nullptr if it does not take it.
template <class P>
P* part_of(Effect& e) {
  return dynamic_cast<P*>(&e);
}
template <class P>
const P* part_of(const Effect& e) {
  return dynamic_cast<const P*>(&e);
}

/// Extra global unknowns (multipliers, a sliding coordinate), numbered by the model.
class ExtraUnknowns {
 public:
  virtual ~ExtraUnknowns() = default;
  /// How many (may be 0: a support whose point is a control point needs none).
  virtual PetscInt n_extra() const = 0;
  /// True for extra k that is part of the state (a sliding coordinate: no mass, no velocity of
  /// its own, but not a multiplier).
  virtual bool extra_is_state(PetscInt) const { return false; }
  /// Values of the extras in the initial state (a sliding coordinate from a projection).
  virtual void initial_values(const Model&, std::vector<PetscInt>&, std::vector<PetscScalar>&) const {}
  /// Extras a continuation (the load steps', the equilibrium start's) keeps within [lo, hi]: a
  /// slider on its carrier. Global rows, on every rank.
  virtual void bounds(const Model&, std::vector<PetscInt>&, std::vector<double>&, std::vector<double>&) const {}
  /// Extras the equilibrium start of a dynamic run holds where they are (a slider the scene
  /// holds there). Global rows, on every rank.
  virtual void held_at_start(std::vector<PetscInt>&) const {}
  /// The control point whose slot holds the extras (DofMap), right after its block (-1: after
  /// all slots, on the last rank): they are then owned with that point and eliminated after it.
  /// Choose a point the extras couple to, so that the multipliers find their pivot in the
  /// coordinates before them and their fill stays local.
  virtual PetscInt elimination_anchor(const Model&) const { return -1; }
  /// The points that could hold the extras, the preferred first (default: elimination_anchor).
  /// An effect with a choice (a rigid joint: either end) gets a point no other effect's extras
  /// use where there is one (Model::finalize): a point's 6 degrees of freedom give pivots to one
  /// set of 6 constraints, so three joints anchored at one point of a net's crossing would make
  /// two of them singular.
  virtual void anchor_choices(const Model& m, std::vector<PetscInt>& cps) const {
    const PetscInt a = elimination_anchor(m);
    if (a >= 0) cps.push_back(a);
  }
  /// The control points whose coordinates give the extras their pivots, the anchor among them
  /// (a slider point's stencil): the split over ranks keeps them on one rank, since a rank's
  /// block with the extras but not those points would be singular.
  virtual void anchor_points(const Model&, std::vector<PetscInt>& cps) const {
    if (anchor_ >= 0) cps.push_back(anchor_);
  }

  /// First global index of the extras (set by the model).
  void set_extra_offset(PetscInt first) { extra_offset_ = first; }
  PetscInt extra_offset() const { return extra_offset_; }
  /// The point chosen to hold the extras (-1: none, or not finalized yet).
  PetscInt anchor() const { return anchor_; }
  void set_anchor(PetscInt cp) { anchor_ = cp; }

 private:
  PetscInt extra_offset_ = -1;
  PetscInt anchor_ = -1;
};

/// A constant mass matrix (beam inertia, point masses, bodies): the model is dynamic when some
/// effect takes this part.
class MassSource {
 public:
  virtual ~MassSource() = default;
  /// M += the effect's mass matrix.
  virtual PetscErrorCode mass(const Model&, const MatSink&) const = 0;
};

/// Kinetic energy that changes with the configuration, T(x, v) = 1/2 v^T A(x) v (the added mass
/// of the fluid around a line: A follows the line's direction). Its step residual reads the step
/// start's rates (EvalContext::v_old, a_old, which the model ghosts only when some effect has
/// this part), and the kinetic energy and momenta of a state count its momentum A(x) v.
class ConfigurationKinetic {
 public:
  virtual ~ConfigurationKinetic() = default;
  /// p += dT/dv at the state ctx.x and velocity v (local ghosted layout).
  virtual void momentum(const EvalContext& ctx, const LocalValues& v, const LocalValues& p) const = 0;
  /// M += A(x) at the state ctx.x: the mass matrix of T at a state (the initial acceleration's).
  virtual PetscErrorCode mass_at(const EvalContext& ctx, const MatSink& M) const = 0;
};

/// Unknowns the effect prescribes (Dirichlet rows), or state it holds by its own constraint.
class PrescribedMotion {
 public:
  virtual ~PrescribedMotion() = default;
  /// The prescribed unknowns and their values. Called on every rank; return owned rows only.
  virtual void prescribed(const Model&, std::vector<PetscInt>&, std::vector<PetscScalar>&) const {}
  /// The same at time t: a support that moves (the rows stay the same, the values follow t).
  virtual void prescribed_at(const Model& m, double /*t*/, std::vector<PetscInt>& rows,
                             std::vector<PetscScalar>& vals) const {
    prescribed(m, rows, vals);
  }
  /// A constraint that moves with time (a driven support) does work: the energy balance counts
  /// it as driving (EnergyRole::Driving) although its type is a constraint.
  virtual bool drives() const { return false; }
  /// State unknowns held through the effect's own constraint (a driven slider's s): nothing
  /// else may hold them (the equilibrium start's held sliders).
  virtual void constrained_state(std::vector<PetscInt>& /*rows*/) const {}
};

/// Points located on beams' centre lines by the model's parallel closest-point search, which may
/// move over the beam (a slider on its carrier).
class MovingPoints {
 public:
  virtual ~MovingPoints() = default;
  /// Points to locate in the reference configuration, before Effect::distribute: the model
  /// answers every effect's queries in one parallel search.
  virtual void closest_point_queries(const Model&, std::vector<ClosestPointQuery>&) const = 0;
  /// The answers, in order, on every rank (so an error is the same everywhere). Throws
  /// std::invalid_argument for a point off its beam.
  virtual void set_closest_points(const Model&, const ClosestPoint*) = 0;
  /// Given the ghosted unknowns before an evaluation (x and the step start x_old), true when the
  /// effect will read unknowns outside Effect::needed_dofs, after updating what it returns: the
  /// model then rebuilds its ghost scatter (collective). Unknowns the effect declared always
  /// stay readable, so it may read its own moving coordinate here.
  virtual bool refresh_needed_dofs(const Model&, const LocalValues& /*x*/, const LocalValues& /*x_old*/) const {
    return false;
  }
};

/// How the numbering and the elimination order should treat what the effect couples.
class NumberingHints {
 public:
  virtual ~NumberingHints() = default;
  /// Pairs of control points coupled in the reference configuration (a rigid joint's two
  /// points; a slider point and the carrier point nearest to it). The numbering keeps coupled
  /// points close, so that a rank's share of a structure stays connected and its interface with
  /// other ranks small (Model::numbering_order).
  virtual void reference_couplings(const Model&, std::vector<std::pair<PetscInt, PetscInt>>&) const {}
  /// Beams whose control points should be eliminated before another beam's, as (first, then)
  /// pairs: a slider before its carrier, so that a joint's fill lands in the carrier's band.
  virtual void elimination_precedence(std::vector<std::pair<int, int>>&) const {}
  /// Beams whose points give the extras their pivots while the effect runs along them (a fixed
  /// guide's rope, which runs through it): the extras are then eliminated after the last of
  /// these beams, not after their anchor's block. Anchored at the point nearest them at the
  /// start, they would find no pivot once the rope has run beyond that point's support.
  virtual void pivots_along(std::vector<int>& /*beams*/) const {}
  /// Owned control points whose block is an orthonormality-constrained director triad: 12
  /// coordinates (phi, d1, d2, d3), then the 6 multipliers of 1/2(d1.d1-1), 1/2(d2.d2-1),
  /// 1/2(d3.d3-1), d1.d2, d1.d3, d2.d3, whose forces are G(x_f)^T lambda and nothing else.
  virtual void director_triads(const Model&, std::vector<PetscInt>& /*cps*/) const {}
};

/// The force and moment a support or joint exerts, on the beam it holds (a joint: on its first
/// beam); the moment about the held point (a rail: about its start).
struct Reaction {
  std::array<double, 3> force{}, moment{};
  bool has_moment = false;
};

/// What ReactionSource::reaction reads, at owned rows (0 elsewhere): raw, the residual of all
/// effects (with the step's inertia) before prescribed rows are replaced; own, this effect's
/// residual; x, the state.
struct ReactionInput {
  std::function<double(PetscInt)> raw, own, x;
};

/// A reaction (supports and joints): Model::reactions lists every effect with this part.
class ReactionSource {
 public:
  virtual ~ReactionSource() = default;
  /// The force (and moment) it exerts on the structure, summed over ranks by the model: add the
  /// terms of owned rows only.
  virtual void reaction(const Model& model, const ReactionInput& in, Reaction& out) const = 0;
  /// Whether reaction() reads ReactionInput::own (assembling it costs a pass over the state).
  virtual bool reaction_reads_own() const { return false; }
};

/// Events: where an indicator function g(x) of the state falls below zero (g >= 0 inside): a
/// slider passing its carrier's end. The stepper evaluates the indicators after each step and,
/// where one has crossed, takes the step again, shortened until the state lies on the boundary.
class EventSource {
 public:
  virtual ~EventSource() = default;
  /// Number of indicator functions.
  virtual int n_events() const = 0;
  /// g_i(x) for i < n_events() from this rank's owned rows of x (the array holds rows
  /// [owned_lo, owned_hi)); 0 for what this rank does not own: the caller sums over the ranks.
  virtual void event_values(const Model& model, const PetscScalar* x, PetscInt owned_lo, PetscInt owned_hi,
                            double* g) const = 0;
  /// The length that scales g_i: an indicator below -1e-12 of it has crossed, and a shortened
  /// step ends on the boundary once g_i is within [0, 1e-9] of it.
  virtual double event_scale(const Model& model, int i) const = 0;
  /// What a crossing of g_i does to the run: ends it as stopped (its results complete up to
  /// there) or as failed.
  enum class Action { Stop, Fail };
  virtual Action event_action(int) const { return Action::Stop; }
  /// The run's message for indicator i crossed with the value g at the state the run ends in:
  /// what happened, then `when` (the caller's "at t = ..."), then the action.
  virtual std::string event_message(const Model& model, int i, double g, const std::string& when) const = 0;
};

/// A joint other effects act through: a sliding joint or a guide, whose coordinate s friction
/// and a drive act on (they take the JointLink part).
class JointTarget {
 public:
  virtual ~JointTarget() = default;
  /// The beam whose point slides (-1: none, a guide fixed in space).
  virtual int slider_beam() const = 0;
  /// A guide's name ("": a sliding joint, found by its slider beam).
  virtual std::string joint_name() const { return ""; }
  /// The mass that moves along s, the scale of friction's stick test: the slider beam's, or a
  /// guide's rope's.
  virtual double sliding_mass(const Model& m) const = 0;
  /// The joint's force on its slider in the global frame under the evaluation's rule (the
  /// step's force under the midpoint-type rules), on the rank that evaluates the joint (true);
  /// false elsewhere.
  virtual bool joint_force(const EvalContext&, std::array<double, 3>&) const = 0;
  /// The magnitude N of its force on the slider transverse to the carrier's unit tangent at s
  /// (the normal force of friction), under the evaluation's rule, and dN / d(dofs) over the
  /// global unknowns it depends on, on the rank that evaluates the joint (true); false elsewhere.
  virtual bool normal_force(const EvalContext&, double& N, std::vector<PetscInt>& dofs,
                            std::vector<double>& dN) const = 0;
  /// The joint's extra unknowns (its multipliers, then s).
  virtual const ExtraUnknowns& joint_unknowns() const = 0;
};

/// An effect acting through a joint (friction on a sliding joint or a guide, a drive of its
/// slider or a winch at a guide): it names the joint's slider beam or the guide, and the model
/// links it to that joint, the last one before it in scene order, before the numbering
/// (Model::finalize).
class JointLink {
 public:
  virtual ~JointLink() = default;
  /// The slider beam of the joint it acts through (-1: a guide, by its name).
  virtual int linked_slider() const = 0;
  /// The guide it acts through ("": a sliding joint, by its slider beam).
  virtual std::string linked_name() const { return ""; }
  /// The joint found (nullptr: none; the effect throws std::invalid_argument naming its table).
  virtual void link(const Model& m, const JointTarget* joint) = 0;
};

/// Named values of the effect at a state, e.g. a contact's force and the length in contact:
/// the history's columns <label>.<name>, one per name.
class OutputSource {
 public:
  virtual ~OutputSource() = default;
  virtual std::vector<std::string> output_names() const = 0;
  /// The history columns' prefix, <prefix>.<name> ("": the effect's scene label).
  virtual std::string output_prefix() const { return ""; }
  /// values[i] += this rank's share of value i at the evaluation's state x (the model sums
  /// the ranks' shares).
  virtual void outputs(const EvalContext& ctx, double* values) const = 0;
};

/// State an effect keeps from one time step to the next besides the unknowns (friction's stuck
/// points on a contact: where each point is held). It changes only when a step is accepted
/// (commit), so a rejected or shortened step leaves it as it was; the stepper's snapshots and
/// the checkpoints hold it (Model::effect_history).
class StepHistory {
 public:
  virtual ~StepHistory() = default;
  /// The values, the same length on every rank; this rank's own entries are those it commits.
  virtual const std::vector<double>& history() const = 0;
  /// Whether entry i is this rank's (the ranks' own entries make up the whole history).
  virtual bool owns_history(size_t i) const = 0;
  /// Replace the values (a snapshot's, a checkpoint's: the whole history on every rank).
  virtual void set_history(const std::vector<double>& values) = 0;
  /// The step from ctx.x_old to ctx.x was accepted: update this rank's entries from it.
  virtual void commit(const EvalContext& ctx) = 0;
};

}  // namespace slidebeam
