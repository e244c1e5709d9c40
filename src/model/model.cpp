// SPDX-License-Identifier: MIT
#include "model/model.hpp"

#include "kernels/beam_kernels.hpp"

#include "util/petsc_check.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>

namespace slidebeam {

namespace {
// Beams joined into loops are eliminated in minimum-degree order: on a 10 x 10 net it filled 4.5x
// less than nested dissection (docs/performance.md, "Multi-beam cables: parallel runs, contact search,
// linear cost").
const char* const kLoopOrdering = MATORDERINGQMD;

// Control points a span couples lie within this many points of each other along their beam:
// three consecutive points of a director beam's quadratic span, two nodes of an ANCF element.
int span_reach(const Beam& b) { return b.is_ancf() ? 1 : 2; }

// An effect's term: an exception from it leaves as a PETSc error that names the effect (the
// assembly runs inside PETSc's callbacks; util/petsc_check.hpp says why nothing may unwind there).
template <class Term>
PetscErrorCode effect_term(const Effect& effect, Term&& term) noexcept {
  try {
    return term();
  } catch (...) {
    std::string label = "?";
    try {
      label = effect.label();
    } catch (...) {
    }
    return current_exception_to_petsc(label.c_str());
  }
}

PetscClassId slidebeam_classid() {
  static PetscClassId id = 0;
  if (!id) PetscClassIdRegister("slidebeam", &id);
  return id;
}
PetscLogEvent event(const std::string& name) {
  static std::map<std::string, PetscLogEvent> events;
  auto it = events.find(name);
  if (it != events.end()) return it->second;
  PetscLogEvent e = 0;
  PetscLogEventRegister(name.c_str(), slidebeam_classid(), &e);
  events[name] = e;
  return e;
}
}  // namespace

Model::Model(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  ev_residual_ = event("SBAssembleResid");
  ev_jacobian_ = event("SBAssembleJac");
  ev_ghost_ = event("SBGhostUpdate");
}

Model::~Model() {
  // Effects may hold no PETSc objects; destroy ours. Safe after PetscFinalize only if never created.
  VecScatterDestroy(&scatter_);
  VecDestroy(&x_local_);
  VecDestroy(&x_old_);
  VecDestroy(&r_local_);
  VecDestroy(&x_old_local_);
  VecDestroy(&xf_local_);
  for (Vec* v : {&v_old_, &a_old_, &v_old_local_, &a_old_local_}) VecDestroy(v);
  VecDestroy(&q_mask_);
  VecDestroy(&s_mask_);
  VecDestroy(&x_);
  VecDestroy(&r_);
  MatDestroy(&J_);
}

int Model::add_beam(const BeamSpec& spec) {
  if (finalized_) throw std::logic_error("add_beam after finalize");
  for (const auto& b : beams_)
    if (b.name() == spec.name) throw std::invalid_argument("duplicate beam name '" + spec.name + "'");
  beams_.emplace_back(spec, static_cast<int>(beams_.size()), static_cast<int>(n_cp_total_));
  n_cp_total_ += beams_.back().n_cp();
  return static_cast<int>(beams_.size()) - 1;
}

int Model::add_effect(const std::string& type, const EffectParams& params) {
  if (finalized_) throw std::logic_error("add_effect after finalize");
  effects_.push_back(EffectRegistry::instance().create(type, *this, params));
  effect_events_.push_back(event("SB:" + type));
  return static_cast<int>(effects_.size()) - 1;
}

void Model::finalize(const PartitionPolicy& partition) {
  if (finalized_) return;
  if (beams_.empty()) throw std::invalid_argument("the model has no beams");
  std::vector<int> coordinates, multipliers;
  for (const auto& b : beams_)
    for (int c = 0; c < b.n_cp(); ++c) {
      coordinates.push_back(b.coordinates_per_cp());
      multipliers.push_back(b.multipliers_per_cp());
    }
  // Extras go into their anchor's slot (in effect order), the rest after all slots.
  std::vector<int> attached(coordinates.size(), 0);
  std::vector<PetscInt> anchor(effects_.size(), -1), slot_position(effects_.size(), 0);
  PetscInt n_tail = 0;
  link_effects();
  resolve_anchors();
  for (size_t k = 0; k < effects_.size(); ++k) {
    const PetscInt n = n_extra(*effects_[k]);
    if (n == 0) continue;
    const PetscInt a = part_of<ExtraUnknowns>(*effects_[k])->anchor();
    if (a >= 0 && a < n_cp_total_) {
      anchor[k] = a;
      slot_position[k] = attached[static_cast<size_t>(a)];
      attached[static_cast<size_t>(a)] += static_cast<int>(n);
    } else {
      slot_position[k] = n_tail;
      n_tail += n;
    }
  }
  PetscInt total = n_tail;
  for (size_t c = 0; c < coordinates.size(); ++c) total += coordinates[c] + multipliers[c] + attached[c];
  // a model too small to gain from distribution is owned and solved by rank 0 alone
  const std::vector<PetscInt> order = numbering_order();
  const std::vector<char> joined = joined_positions(order);
  map_ = DofMap(coordinates, multipliers, n_tail, rank_, size_, attached, total < partition.serial_below ? 1 : 0, order,
                joined);
  if (map_.owners() > 1) {
    // A split that cuts wide (a net cut across dozens of ropes) costs the parallel solve more in
    // interface set-up than it saves: such a model is owned by rank 0 alone.
    cut_points_ = largest_cut();
    if (partition.serial_above_cut > 0 && cut_points_ > partition.serial_above_cut)
      map_ = DofMap(coordinates, multipliers, n_tail, rank_, size_, attached, 1, order, joined);
  }
  for (size_t k = 0; k < effects_.size(); ++k)
    if (n_extra(*effects_[k]) > 0)
      part_of<ExtraUnknowns>(*effects_[k])->set_extra_offset(anchor[k] >= 0 ? map_.attached(anchor[k]) + slot_position[k]
                                                                            : map_.extra(slot_position[k]));
  elimination_order_ = compute_elimination_order();
  locate_points();
  for (auto& e : effects_) e->distribute(*this);

  SB_CHECK(VecCreateMPI(comm_, map_.local_size(), map_.global_size(), &x_));
  SB_CHECK(VecSetOptionsPrefix(x_, "sb_x_"));
  SB_CHECK(VecDuplicate(x_, &r_));
  kinetic_of_.clear();
  for (const auto& e : effects_)
    if (const auto* k = part_of<ConfigurationKinetic>(*e)) kinetic_of_.push_back(k);
  SB_CHECK(build_ghosts());

  // Jacobian with exact preallocation: record every block effects may touch, plus the diagonal.
  Mat P = nullptr;
  SB_CHECK(MatCreate(comm_, &P));
  SB_CHECK(MatSetType(P, MATPREALLOCATOR));
  SB_CHECK(MatSetSizes(P, map_.local_size(), map_.local_size(), map_.global_size(), map_.global_size()));
  SB_CHECK(MatSetUp(P));
  MatSink psink(P);
  for (const auto& e : effects_) SB_CHECK(e->pattern(*this, psink));
  for (PetscInt i = map_.owned_lo(); i < map_.owned_hi(); ++i) {
    const PetscScalar zero = 0.0;
    SB_CHECK(MatSetValues(P, 1, &i, 1, &i, &zero, ADD_VALUES));
  }
  SB_CHECK(MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY));
  SB_CHECK(MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY));
  SB_CHECK(MatCreate(comm_, &J_));
  SB_CHECK(MatSetOptionsPrefix(J_, "sb_J_"));
  SB_CHECK(MatSetSizes(J_, map_.local_size(), map_.local_size(), map_.global_size(), map_.global_size()));
  SB_CHECK(MatSetType(J_, MATAIJ));
  SB_CHECK(MatSetFromOptions(J_));
  SB_CHECK(MatPreallocatorPreallocate(P, PETSC_TRUE, J_));
  SB_CHECK(MatDestroy(&P));
  SB_CHECK(MatSetOption(J_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  SB_CHECK(MatSetOption(J_, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));

  prescribers_.clear();
  movers_.clear();
  mass_of_.clear();
  for (const auto& e : effects_) {
    mass_of_.push_back(part_of<MassSource>(*e));
    if (const auto* pm = part_of<PrescribedMotion>(*e)) {
      prescribers_.push_back(pm);
      moving_prescriptions_ |= pm->drives();
    }
    if (const auto* mp = part_of<MovingPoints>(*e)) movers_.push_back(mp);
  }
  collect_prescribed(0.0);
  // Coordinates versus multipliers/extras.
  SB_CHECK(VecDuplicate(x_, &q_mask_));
  {
    PetscScalar* a = nullptr;
    SB_CHECK(VecGetArray(q_mask_, &a));
    for (PetscInt i = map_.owned_lo(); i < map_.owned_hi(); ++i) a[i - map_.owned_lo()] = 0.0;
    for (PetscInt cp = 0; cp < n_cp_total_; ++cp) {
      if (!map_.owns_cp(cp)) continue;
      for (int k = 0; k < map_.n_coordinates(cp); ++k) a[map_.q(cp, k) - map_.owned_lo()] = 1.0;
    }
    SB_CHECK(VecRestoreArray(q_mask_, &a));
  }
  SB_CHECK(VecDuplicate(x_, &s_mask_));
  SB_CHECK(VecZeroEntries(s_mask_));
  for (const auto& effect : effects_) {
    const auto* e = part_of<ExtraUnknowns>(*effect);
    if (!e) continue;
    for (PetscInt k = 0; k < e->n_extra(); ++k) {
      if (!e->extra_is_state(k)) continue;
      has_sliding_state_ = true;
      const PetscInt row = e->extra_offset() + k;
      if (row >= map_.owned_lo() && row < map_.owned_hi()) SB_CHECK(VecSetValue(s_mask_, row, 1.0, INSERT_VALUES));
    }
    std::vector<PetscInt> rows;
    std::vector<PetscScalar> vals;
    e->initial_values(*this, rows, vals);
    for (size_t i = 0; i < rows.size(); ++i)
      if (rows[i] >= map_.owned_lo() && rows[i] < map_.owned_hi()) {
        init_rows_.push_back(rows[i]);
        init_values_.push_back(vals[i]);
      }
  }
  SB_CHECK(VecAssemblyBegin(s_mask_));
  SB_CHECK(VecAssemblyEnd(s_mask_));
  has_inertia_ = std::any_of(mass_of_.begin(), mass_of_.end(), [](const MassSource* m) { return m != nullptr; });
  history_.clear();
  for (const auto& e : effects_)
    if (auto* h = part_of<StepHistory>(*e)) history_.push_back(h);
  rate_force_.clear();
  for (const auto& e : effects_) {
    rate_force_.push_back(EffectRegistry::instance().spec(e->type()).rate_force ? 1 : 0);
    has_rate_force_ |= rate_force_.back() != 0;
  }
  compute_beam_masses();
  finalized_ = true;
  set_reference_state(x_);
}

void Model::locate_points() {
  std::vector<ClosestPointQuery> queries;
  std::vector<size_t> first(effects_.size() + 1, 0);
  for (size_t k = 0; k < effects_.size(); ++k) {
    if (const auto* mp = part_of<MovingPoints>(*effects_[k])) mp->closest_point_queries(*this, queries);
    first[k + 1] = queries.size();
  }
  if (queries.empty()) return;
  if (size_ > 1) MPI_Barrier(comm_);  // the event times the search, not the ranks' arrival
  PetscLogEventBegin(event("SBContactSearch"), 0, 0, 0, 0);
  const std::vector<ClosestPoint> answers = closest_points(*this, queries);
  PetscLogEventEnd(event("SBContactSearch"), 0, 0, 0, 0);
  for (size_t k = 0; k < effects_.size(); ++k)
    if (first[k + 1] > first[k]) part_of<MovingPoints>(*effects_[k])->set_closest_points(*this, answers.data() + first[k]);
}

std::vector<double> Model::extra_values(int effect, Vec x) const {
  const auto* extras = part_of<ExtraUnknowns>(*effects_.at(static_cast<size_t>(effect)));
  if (!extras) return {};
  const ExtraUnknowns& e = *extras;
  std::vector<double> v(static_cast<size_t>(e.n_extra()), 0.0);
  const PetscScalar* a = nullptr;
  SB_CHECK(VecGetArrayRead(x, &a));
  for (PetscInt k = 0; k < e.n_extra(); ++k) {
    const PetscInt row = e.extra_offset() + k;
    if (row >= map_.owned_lo() && row < map_.owned_hi()) v[static_cast<size_t>(k)] = a[row - map_.owned_lo()];
  }
  SB_CHECK(VecRestoreArrayRead(x, &a));
  if (!v.empty()) MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, comm_);
  return v;
}

void Model::compute_beam_masses() {
  // the x-position unknown of every control point (a director point's phi_x, an ANCF node's
  // r_x): a rigid translation along x moves these by 1 and nothing else, so the sum of M over
  // them is the mass that translates
  std::unordered_map<PetscInt, int> beam_of_row;
  for (size_t b = 0; b < beams_.size(); ++b)
    for (int c = 0; c < beams_[b].n_cp(); ++c) beam_of_row[map_.q(beams_[b].first_cp() + c, 0)] = static_cast<int>(b);
  beam_mass_.assign(beams_.size(), 0.0);
  const MatSink::Reader tally = [&](PetscInt m, const PetscInt* rows, PetscInt n, const PetscInt* cols,
                                    const PetscScalar* v) {
    for (PetscInt i = 0; i < m; ++i) {
      const auto row = beam_of_row.find(rows[i]);
      if (row == beam_of_row.end()) continue;
      for (PetscInt j = 0; j < n; ++j)
        if (beam_of_row.count(cols[j])) beam_mass_[static_cast<size_t>(row->second)] += v[i * n + j];
    }
  };
  const MatSink sink(&tally);
  for (const MassSource* ms : mass_of_)
    if (ms) SB_CHECK(ms->mass(*this, sink));
  MPI_Allreduce(MPI_IN_PLACE, beam_mass_.data(), static_cast<int>(beam_mass_.size()), MPI_DOUBLE, MPI_SUM, comm_);
}

Mat Model::create_mass_matrix() const {
  // Its own pattern (COO), not the Jacobian's: M is applied in every step residual, and the
  // Jacobian's pattern is about 10x denser.
  Mat M = nullptr;
  SB_CHECK(MatCreate(comm_, &M));
  SB_CHECK(MatSetSizes(M, map_.local_size(), map_.local_size(), PETSC_DETERMINE, PETSC_DETERMINE));
  SB_CHECK(MatSetType(M, MATAIJ));
  CooAssembly coo;
  coo.begin();
  MatSink sink(&coo);
  for (const MassSource* ms : mass_of_)
    if (ms) SB_CHECK(ms->mass(*this, sink));
  SB_CHECK(coo.end(M));
  return M;
}

Momenta Model::momenta(Vec x, Vec p) const {
  Momenta out;
  const PetscScalar *xa = nullptr, *pa = nullptr;
  SB_CHECK(VecGetArrayRead(x, &xa));
  SB_CHECK(VecGetArrayRead(p, &pa));
  Eigen::Vector3d L = Eigen::Vector3d::Zero(), J = Eigen::Vector3d::Zero();
  for (PetscInt cp = 0; cp < n_cp_total_; ++cp) {
    if (!map_.owns_cp(cp)) continue;
    const PetscInt o = map_.q(cp, 0) - map_.owned_lo();
    // J = sum_A phi^A x p_phi^A + sum_i d_i^A x p_di^A (docs/theory.md, "Invariants"). The same sum over
    // every 3-block of coordinates holds for any interpolation r = sum_a S_a y_a whose position
    // blocks' shape functions sum to one (ANCF: r, r'); L is the sum over the position blocks.
    for (int blk = 0; blk < map_.n_coordinates(cp) / 3; ++blk) {
      const Eigen::Map<const Eigen::Vector3d> y(xa + o + 3 * blk), py(pa + o + 3 * blk);
      if (blk == 0) L += py;
      J += y.cross(py);
    }
  }
  SB_CHECK(VecRestoreArrayRead(p, &pa));
  SB_CHECK(VecRestoreArrayRead(x, &xa));
  double buf[6] = {L(0), L(1), L(2), J(0), J(1), J(2)};
  MPI_Allreduce(MPI_IN_PLACE, buf, 6, MPI_DOUBLE, MPI_SUM, comm_);
  for (int k = 0; k < 3; ++k) {
    out.linear[k] = buf[k];
    out.angular[k] = buf[3 + k];
  }
  return out;
}

PetscErrorCode Model::set_step_start(Vec x_old) {
  PetscFunctionBeginUser;
  if (x_old != x_old_) {  // keep it alive: a ghost rebuild within the step ghosts it again
    PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(x_old)));
    PetscCall(VecDestroy(&x_old_));
    x_old_ = x_old;
  }
  PetscCall(update_ghosts(x_old, x_old_local_));
  ++step_starts_;
  PetscFunctionReturn(0);
}

PetscErrorCode Model::set_step_rates(Vec v, Vec a, double beta, double gamma) {
  PetscFunctionBeginUser;
  if (kinetic_of_.empty()) PetscFunctionReturn(0);
  for (auto [given, kept] : {std::pair{v, &v_old_}, std::pair{a, &a_old_}})
    if (given != *kept) {
      PetscCall(PetscObjectReference(reinterpret_cast<PetscObject>(given)));
      PetscCall(VecDestroy(kept));
      *kept = given;
    }
  rate_beta_ = beta;
  rate_gamma_ = gamma;
  PetscCall(update_ghosts(v_old_, v_old_local_));
  PetscCall(update_ghosts(a_old_, a_old_local_));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::add_configuration_momentum(Vec x, Vec v, Vec p) const {
  PetscFunctionBeginUser;
  if (kinetic_of_.empty()) PetscFunctionReturn(0);
  PetscCall(with_context(StepEval{StepRule::Endpoint, 0.0, 1.0}, x, [&](const EvalContext& ctx) -> PetscErrorCode {
    PetscFunctionBeginUser;
    PetscCall(update_ghosts(v, v_old_local_));  // scratch: the next step sets its start's rates again
    PetscCall(VecZeroEntries(r_local_));
    PetscScalar *va = nullptr, *ra = nullptr;
    PetscCall(VecGetArray(v_old_local_, &va));
    PetscCall(VecGetArray(r_local_, &ra));
    const LocalValues vv(ghost_dofs_, va), rv(ghost_dofs_, ra);
    for (const ConfigurationKinetic* k : kinetic_of_) k->momentum(ctx, vv, rv);
    PetscCall(VecRestoreArray(r_local_, &ra));
    PetscCall(VecRestoreArray(v_old_local_, &va));
    PetscFunctionReturn(0);
  }));
  PetscCall(VecScatterBegin(scatter_, r_local_, p, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter_, r_local_, p, ADD_VALUES, SCATTER_REVERSE));
  if (v_old_) PetscCall(update_ghosts(v_old_, v_old_local_));  // the step start's again
  PetscFunctionReturn(0);
}

PetscErrorCode Model::build_ghosts() const {
  PetscFunctionBeginUser;
  std::vector<PetscInt> dofs;
  for (const auto& e : effects_) e->needed_dofs(*this, dofs);
  std::sort(dofs.begin(), dofs.end());
  dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
  ghost_dofs_.assign(std::move(dofs));
  const PetscInt n_ghost = ghost_dofs_.size();
  for (Vec* v : {&x_local_, &r_local_, &x_old_local_, &xf_local_}) PetscCall(VecDestroy(v));
  PetscCall(VecScatterDestroy(&scatter_));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, n_ghost, &x_local_));
  PetscCall(VecDuplicate(x_local_, &r_local_));
  PetscCall(VecDuplicate(x_local_, &x_old_local_));
  PetscCall(VecDuplicate(x_local_, &xf_local_));
  for (Vec* v : {&v_old_local_, &a_old_local_}) {
    PetscCall(VecDestroy(v));
    if (!kinetic_of_.empty()) PetscCall(VecDuplicate(x_local_, v));
  }
  IS is = nullptr;
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n_ghost, ghost_dofs_.dofs().data(), PETSC_COPY_VALUES, &is));
  PetscCall(VecScatterCreate(x_, is, x_local_, nullptr, &scatter_));
  PetscCall(ISDestroy(&is));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::prepare_ghosts(const StepEval& ev, Vec x) const {
  PetscFunctionBeginUser;
  PetscCall(update_ghosts(x));
  const bool two_states = ev.rule != StepRule::Endpoint;
  int moved = 0;
  {
    PetscScalar *xa = nullptr, *oa = nullptr;
    PetscCall(VecGetArray(x_local_, &xa));
    if (two_states) PetscCall(VecGetArray(x_old_local_, &oa));
    const LocalValues xv(ghost_dofs_, xa), ov(ghost_dofs_, two_states ? oa : xa);
    for (const MovingPoints* e : movers_) moved |= e->refresh_needed_dofs(*this, xv, ov) ? 1 : 0;
    if (two_states) PetscCall(VecRestoreArray(x_old_local_, &oa));
    PetscCall(VecRestoreArray(x_local_, &xa));
  }
  if (size_ > 1) PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_INT, MPI_LOR, comm_));
  if (!moved) PetscFunctionReturn(0);
  ++ghost_rebuilds_;
  PetscCall(PetscInfo(nullptr, "Ghost set rebuilt (a sliding joint left its carrier window): %d\n", ghost_rebuilds_));
  PetscCall(build_ghosts());
  PetscCall(update_ghosts(x));
  // the step start too, whatever this evaluation's rule: a later two-state evaluation of the
  // same step (a record's reactions after its energies) reads it without ghosting it again
  if (x_old_) PetscCall(update_ghosts(x_old_, x_old_local_));
  if (v_old_) PetscCall(update_ghosts(v_old_, v_old_local_));
  if (a_old_) PetscCall(update_ghosts(a_old_, a_old_local_));
  PetscFunctionReturn(0);
}

void Model::collect_prescribed(double t) const {
  // Prescribed unknowns (supports): owned rows only, later effects win on duplicates.
  std::map<PetscInt, PetscScalar> bc;
  for (const PrescribedMotion* e : prescribers_) {
    std::vector<PetscInt> rows;
    std::vector<PetscScalar> vals;
    e->prescribed_at(*this, t, rows, vals);
    for (size_t i = 0; i < rows.size(); ++i)
      if (rows[i] >= map_.owned_lo() && rows[i] < map_.owned_hi()) bc[rows[i]] = vals[i];
  }
  bc_rows_.clear();
  bc_values_.clear();
  for (const auto& kv : bc) {
    bc_rows_.push_back(kv.first);
    bc_values_.push_back(kv.second);
  }
}

void Model::set_prescribed_time(double t) const {
  if (moving_prescriptions_) collect_prescribed(t);
}

void Model::apply_prescribed(Vec x) const {
  PetscScalar* a = nullptr;
  SB_CHECK(VecGetArray(x, &a));
  for (size_t i = 0; i < bc_rows_.size(); ++i) a[bc_rows_[i] - map_.owned_lo()] = bc_values_[i];
  SB_CHECK(VecRestoreArray(x, &a));
}

void Model::extrapolate(Vec x, Vec x_last, Vec x_prev, double alpha) const {
  SB_CHECK(VecAXPBYPCZ(x, 1.0 + alpha, -alpha, 0.0, x_last, x_prev));
  PetscScalar* a = nullptr;
  const PetscScalar *al = nullptr, *ap = nullptr;
  SB_CHECK(VecGetArray(x, &a));
  SB_CHECK(VecGetArrayRead(x_last, &al));
  SB_CHECK(VecGetArrayRead(x_prev, &ap));
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (const auto& b : beams_) {
    if (b.multipliers_per_cp() == 0) continue;  // no director triads (ANCF nodes)
    for (PetscInt cp = b.first_cp(); cp < b.first_cp() + b.n_cp(); ++cp) {
      if (!map_.owns_cp(cp)) continue;
      const PetscInt j = map_.q(cp, 3) - map_.owned_lo();
      const Eigen::Map<const Eigen::Matrix3d> Dl(al + j), Dp(ap + j);  // columns d1, d2, d3
      Eigen::Map<Eigen::Matrix3d> D(a + j);
      if ((Dl.transpose() * Dl - I).cwiseAbs().maxCoeff() > 1e-8 || (Dp.transpose() * Dp - I).cwiseAbs().maxCoeff() > 1e-8) {
        kernels::closest_orthonormal_frame(a + j);  // not two rotations: the linear extrapolation, projected
        continue;
      }
      const Eigen::AngleAxisd turn(Eigen::Matrix3d(Dl * Dp.transpose()));
      D = Eigen::AngleAxisd(alpha * turn.angle(), turn.axis()) * Dl;
    }
  }
  SB_CHECK(VecRestoreArrayRead(x_prev, &ap));
  SB_CHECK(VecRestoreArrayRead(x_last, &al));
  SB_CHECK(VecRestoreArray(x, &a));
  apply_prescribed(x);
}

void Model::project_directors(Vec x) const {
  PetscScalar* a = nullptr;
  SB_CHECK(VecGetArray(x, &a));
  for (const auto& b : beams_) {
    if (b.multipliers_per_cp() == 0) continue;  // no director triads (ANCF nodes)
    for (PetscInt cp = b.first_cp(); cp < b.first_cp() + b.n_cp(); ++cp) {
      if (!map_.owns_cp(cp)) continue;
      // columns d1, d2, d3; a reflection means the extrapolation was useless: kept as it is
      kernels::closest_orthonormal_frame(a + map_.q(cp, 3) - map_.owned_lo());
    }
  }
  SB_CHECK(VecRestoreArray(x, &a));
  apply_prescribed(x);
}

void Model::set_reference_state(Vec x) const {
  SB_CHECK(VecSet(x, 0.0));
  PetscScalar* a = nullptr;
  SB_CHECK(VecGetArray(x, &a));
  for (const auto& b : beams_) {
    for (int c = 0; c < b.n_cp(); ++c) {
      const PetscInt cp = b.first_cp() + c;
      if (!map_.owns_cp(cp)) continue;
      const int nq = b.coordinates_per_cp();
      for (int k = 0; k < nq; ++k) a[map_.q(cp, k) - map_.owned_lo()] = b.q_ref()[static_cast<size_t>(nq * c + k)];
    }
  }
  for (size_t i = 0; i < init_rows_.size(); ++i) a[init_rows_[i] - map_.owned_lo()] = init_values_[i];
  SB_CHECK(VecRestoreArray(x, &a));
  apply_prescribed(x);
}

PetscErrorCode Model::update_ghosts(Vec x, Vec local) const {
  PetscFunctionBeginUser;
  if (!local) local = x_local_;
  PetscCall(PetscLogEventBegin(ev_ghost_, 0, 0, 0, 0));
  PetscCall(VecScatterBegin(scatter_, x, local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(scatter_, x, local, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(PetscLogEventEnd(ev_ghost_, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

template <class Body>
PetscErrorCode Model::with_context(const StepEval& ev, Vec x, Body&& body) const {
  PetscFunctionBeginUser;
  PetscCall(prepare_ghosts(ev, x));
  // Endpoint rule: one state. Otherwise x_f = (1 - theta) x_old + theta x (x_old ghosted by
  // set_step_start).
  // Within a time step (h > 0) the step start is readable under every rule (rates).
  const bool two_states = ev.rule != StepRule::Endpoint;
  const bool has_start = two_states || ev.h > 0.0;
  if (two_states) PetscCall(VecAXPBYPCZ(xf_local_, 1.0 - ev.theta, ev.theta, 0.0, x_old_local_, x_local_));
  PetscScalar *xa = nullptr, *oa = nullptr, *fa = nullptr;
  PetscCall(VecGetArray(x_local_, &xa));
  if (has_start) PetscCall(VecGetArray(x_old_local_, &oa));
  if (two_states) PetscCall(VecGetArray(xf_local_, &fa));
  {
    LocalValues xv(ghost_dofs_, xa);
    LocalValues ov(ghost_dofs_, has_start ? oa : xa), fv(ghost_dofs_, two_states ? fa : xa);
    EvalContext ctx{*this,         map_,        ev.t,      xv,   fv,       ov, ev.rule, two_states ? ev.theta : 1.0,
                    ev.dissipation, step_starts_, ev.t_start, ev.t_end, ev.h, ev.scheme};
    const bool rates = has_start && ev.h > 0.0 && v_old_;
    PetscScalar *va = nullptr, *aa = nullptr;
    if (rates) {
      PetscCall(VecGetArray(v_old_local_, &va));
      PetscCall(VecGetArray(a_old_local_, &aa));
    }
    const LocalValues vv(ghost_dofs_, rates ? va : xa), av(ghost_dofs_, rates ? aa : xa);
    if (rates) {
      ctx.v_old = &vv;
      ctx.a_old = &av;
      ctx.beta = rate_beta_;
      ctx.gamma = rate_gamma_;
    }
    const PetscErrorCode ierr = body(static_cast<const EvalContext&>(ctx));
    if (rates) {
      PetscCall(VecRestoreArray(a_old_local_, &aa));
      PetscCall(VecRestoreArray(v_old_local_, &va));
    }
    PetscCall(ierr);
  }
  if (two_states) PetscCall(VecRestoreArray(xf_local_, &fa));
  if (has_start) PetscCall(VecRestoreArray(x_old_local_, &oa));
  PetscCall(VecRestoreArray(x_local_, &xa));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::assemble_effects_residual(const StepEval& ev, Vec x, Vec F) const {
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ev_residual_, 0, 0, 0, 0));
  PetscCall(assemble_residual_of(ev, x, F, -1));
  PetscCall(PetscLogEventEnd(ev_residual_, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::effect_residual(size_t k, const StepEval& ev, Vec x, Vec F) const {
  return assemble_residual_of(ev, x, F, static_cast<long>(k));
}

PetscErrorCode Model::assemble_residual_of(const StepEval& ev, Vec x, Vec F, long only) const {
  PetscFunctionBeginUser;
  PetscCall(with_context(ev, x, [&](const EvalContext& ctx) -> PetscErrorCode {
    PetscFunctionBeginUser;
    // r_local_ after the ghosts are ready: a rebuild replaces it
    PetscCall(VecZeroEntries(r_local_));
    PetscScalar* ra = nullptr;
    PetscCall(VecGetArray(r_local_, &ra));
    const LocalValues rv(ghost_dofs_, ra);
    const auto add = [&](size_t k) -> PetscErrorCode {
      PetscFunctionBeginUser;
      if (only >= 0 && k != static_cast<size_t>(only)) PetscFunctionReturn(0);
      PetscCall(PetscLogEventBegin(effect_events_[k], 0, 0, 0, 0));
      PetscCall(effect_term(*effects_[k], [&] { return effects_[k]->residual(ctx, rv); }));
      PetscCall(PetscLogEventEnd(effect_events_[k], 0, 0, 0, 0));
      PetscFunctionReturn(0);
    };
    if (ev.rate_weight != 1.0 && has_rate_force_) {
      // the rate forces first, into the zeroed array, then scaled; the others add to that
      for (size_t k = 0; k < effects_.size(); ++k)
        if (rate_force_[k]) PetscCall(add(k));
      PetscInt n = 0;
      PetscCall(VecGetLocalSize(r_local_, &n));
      for (PetscInt i = 0; i < n; ++i) ra[i] *= ev.rate_weight;
      for (size_t k = 0; k < effects_.size(); ++k)
        if (!rate_force_[k]) PetscCall(add(k));
    } else {
      for (size_t k = 0; k < effects_.size(); ++k) PetscCall(add(k));
    }
    PetscCall(VecRestoreArray(r_local_, &ra));
    PetscFunctionReturn(0);
  }));
  PetscCall(VecZeroEntries(F));
  PetscCall(VecScatterBegin(scatter_, r_local_, F, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(scatter_, r_local_, F, ADD_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::set_prescribed_residual_rows(Vec x, Vec F) const {
  PetscFunctionBeginUser;
  if (bc_rows_.empty()) PetscFunctionReturn(0);
  const PetscScalar* xg = nullptr;
  PetscScalar* f = nullptr;
  PetscCall(VecGetArrayRead(x, &xg));
  PetscCall(VecGetArray(F, &f));
  for (size_t i = 0; i < bc_rows_.size(); ++i) {
    const PetscInt l = bc_rows_[i] - map_.owned_lo();
    f[l] = xg[l] - bc_values_[i];
  }
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArrayRead(x, &xg));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::assemble_residual(double t, Vec x, Vec F) const {
  PetscFunctionBeginUser;
  PetscCall(assemble_effects_residual(StepEval{StepRule::Endpoint, t, 1.0}, x, F));
  PetscCall(set_prescribed_residual_rows(x, F));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::assemble_effects_jacobian(const StepEval& ev, Vec x, Mat J, CooAssembly* coo, double scale,
                                                double mass_scale) const {
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ev_jacobian_, 0, 0, 0, 0));
  if (coo) coo->begin();
  else PetscCall(MatZeroEntries(J));
  PetscCall(with_context(ev, x, [&](const EvalContext& ctx) -> PetscErrorCode {
    PetscFunctionBeginUser;
    const MatSink sink = coo ? MatSink(coo, scale) : MatSink(J, scale);
    const double rate_scale = scale * ev.rate_weight;
    const MatSink rate_sink = coo ? MatSink(coo, rate_scale) : MatSink(J, rate_scale);
    const MatSink mass_sink = coo ? MatSink(coo, mass_scale) : MatSink(J, mass_scale);
    for (size_t k = 0; k < effects_.size(); ++k) {
      PetscCall(PetscLogEventBegin(effect_events_[k], 0, 0, 0, 0));
      PetscCall(effect_term(*effects_[k], [&] {
        PetscFunctionBeginUser;
        PetscCall(effects_[k]->jacobian(ctx, rate_force_[k] ? rate_sink : sink));
        if (mass_scale != 0.0 && mass_of_[k]) PetscCall(mass_of_[k]->mass(*this, mass_sink));
        if (mass_scale != 0.0 && ev.configuration_mass)
          if (const auto* kin = part_of<ConfigurationKinetic>(*effects_[k])) PetscCall(kin->mass_at(ctx, mass_sink));
        PetscFunctionReturn(0);
      }));
      PetscCall(PetscLogEventEnd(effect_events_[k], 0, 0, 0, 0));
    }
    if (coo)  // every diagonal entry exists (identity rows of supports, pivoting LU)
      for (PetscInt i = map_.owned_lo(); i < map_.owned_hi(); ++i) {
        const PetscScalar zero = 0.0;
        PetscCall(sink.add(1, &i, 1, &i, &zero));
      }
    PetscFunctionReturn(0);
  }));
  if (coo) {
    PetscCall(coo->end(J));
    PetscCall(MatSetOption(J, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  } else {
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  }
  PetscCall(PetscLogEventEnd(ev_jacobian_, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::set_prescribed_jacobian_rows(Mat J) const {
  PetscFunctionBeginUser;
  // Prescribed unknowns: identity rows (F_i = x_i - xbar_i). The columns stay, so J is the exact
  // derivative of F (what -snes_test_jacobian checks); LU does not need symmetry.
  PetscCall(MatZeroRows(J, static_cast<PetscInt>(bc_rows_.size()), bc_rows_.data(), 1.0, nullptr, nullptr));
  PetscFunctionReturn(0);
}

PetscErrorCode Model::assemble_jacobian(double t, Vec x, Mat J) const {
  PetscFunctionBeginUser;
  PetscCall(assemble_effects_jacobian(StepEval{StepRule::Endpoint, t, 1.0}, x, J, J == J_ ? &coo_ : nullptr));
  PetscCall(set_prescribed_jacobian_rows(J));
  PetscFunctionReturn(0);
}

std::vector<double> Model::effect_energies(double t, Vec x) const {
  std::vector<size_t> all(effects_.size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = k;
  return effect_energies(t, x, all);
}

std::vector<double> Model::effect_energies(double t, Vec x, const std::vector<size_t>& which) const {
  std::vector<double> e(which.size(), 0.0);
  SB_CHECK(with_context(StepEval{StepRule::Endpoint, t, 1.0}, x, [&](const EvalContext& ctx) -> PetscErrorCode {
    for (size_t i = 0; i < which.size(); ++i) e[i] = effects_[which[i]]->energy(ctx);
    return 0;
  }));
  MPI_Allreduce(MPI_IN_PLACE, e.data(), static_cast<int>(e.size()), MPI_DOUBLE, MPI_SUM, comm_);
  return e;
}

std::vector<std::pair<int, std::string>> Model::output_names() const {
  std::vector<std::pair<int, std::string>> names;
  for (size_t k = 0; k < effects_.size(); ++k)
    if (const auto* o = part_of<OutputSource>(*effects_[k]))
      for (const std::string& name : o->output_names()) names.emplace_back(static_cast<int>(k), name);
  return names;
}

std::string Model::output_prefix(int k) const {
  const auto* o = part_of<OutputSource>(*effects_.at(static_cast<size_t>(k)));
  return o ? o->output_prefix() : std::string();
}

static const EventSource& event_source(const std::vector<std::unique_ptr<Effect>>& effects, int k) {
  const auto* e = part_of<EventSource>(*effects.at(static_cast<size_t>(k)));
  if (!e) throw std::invalid_argument("effect " + std::to_string(k) + " has no events");
  return *e;
}

std::tuple<std::vector<PetscInt>, std::vector<double>, std::vector<double>> Model::unknown_bounds(
    const std::vector<PetscInt>& except) const {
  std::vector<PetscInt> rows, kept;
  std::vector<double> lo, hi, kept_lo, kept_hi;
  for (const auto& e : effects_)
    if (const auto* x = part_of<ExtraUnknowns>(*e)) x->bounds(*this, rows, lo, hi);
  for (size_t i = 0; i < rows.size(); ++i)
    if (std::find(except.begin(), except.end(), rows[i]) == except.end()) {
      kept.push_back(rows[i]);
      kept_lo.push_back(lo[i]);
      kept_hi.push_back(hi[i]);
    }
  return {kept, kept_lo, kept_hi};
}

std::vector<PetscInt> Model::held_at_start() const {
  std::vector<PetscInt> rows;
  for (const auto& e : effects_)
    if (const auto* x = part_of<ExtraUnknowns>(*e)) x->held_at_start(rows);
  return rows;
}

std::string Model::event_message(int k, int i, double g, const std::string& when) const {
  return event_source(effects_, k).event_message(*this, i, g, when);
}

bool Model::event_fails_run(int k, int i) const {
  return event_source(effects_, k).event_action(i) == EventSource::Action::Fail;
}

std::vector<double> Model::effect_outputs(double t, Vec x) const {
  return effect_outputs(StepEval{StepRule::Endpoint, t, 1.0}, x);
}

std::vector<double> Model::effect_outputs(const StepEval& ev, Vec x) const {
  std::vector<std::pair<const OutputSource*, size_t>> sources;  // and the first value's index
  size_t n = 0;
  for (const auto& e : effects_)
    if (const auto* o = part_of<OutputSource>(*e)) {
      sources.emplace_back(o, n);
      n += o->output_names().size();
    }
  std::vector<double> v(n, 0.0);
  if (n == 0) return v;
  SB_CHECK(with_context(ev, x, [&](const EvalContext& ctx) -> PetscErrorCode {
    for (const auto& [o, first] : sources) o->outputs(ctx, v.data() + first);
    return 0;
  }));
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm_);
  return v;
}

std::vector<double> Model::effect_history() const {
  std::vector<double> v;
  for (const StepHistory* h : history_) v.insert(v.end(), h->history().begin(), h->history().end());
  return v;
}

std::vector<double> Model::gathered_effect_history() const {
  std::vector<double> v;
  for (const StepHistory* h : history_) {
    const std::vector<double>& own = h->history();
    for (size_t i = 0; i < own.size(); ++i) v.push_back(h->owns_history(i) ? own[i] : 0.0);
  }
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, comm_);
  return v;
}

void Model::set_effect_history(const std::vector<double>& values) {
  size_t n = 0;
  for (const StepHistory* h : history_) n += h->history().size();
  if (values.size() != n)
    throw std::invalid_argument("effect history: " + std::to_string(values.size()) + " values for " +
                                std::to_string(n));
  size_t first = 0;
  for (StepHistory* h : history_) {
    const size_t k = h->history().size();
    h->set_history(std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(first),
                                       values.begin() + static_cast<std::ptrdiff_t>(first + k)));
    first += k;
  }
}

void Model::clear_effect_history() {
  for (StepHistory* h : history_) h->set_history(std::vector<double>(h->history().size(), 0.0));
}

void Model::commit_effect_history(const StepEval& ev, Vec x) const {
  if (history_.empty()) return;
  SB_CHECK(with_context(ev, x, [&](const EvalContext& ctx) -> PetscErrorCode {
    for (StepHistory* h : history_) h->commit(ctx);
    return 0;
  }));
}

std::vector<std::pair<int, Reaction>> Model::reactions(const StepEval& ev, Vec x, Vec F_raw, double scale) const {
  std::vector<std::pair<int, Reaction>> out;
  Vec own = nullptr;
  SB_CHECK(VecDuplicate(x, &own));
  const PetscInt lo = map_.owned_lo(), hi = map_.owned_hi();
  const PetscScalar *raw = nullptr, *xa = nullptr, *ow = nullptr;
  auto at = [lo, hi](const PetscScalar* a, PetscInt i) { return i >= lo && i < hi ? a[i - lo] : 0.0; };
  for (size_t k = 0; k < effects_.size(); ++k) {
    const auto* source = dynamic_cast<const ReactionSource*>(effects_[k].get());
    if (!source) continue;
    // the effect's own residual, assembled alone (only for effects that read it)
    SB_CHECK(VecZeroEntries(own));
    if (source->reaction_reads_own()) SB_CHECK(effect_residual(k, ev, x, own));
    SB_CHECK(VecGetArrayRead(F_raw, &raw));
    SB_CHECK(VecGetArrayRead(x, &xa));
    SB_CHECK(VecGetArrayRead(own, &ow));
    const ReactionInput in{[&](PetscInt i) { return at(raw, i); }, [&](PetscInt i) { return scale * at(ow, i); },
                           [&](PetscInt i) { return at(xa, i); }};
    Reaction r;
    source->reaction(*this, in, r);
    SB_CHECK(VecRestoreArrayRead(own, &ow));
    SB_CHECK(VecRestoreArrayRead(x, &xa));
    SB_CHECK(VecRestoreArrayRead(F_raw, &raw));
    out.emplace_back(static_cast<int>(k), r);
  }
  SB_CHECK(VecDestroy(&own));
  // each rank added the terms of its rows: one sum over ranks for all of them
  std::vector<double> buf;
  for (const auto& [k, r] : out) {
    buf.insert(buf.end(), r.force.begin(), r.force.end());
    buf.insert(buf.end(), r.moment.begin(), r.moment.end());
    buf.push_back(r.has_moment ? 1.0 : 0.0);
  }
  MPI_Allreduce(MPI_IN_PLACE, buf.data(), static_cast<int>(buf.size()), MPI_DOUBLE, MPI_SUM, comm_);
  for (size_t j = 0; j < out.size(); ++j) {
    Reaction& r = out[j].second;
    for (int c = 0; c < 3; ++c) {
      r.force[c] = buf[7 * j + c];
      r.moment[c] = buf[7 * j + 3 + c];
    }
    r.has_moment = buf[7 * j + 6] > 0.0;
  }
  return out;
}

std::vector<std::pair<int, Reaction>> Model::static_reactions(double t, Vec x) const {
  Vec F = nullptr;
  SB_CHECK(VecDuplicate(x, &F));
  SB_CHECK(assemble_effects_residual(StepEval{StepRule::Endpoint, t, 1.0}, x, F));
  auto r = reactions(StepEval{StepRule::Endpoint, t, 1.0}, x, F);
  SB_CHECK(VecDestroy(&F));
  return r;
}

std::vector<double> Model::beam_coordinates(int beam_index, Vec x) const {
  const Beam& b = beam(beam_index);
  const int nq = b.coordinates_per_cp();
  std::vector<double> q(static_cast<size_t>(nq * b.n_cp()), 0.0);
  const PetscScalar* a = nullptr;
  SB_CHECK(VecGetArrayRead(x, &a));
  for (int c = 0; c < b.n_cp(); ++c) {
    const PetscInt cp = b.first_cp() + c;
    if (!map_.owns_cp(cp)) continue;
    for (int k = 0; k < nq; ++k) q[static_cast<size_t>(nq * c + k)] = a[map_.q(cp, k) - map_.owned_lo()];
  }
  SB_CHECK(VecRestoreArrayRead(x, &a));
  MPI_Allreduce(MPI_IN_PLACE, q.data(), static_cast<int>(q.size()), MPI_DOUBLE, MPI_SUM, comm_);
  return q;
}

std::vector<PetscInt> Model::director_triads() const {
  std::vector<PetscInt> cps;
  for (const auto& e : effects_)
    if (const auto* h = part_of<NumberingHints>(*e)) h->director_triads(*this, cps);
  std::sort(cps.begin(), cps.end());
  cps.erase(std::unique(cps.begin(), cps.end()), cps.end());
  return cps;
}

void Model::link_effects() {
  for (size_t k = 0; k < effects_.size(); ++k) {
    auto* link = part_of<JointLink>(*effects_[k]);
    if (!link) continue;
    const JointTarget* joint = nullptr;  // the last one before it (constraints come first: model.py)
    for (size_t j = 0; j < k; ++j) {
      const auto* target = part_of<JointTarget>(*effects_[j]);
      if (!target) continue;
      const std::string name = link->linked_name();
      if (name.empty() ? target->joint_name().empty() && target->slider_beam() == link->linked_slider()
                       : target->joint_name() == name)
        joint = target;
    }
    link->link(*this, joint);
  }
}

void Model::resolve_anchors() {
  // Effects with one choice keep it; those with several (rigid joints) are matched to distinct
  // points not otherwise taken (augmenting paths, effects in scene order): a star of joints at
  // a crossing is anchored one joint per end. Where no such matching exists, the first choice.
  std::vector<std::vector<PetscInt>> choices(effects_.size());
  std::vector<PetscInt> holder(static_cast<size_t>(n_cp_total_), -1);  // point -> matched effect
  std::vector<char> taken(static_cast<size_t>(n_cp_total_), 0);        // ... or a single-choice effect's
  for (size_t k = 0; k < effects_.size(); ++k) {
    if (n_extra(*effects_[k]) == 0) continue;
    part_of<ExtraUnknowns>(*effects_[k])->anchor_choices(*this, choices[k]);
    auto& c = choices[k];
    c.erase(std::remove_if(c.begin(), c.end(), [&](PetscInt p) { return p < 0 || p >= n_cp_total_; }), c.end());
    if (c.size() == 1) taken[static_cast<size_t>(c[0])] = 1;
  }
  std::vector<char> visited(static_cast<size_t>(n_cp_total_), 0);
  const std::function<bool(size_t)> augment = [&](size_t k) {
    for (PetscInt p : choices[k]) {
      const auto i = static_cast<size_t>(p);
      if (taken[i] || visited[i]) continue;
      visited[i] = 1;
      if (holder[i] < 0 || augment(static_cast<size_t>(holder[i]))) {
        holder[i] = static_cast<PetscInt>(k);
        return true;
      }
    }
    return false;
  };
  std::vector<PetscInt> anchor(effects_.size(), -1);
  for (size_t k = 0; k < effects_.size(); ++k) {
    if (choices[k].empty()) continue;
    anchor[k] = choices[k][0];
    if (choices[k].size() < 2) continue;
    std::fill(visited.begin(), visited.end(), 0);
    augment(k);
  }
  for (PetscInt p = 0; p < n_cp_total_; ++p)
    if (holder[static_cast<size_t>(p)] >= 0) anchor[static_cast<size_t>(holder[static_cast<size_t>(p)])] = p;
  for (size_t k = 0; k < effects_.size(); ++k)
    if (auto* extras = part_of<ExtraUnknowns>(*effects_[k])) extras->set_anchor(anchor[k]);
}

std::vector<PetscInt> Model::numbering_order() const {
  std::vector<std::pair<PetscInt, PetscInt>> links;
  for (const auto& e : effects_)
    if (const auto* h = part_of<NumberingHints>(*e)) h->reference_couplings(*this, links);
  links.erase(std::remove_if(links.begin(), links.end(), [](const auto& l) { return l.first == l.second; }),
              links.end());
  if (links.empty()) return {};
  // Graph of the control points: each beam a chain, plus the effects' couplings.
  const auto n = static_cast<size_t>(n_cp_total_);
  std::vector<std::vector<PetscInt>> adjacent(n);
  for (const auto& b : beams_)
    for (int c = 0; c + 1 < b.n_cp(); ++c) {
      const PetscInt a = b.first_cp() + c;
      adjacent[static_cast<size_t>(a)].push_back(a + 1);
      adjacent[static_cast<size_t>(a) + 1].push_back(a);
    }
  for (const auto& [a, b] : links) {
    adjacent[static_cast<size_t>(a)].push_back(b);
    adjacent[static_cast<size_t>(b)].push_back(a);
  }
  for (auto& next : adjacent) {
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
  }
  // Cuthill-McKee: breadth first, unvisited neighbours by increasing degree (then index).
  for (auto& next : adjacent)
    std::stable_sort(next.begin(), next.end(), [&](PetscInt u, PetscInt v) {
      return adjacent[static_cast<size_t>(u)].size() < adjacent[static_cast<size_t>(v)].size();
    });
  std::vector<int> mark(n, 0);  // the last search that reached a point (0: none)
  int search = 0;
  const auto breadth_first = [&](PetscInt root, std::vector<PetscInt>& reached) {
    ++search;
    reached.assign(1, root);
    mark[static_cast<size_t>(root)] = search;
    for (size_t head = 0; head < reached.size(); ++head)
      for (PetscInt v : adjacent[static_cast<size_t>(reached[head])])
        if (mark[static_cast<size_t>(v)] != search) {
          mark[static_cast<size_t>(v)] = search;
          reached.push_back(v);
        }
  };
  const std::vector<int> loop_of = loop_structures();
  std::vector<PetscInt> order, component;
  order.reserve(n);
  for (PetscInt first = 0; first < n_cp_total_; ++first) {
    if (mark[static_cast<size_t>(first)] != 0) continue;
    // From the point farthest from the structure's first point (a pseudo-peripheral point);
    // reversed, the order then starts near the first point: a lone beam keeps its own order.
    breadth_first(first, component);
    breadth_first(component.back(), component);
    std::reverse(component.begin(), component.end());
    if (std::any_of(component.begin(), component.end(),
                    [&](PetscInt cp) { return loop_of[static_cast<size_t>(beam_of_cp(cp))] >= 0; }))
      order_along_longest_axis(component);
    order.insert(order.end(), component.begin(), component.end());
  }
  return order;
}

PetscInt Model::largest_cut() const {
  // neighbours: the points a span couples, and the effects' couplings (joints, sliders)
  std::vector<std::pair<PetscInt, PetscInt>> links;
  for (const auto& e : effects_)
    if (const auto* h = part_of<NumberingHints>(*e)) h->reference_couplings(*this, links);
  std::vector<char> at_cut(static_cast<size_t>(n_cp_total_), 0);
  const auto mark = [&](PetscInt a, PetscInt b) {
    if (map_.cp_owner(a) == map_.cp_owner(b)) return;
    at_cut[static_cast<size_t>(a)] = 1;
    at_cut[static_cast<size_t>(b)] = 1;
  };
  for (const auto& beam : beams_)
    for (int c = 0; c < beam.n_cp(); ++c)
      for (int d = 1; d <= span_reach(beam) && c + d < beam.n_cp(); ++d) mark(beam.first_cp() + c, beam.first_cp() + c + d);
  for (const auto& [a, b] : links) mark(a, b);
  std::vector<PetscInt> per_rank(static_cast<size_t>(size_), 0);
  for (PetscInt cp = 0; cp < n_cp_total_; ++cp)
    if (at_cut[static_cast<size_t>(cp)]) ++per_rank[static_cast<size_t>(map_.cp_owner(cp))];
  return *std::max_element(per_rank.begin(), per_rank.end());
}

void Model::order_along_longest_axis(std::vector<PetscInt>& cps) const {
  // A net's breadth-first levels run diagonally across it: a split between two levels cuts
  // about twice the ropes a straight cut does, and every rope cut costs a dozen interface
  // unknowns on either side. Ordered along the axis of its largest extent, the split of the
  // numbering over ranks is a straight cut across the shorter side.
  const auto position = [&](PetscInt cp, int k) {
    const Beam& b = beams_[static_cast<size_t>(beam_of_cp(cp))];
    return b.q_ref()[static_cast<size_t>(b.coordinates_per_cp() * (cp - b.first_cp()) + k)];
  };
  int axis = 0;
  double extent = -1.0;
  for (int k = 0; k < 3; ++k) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (PetscInt cp : cps) {
      lo = std::min(lo, position(cp, k));
      hi = std::max(hi, position(cp, k));
    }
    if (hi - lo > extent * (1.0 + 1e-9)) {
      extent = hi - lo;
      axis = k;
    }
  }
  std::stable_sort(cps.begin(), cps.end(), [&](PetscInt a, PetscInt b) { return position(a, axis) < position(b, axis); });
}

std::vector<char> Model::joined_positions(const std::vector<PetscInt>& order) const {
  std::vector<PetscInt> position(static_cast<size_t>(n_cp_total_));
  for (PetscInt p = 0; p < n_cp_total_; ++p)
    position[static_cast<size_t>(order.empty() ? p : order[static_cast<size_t>(p)])] = p;
  std::vector<char> joined(static_cast<size_t>(n_cp_total_), 0);
  std::vector<PetscInt> cps;
  for (const auto& e : effects_) {
    if (n_extra(*e) == 0) continue;
    cps.clear();
    part_of<ExtraUnknowns>(*e)->anchor_points(*this, cps);
    if (cps.size() < 2) continue;
    PetscInt lo = n_cp_total_, hi = -1;
    for (PetscInt cp : cps) {
      lo = std::min(lo, position[static_cast<size_t>(cp)]);
      hi = std::max(hi, position[static_cast<size_t>(cp)]);
    }
    for (PetscInt p = lo + 1; p <= hi; ++p) joined[static_cast<size_t>(p)] = 1;
  }
  return joined;
}

int Model::beam_of_cp(PetscInt cp) const {
  const auto after = std::upper_bound(beams_.begin(), beams_.end(), cp,
                                      [](PetscInt c, const Beam& b) { return c < b.first_cp(); });
  return static_cast<int>(after - beams_.begin()) - 1;
}

std::vector<int> Model::loop_structures(std::vector<std::pair<PetscInt, PetscInt>>* links_out) const {
  // Links that hold for the whole run (rigid joints; not a sliding joint's, which moves and is
  // ordered by elimination_precedence instead).
  std::vector<std::pair<PetscInt, PetscInt>> links, mine;
  std::vector<std::pair<int, int>> precedence;
  for (const auto& e : effects_) {
    const auto* h = part_of<NumberingHints>(*e);
    if (!h) continue;
    precedence.clear();
    h->elimination_precedence(precedence);
    if (!precedence.empty()) continue;
    mine.clear();
    h->reference_couplings(*this, mine);
    for (const auto& [a, b] : mine)
      if (beam_of_cp(a) != beam_of_cp(b)) links.emplace_back(a, b);
  }
  // Structures: beams joined by the links (union-find); a structure with more links than it
  // needs to be connected has a loop.
  const auto nb = beams_.size();
  std::vector<size_t> parent(nb);
  for (size_t b = 0; b < nb; ++b) parent[b] = b;
  const std::function<size_t(size_t)> root = [&](size_t b) { return parent[b] == b ? b : parent[b] = root(parent[b]); };
  std::vector<long> surplus(nb, 0);  // per root: links minus the links a tree of its beams needs
  for (const auto& [a, b] : links) {
    const size_t ra = root(static_cast<size_t>(beam_of_cp(a))), rb = root(static_cast<size_t>(beam_of_cp(b)));
    if (ra == rb) {
      ++surplus[ra];
    } else {
      parent[rb] = ra;
      surplus[ra] += surplus[rb];
    }
  }
  std::vector<int> out(nb, -1), slot(nb, -1);
  int count = 0;
  for (size_t b = 0; b < nb; ++b) {
    const size_t r = root(b);
    if (surplus[r] == 0) continue;
    if (slot[r] < 0) slot[r] = count++;
    out[b] = slot[r];
  }
  if (links_out) *links_out = std::move(links);
  return out;
}

std::vector<std::vector<PetscInt>> Model::loop_structure_orders() const {
  std::vector<std::pair<PetscInt, PetscInt>> links;
  const std::vector<int> loop_of = loop_structures(&links);
  std::vector<std::vector<PetscInt>> out;
  for (size_t b = 0; b < beams_.size(); ++b) {
    if (loop_of[b] < 0) continue;
    if (out.size() <= static_cast<size_t>(loop_of[b])) out.resize(static_cast<size_t>(loop_of[b]) + 1);
    const Beam& beam = beams_[b];
    for (int c = 0; c < beam.n_cp(); ++c) out[static_cast<size_t>(loop_of[b])].push_back(beam.first_cp() + c);
  }
  // Each loop structure's points in minimum-degree order of their graph: the points a span
  // couples (span_reach) and the links.
  for (auto& points : out) {
    const auto n = static_cast<PetscInt>(points.size());
    std::map<PetscInt, PetscInt> index;
    for (PetscInt i = 0; i < n; ++i) index[points[static_cast<size_t>(i)]] = i;
    std::vector<std::vector<PetscInt>> adjacent(static_cast<size_t>(n));
    for (PetscInt i = 0; i < n; ++i) {
      const PetscInt cp = points[static_cast<size_t>(i)];
      const Beam& beam = beams_[static_cast<size_t>(beam_of_cp(cp))];
      const int reach = span_reach(beam);
      for (int d = -reach; d <= reach; ++d) {
        const PetscInt c = cp - beam.first_cp() + d;
        if (c >= 0 && c < beam.n_cp()) adjacent[static_cast<size_t>(i)].push_back(i + d);
      }
    }
    for (const auto& [a, b] : links) {
      const auto ia = index.find(a), ib = index.find(b);
      if (ia == index.end() || ib == index.end()) continue;
      adjacent[static_cast<size_t>(ia->second)].push_back(ib->second);
      adjacent[static_cast<size_t>(ib->second)].push_back(ia->second);
    }
    std::vector<PetscInt> row_start{0}, cols;
    for (auto& next : adjacent) {
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      cols.insert(cols.end(), next.begin(), next.end());
      row_start.push_back(static_cast<PetscInt>(cols.size()));
    }
    std::vector<PetscScalar> ones(cols.size(), 1.0);
    Mat graph = nullptr;
    IS rows = nullptr, columns = nullptr;
    SB_CHECK(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, n, n, row_start.data(), cols.data(), ones.data(), &graph));
    SB_CHECK(MatGetOrdering(graph, kLoopOrdering, &rows, &columns));
    const PetscInt* perm = nullptr;
    SB_CHECK(ISGetIndices(rows, &perm));
    std::vector<PetscInt> ordered(static_cast<size_t>(n));
    for (PetscInt i = 0; i < n; ++i) ordered[static_cast<size_t>(i)] = points[static_cast<size_t>(perm[i])];
    SB_CHECK(ISRestoreIndices(rows, &perm));
    SB_CHECK(ISDestroy(&rows));
    SB_CHECK(ISDestroy(&columns));
    SB_CHECK(MatDestroy(&graph));
    points = std::move(ordered);
  }
  return out;
}

std::vector<PetscInt> Model::compute_elimination_order() const {
  // Units: a structure of beams joined into loops (a net) is eliminated as one, its points in a
  // fill-reducing order (loop_structure_orders); every other beam is a unit of its own, its
  // points in their order.
  const int nb = static_cast<int>(beams_.size());
  const std::vector<std::vector<PetscInt>> loops = loop_structure_orders();
  std::vector<int> unit_of(static_cast<size_t>(nb), -1);
  std::vector<std::vector<PetscInt>> units;  // each unit's control points in elimination order
  for (size_t l = 0; l < loops.size(); ++l)
    for (PetscInt cp : loops[l]) unit_of[static_cast<size_t>(beam_of_cp(cp))] = -2 - static_cast<int>(l);
  std::vector<int> loop_unit(loops.size(), -1);
  for (int b = 0; b < nb; ++b) {  // units numbered in scene order of their first beam
    int& u = unit_of[static_cast<size_t>(b)];
    if (u <= -2) {
      const auto l = static_cast<size_t>(-2 - u);
      if (loop_unit[l] < 0) {
        loop_unit[l] = static_cast<int>(units.size());
        units.push_back(loops[l]);
      }
      u = loop_unit[l];
      continue;
    }
    u = static_cast<int>(units.size());
    const Beam& beam = beams_[static_cast<size_t>(b)];
    units.emplace_back();
    for (int c = 0; c < beam.n_cp(); ++c) units.back().push_back(beam.first_cp() + c);
  }
  // Unit order: a topological order of the precedence pairs (a slider's beam before its
  // carrier's; stable: scene order otherwise); pairs that form a cycle (beams sliding on each
  // other) are dropped.
  const int nu = static_cast<int>(units.size());
  std::vector<std::vector<int>> after(static_cast<size_t>(nu));
  std::vector<int> indegree(static_cast<size_t>(nu), 0);
  {
    std::vector<std::pair<int, int>> pairs;
    for (const auto& e : effects_)
      if (const auto* h = part_of<NumberingHints>(*e)) h->elimination_precedence(pairs);
    for (auto& [first, then] : pairs) {
      first = unit_of[static_cast<size_t>(first)];
      then = unit_of[static_cast<size_t>(then)];
    }
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(), [](const auto& pr) { return pr.first == pr.second; }),
                pairs.end());
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (const auto& [first, then] : pairs) {
      after[static_cast<size_t>(first)].push_back(then);
      ++indegree[static_cast<size_t>(then)];
    }
  }
  // Extras whose pivots run along beams (pivots_along) wait until those beams' units are placed.
  struct Waiting {
    PetscInt first, end;
    std::vector<int> units;
    bool placed;
  };
  std::vector<Waiting> waiting;
  std::vector<char> moved(static_cast<size_t>(map_.global_size()), 0);
  for (const auto& e : effects_) {
    const auto* h = part_of<NumberingHints>(*e);
    const PetscInt n = n_extra(*e);
    if (!h || n == 0) continue;
    std::vector<int> beams;
    h->pivots_along(beams);
    if (beams.empty()) continue;
    const PetscInt first = part_of<ExtraUnknowns>(*e)->extra_offset();
    Waiting w{first, first + n, {}, false};
    for (int b : beams) w.units.push_back(unit_of[static_cast<size_t>(b)]);
    waiting.push_back(std::move(w));
    for (PetscInt i = first; i < first + n; ++i) moved[static_cast<size_t>(i)] = 1;
  }
  // Each slot: a control point's block and the extras anchored at it; then the extras without
  // an anchor.
  std::vector<PetscInt> order;
  order.reserve(static_cast<size_t>(map_.global_size()));
  std::vector<bool> placed(static_cast<size_t>(nu), false);
  for (int done = 0; done < nu; ++done) {
    int next = -1;
    for (int u = 0; u < nu && next < 0; ++u)
      if (!placed[static_cast<size_t>(u)] && indegree[static_cast<size_t>(u)] == 0) next = u;
    if (next < 0)  // a cycle: take the first unplaced unit
      for (int u = 0; u < nu && next < 0; ++u)
        if (!placed[static_cast<size_t>(u)]) next = u;
    placed[static_cast<size_t>(next)] = true;
    for (int then : after[static_cast<size_t>(next)]) --indegree[static_cast<size_t>(then)];
    for (PetscInt cp : units[static_cast<size_t>(next)])
      for (PetscInt i = 0; i < map_.slot_size(cp); ++i)
        if (!moved[static_cast<size_t>(map_.q(cp, 0) + i)]) order.push_back(map_.q(cp, 0) + i);
    for (Waiting& w : waiting) {
      if (w.placed || !std::all_of(w.units.begin(), w.units.end(), [&](int u) { return placed[static_cast<size_t>(u)]; }))
        continue;
      for (PetscInt i = w.first; i < w.end; ++i) order.push_back(i);
      w.placed = true;
    }
  }
  for (PetscInt i = map_.extra(0); i < map_.global_size(); ++i)
    if (!moved[static_cast<size_t>(i)]) order.push_back(i);
  return order;
}

}  // namespace slidebeam
