// SPDX-License-Identifier: MIT
#pragma once
/// @file The effect interface: one physical term of the model (a beam's elastic energy, gravity, a
/// load, a support, ...) behind residual, tangent and energy, registered by name. The model
/// assembles exactly the effects a scene creates.

#include "model/dof_map.hpp"
#include "model/effect_parts.hpp"

#include <petscmat.h>

#include <array>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace slidebeam {

class Model;

/// Parameters of an effect, as given by the scene (numbers, vectors, strings).
struct EffectParams {
  std::map<std::string, double> num;
  std::map<std::string, std::vector<double>> vec;
  std::map<std::string, std::string> str;

  double number(const std::string& key) const;
  double number(const std::string& key, double fallback) const;
  const std::vector<double>& vector(const std::string& key, size_t expected_size) const;
  const std::string& string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& fallback) const;
};

/// The sorted global unknowns a rank reads (owned and ghosted), with a constant-time map from a
/// global index to its position: effects look up every control point of every element in every
/// evaluation, and a binary search there was 5 % of a pendulum step.
class GhostIndex {
 public:
  /// Take a sorted, duplicate-free list and build the map.
  void assign(std::vector<PetscInt> dofs);
  const std::vector<PetscInt>& dofs() const { return dofs_; }
  PetscInt size() const { return static_cast<PetscInt>(dofs_.size()); }
  /// Position of a global unknown; throws if it is not in the list.
  PetscInt index(PetscInt global) const {
    if (!table_.empty()) {
      const PetscInt k = global - base_;
      if (k >= 0 && k < static_cast<PetscInt>(table_.size()) && table_[k] >= 0) return table_[k];
    }
    return search(global);
  }

 private:
  PetscInt search(PetscInt global) const;
  std::vector<PetscInt> dofs_;
  std::vector<PetscInt> table_;  // position of base_ + k, -1 if absent (empty: spread too wide)
  PetscInt base_ = 0;
};

/// Ghosted values of the unknowns an effect reads, indexed by global unknown.
class LocalValues {
 public:
  LocalValues(const GhostIndex& index, PetscScalar* data) : index_(&index), data_(data) {}
  /// Pointer to the 18 unknowns of control point cp (12 coordinates, then 6 multipliers).
  PetscScalar* cp(const DofMap& map, PetscInt cp) const { return data_ + index(map.q(cp, 0)); }
  PetscScalar& at(PetscInt global) const { return data_[index(global)]; }

 private:
  PetscInt index(PetscInt global) const { return index_->index(global); }
  const GhostIndex* index_;
  PetscScalar* data_;
};

/// How an effect evaluates its forces within a time step (docs/theory.md, "Time integration").
///  - Endpoint: forces at x (statics, Newmark, HHT).
///  - Theta: forces at the state xf = (1 - theta) x_old + theta x, so their derivative with
///    respect to x is theta times the derivative at xf (midpoint rule: theta = 1/2).
///  - EnergyMomentum: as Theta with theta = 1/2, except that terms with a discrete gradient
///    (strain energy: averaged strains) use it.
/// In every rule, constraint rows are evaluated at x (constraints hold at the end of the step)
/// and multipliers are always read from x.
enum class StepRule { Endpoint, Theta, EnergyMomentum };

/// The time-stepping scheme of an evaluation (Static: load steps, no rates).
enum class StepScheme { Static, EnergyMomentum, Midpoint, Newmark, HHT };

/// Evaluation state handed to effects.
struct EvalContext {
  const Model& model;
  const DofMap& map;
  double t;                 ///< time of the loads (static: pseudo-time of the load step)
  const LocalValues& x;     ///< current unknowns (ghosted): end of the step
  const LocalValues& xf;    ///< where forces are evaluated (== x for Endpoint)
  const LocalValues& x_old; ///< start of the step (== x for statics)
  StepRule rule = StepRule::Endpoint;
  double theta = 1.0;       ///< d xf / d x
  double dissipation = 0.0; ///< EnergyMomentum: xi of the energy-decaying variant (0: conserving)
  /// Changes whenever x_old does (each set_step_start): effects may cache what they compute
  /// from x_old for the whole step under this key.
  unsigned long step_start = 0;
  /// The step: from t_start (state x_old) to t_end (state x) by h = t_end - t_start, with this
  /// scheme. h = 0 outside time steps (statics, energies, initial values): rate-dependent
  /// effects then exert no force. Rates are mean rates over the step, (x - x_old) / h.
  double t_start = 0.0, t_end = 0.0, h = 0.0;
  StepScheme scheme = StepScheme::Static;
  /// Within a step, for ConfigurationKinetic effects only (null otherwise): the velocity and
  /// acceleration at the step's start, ghosted, and Newmark's beta and gamma (Newmark, HHT:
  /// v = v_old + h ((1 - gamma) a_old + gamma a), a = (x - x_old - h v_old) / (beta h^2) -
  /// (1 / (2 beta) - 1) a_old; energy-momentum, midpoint: v = 2 (x - x_old) / h - v_old).
  const LocalValues* v_old = nullptr;
  const LocalValues* a_old = nullptr;
  double beta = 0.25, gamma = 0.5;
};

/// How an effect's work enters the energy balance of a dynamic run, H - H_0 = W - D (H: kinetic
/// plus stored energy, W: work put in from outside, D: energy dissipated).
enum class EnergyRole {
  Stored,       ///< strain, potential or kinetic energy: part of H (its explicit time change, if
                ///< time_dependent(), is work put in)
  Constraint,   ///< does no work (supports, joints)
  External,     ///< a non-conservative external force (drag, a follower load): its work is in W
  Dissipative,  ///< damping, friction: what it takes out is in D
  Driving,      ///< prescribed motion: the power it puts in is in W
};
const char* energy_role_name(EnergyRole role);

/// One parameter of an effect as a scene gives it: the Python scene parser validates a table
/// with these and the documentation lists them.
struct ParamSpec {
  enum class Kind {
    Number,        ///< a float in [min, max]
    Integer,       ///< an integer in [min, max]
    Vector,        ///< `size` floats
    Choice,        ///< one of `choices`
    Beam,          ///< a beam's name (EffectParams::num gets its index)
    Track,         ///< a beam's name, or a list of beams' names joined end to end (num: the
                   ///< first one's index; a list also vec: <key>_track, the indices in order)
    Point,         ///< arc length on the beam `on`: "start", "end" or a number (num: s, or <on>_s)
    End,           ///< as Point, at one end of the beam only
    Position,      ///< a point the entry's Point must match (checked, not passed on)
    Motion,        ///< a sub-table {displacement (m), rotation (rad; size 6 only), time_function}
                   ///< starting from 0 (vec: motion_displacement, motion_rotation; num/str: tf_*)
    Beams,         ///< two different beams' names (num: <key without s>_a, _b, e.g. beam_a)
    Ends,          ///< one of "start"/"end" per beam of the Beams parameter (num: s_a, s_b)
    Points,        ///< as Ends, or an arc length in [0, L], per beam of the Beams parameter
    TimeFunction,  ///< a [time_function] table (num/str: tf_*); fallback "load": a ramp over
                   ///< the load steps in statics, constant in dynamics
    Name,          ///< a name (str) of letters, digits, '_' and '-': the entry's own (by
                   ///< default <table><k>, k its number in the table from 1), or, optional, the
                   ///< name of another entry it acts on
  };
  std::string key;
  Kind kind = Kind::Number;
  std::string unit;      ///< SI unit, "" for dimensionless
  std::string meaning;
  std::string fallback;  ///< the default as TOML text; "" when the key is required
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;  ///< min itself is not allowed (x > min)
  int size = 0;           ///< Vector: its length; Motion: 3 (displacement) or 6 (and rotation)
  /// Choice: the allowed values; Beam, Beams: the allowed formulations ("director", "ancf";
  /// empty: any)
  std::vector<std::string> choices;
  bool optional = false;  ///< may be left out (the effect then decides); no fallback
  std::string on;         ///< Point, End, Position: the Beam parameter it lies on ("": "beam")
};

/// A scene parameter an effect refuses, by key: the scene layer names the table entry.
struct ParamError : std::invalid_argument {
  ParamError(std::string key_, const std::string& message) : std::invalid_argument(message), key(std::move(key_)) {}
  std::string key;
};

/// What a scene may say about an effect type, and its place in the energy balance: given once,
/// with the effect's registration.
struct EffectSpec {
  std::string type;   ///< the registered name
  std::string table;  ///< the scene's [[table]] that creates one per entry ("": the model creates it)
  /// Several effect types may share a table: the entry's `type` key picks the one whose variant
  /// it names ("": the table has one type and no `type` key).
  std::string variant;
  bool single = false;  ///< a single [table], not an array of [[table]]s
  std::string meaning;
  std::vector<ParamSpec> params;
  EnergyRole role = EnergyRole::Stored;
  /// Stored effects: which part of H their energy() is ("strain", "potential" or "kinetic").
  std::string stored;
  /// A force from the step's mean rates, none outside a step (damping, drag): HHT weights it by
  /// 1, not by 1 + alpha, since its history term at the step start (h = 0) is zero.
  bool rate_force = false;
};

/// Fast repeated assembly of one matrix in PETSc's coordinate (COO) format: the first assembly
/// records the (row, column) of every value effects add, in call order, and hands them to
/// MatSetPreallocationCOO; later assemblies only check that the indices are the same and fill a
/// flat value array for MatSetValuesCOO. No per-entry search in the CSR structure (MatSetValues
/// spent ~20 ns per entry, 70% of a Jacobian). If the indices change (a term moved to other
/// unknowns), the pattern is recorded again.
class CooAssembly {
 public:
  void begin();
  void add(PetscInt m, const PetscInt* rows, PetscInt n, const PetscInt* cols, const PetscScalar* v, double scale);
  /// Move the values into A (collective). A must be the matrix this object always serves.
  PetscErrorCode end(Mat A);
  /// Incremented whenever the pattern is recorded again after the first time: a factorisation
  /// of the matrix must then be set up anew (PCReset), not only refactored numerically.
  int generation() const { return generation_; }

 private:
  std::vector<PetscInt> i_, j_;     // COO indices, one per value
  std::vector<PetscInt> calls_;     // signature of every add: m, n, rows, cols (cheap to compare)
  std::vector<PetscScalar> v_;
  size_t cursor_ = 0, call_cursor_ = 0;
  bool pattern_changed_ = true;
  bool recorded_ = false;
  int generation_ = 0;
};

/// Adds element matrices into a global matrix: with MatSetValues, or into a CooAssembly; or
/// hands them to a function that reads them (a sum over some entries: Model's beam masses).
/// Values are multiplied by a scale (1 by default; not for a reader).
class MatSink {
 public:
  using Reader = std::function<void(PetscInt m, const PetscInt* rows, PetscInt n, const PetscInt* cols,
                                    const PetscScalar* v)>;
  explicit MatSink(Mat A, double scale = 1.0) : A_(A), scale_(scale) {}
  explicit MatSink(CooAssembly* coo, double scale = 1.0) : coo_(coo), scale_(scale) {}
  explicit MatSink(const Reader* reader) : reader_(reader) {}
  /// A(rows, cols) += scale * values (row-major, m x n).
  PetscErrorCode add(PetscInt m, const PetscInt* rows, PetscInt n, const PetscInt* cols, const PetscScalar* v) const;

 private:
  Mat A_ = nullptr;
  CooAssembly* coo_ = nullptr;
  const Reader* reader_ = nullptr;
  double scale_ = 1.0;
};

/// The core every effect has: what it is, which unknowns its items read, its residual, tangent
/// and energy. Anything more is an opt-in part (model/effect_parts.hpp).
class Effect {
 public:
  virtual ~Effect() = default;

  /// Registered name of the effect type ("beam_elastic", "gravity", ...).
  virtual std::string type() const = 0;
  /// Human-readable label of this instance ("beam_elastic[strip]").
  virtual std::string label() const = 0;

  /// Choose the items (elements, points) this rank evaluates. Called once after numbering.
  virtual void distribute(const Model& model) = 0;
  /// Global unknowns read by this rank's items (for the ghost scatter).
  virtual void needed_dofs(const Model& model, std::vector<PetscInt>& dofs) const = 0;
  /// Record every Jacobian entry the effect may ever touch (values are ignored).
  virtual PetscErrorCode pattern(const Model& model, const MatSink& sink) const = 0;

  /// r += dPi/dq (internal forces minus external forces, constraint rows); local ghosted layout.
  virtual PetscErrorCode residual(const EvalContext& ctx, const LocalValues& r) const = 0;
  /// J += d r / d x.
  virtual PetscErrorCode jacobian(const EvalContext& ctx, const MatSink& J) const = 0;
  /// This rank's share of the effect's potential energy (0 for non-potential effects).
  virtual double energy(const EvalContext&) const { return 0.0; }
  /// True if the effect depends on time explicitly (a load with a time function): its stored
  /// energy then changes with time alone, and the energy balance counts that change as work.
  virtual bool time_dependent() const { return false; }
};

/// ExtraUnknowns::n_extra of an effect, 0 for one without the part.
inline PetscInt n_extra(const Effect& e) {
  const auto* x = part_of<ExtraUnknowns>(e);
  return x ? x->n_extra() : 0;
}

using EffectFactory = std::function<std::unique_ptr<Effect>(const Model&, const EffectParams&)>;

/// Type -> (spec, factory). The built-in effect types are registered on first use (explicitly,
/// not by static initialisers, which a static library may drop).
class EffectRegistry {
 public:
  static EffectRegistry& instance();
  void add(EffectSpec spec, EffectFactory f);
  std::unique_ptr<Effect> create(const std::string& name, const Model& model, const EffectParams& p) const;
  std::vector<std::string> names() const;
  const EffectSpec& spec(const std::string& name) const;
  /// Every spec as JSON (the Python scene parser's schema of effect tables).
  std::string specs_json() const;

 private:
  std::map<std::string, std::pair<EffectSpec, EffectFactory>> entries_;
};

/// Adds the built-in effects (effects/*.cpp) to a registry.
void register_builtin_effects(EffectRegistry& registry);

}  // namespace slidebeam
