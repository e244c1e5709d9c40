// SPDX-License-Identifier: MIT
#include "solvers/solver_options.hpp"

#include "model/model.hpp"

#include "util/petsc_check.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <sstream>

namespace slidebeam {

namespace {

struct Copy {
  std::string copy;    // prefixed name, without dash
  std::string source;  // the plain name
  std::string value;   // the value copied
};

std::vector<Copy>& copies() {
  static std::vector<Copy> c;
  return c;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool is_number(const std::string& s) {
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end && *end == '\0' && !s.empty();
}

/// The options database as (lower-case name without dash -> value), read without marking
/// anything used (PetscOptionsGetAll).
PetscErrorCode database(std::map<std::string, std::string>* out) {
  PetscFunctionBeginUser;
  char* all = nullptr;
  PetscCall(PetscOptionsGetAll(nullptr, &all));
  std::istringstream in(all ? all : "");
  PetscCall(PetscFree(all));
  std::vector<std::string> tokens;
  for (std::string tok; in >> tok;) tokens.push_back(tok);
  for (size_t i = 0; i < tokens.size(); ++i) {
    const std::string& tok = tokens[i];
    if (tok.size() < 2 || tok[0] != '-' || is_number(tok)) continue;
    std::string value;
    if (i + 1 < tokens.size() && (tokens[i + 1][0] != '-' || is_number(tokens[i + 1]))) value = tokens[++i];
    (*out)[lower(tok.substr(1))] = value;
  }
  PetscFunctionReturn(0);
}

bool plain_family(const std::string& name) {
  for (const char* f : kPlainFamilies)
    if (name.rfind(f, 0) == 0) return true;
  return false;
}

PetscErrorCode inherit_plain_options(const std::string& prefix) {
  PetscFunctionBeginUser;
  std::map<std::string, std::string> db;
  PetscCall(database(&db));
  auto& reg = copies();
  // Our earlier copies under this prefix follow their plain options.
  for (auto it = reg.begin(); it != reg.end();) {
    if (it->copy.rfind(prefix, 0) != 0) {
      ++it;
      continue;
    }
    const auto cur = db.find(it->copy);
    const auto src = db.find(it->source);
    if (cur == db.end() || cur->second != it->value) {  // changed or removed by someone else: not ours now
      it = reg.erase(it);
      continue;
    }
    if (src == db.end()) {
      PetscCall(PetscOptionsClearValue(nullptr, ("-" + it->copy).c_str()));
      db.erase(cur);
      it = reg.erase(it);
      continue;
    }
    if (src->second != it->value) {
      PetscCall(PetscOptionsSetValue(nullptr, ("-" + it->copy).c_str(), src->second.empty() ? nullptr : src->second.c_str()));
      it->value = src->second;
      db[it->copy] = src->second;
    }
    ++it;
  }
  for (const auto& [name, value] : db) {
    if (!plain_family(name)) continue;
    const std::string copy = prefix + name;
    if (db.count(copy)) continue;  // given under the prefix (or copied before): that one holds
    PetscCall(PetscOptionsSetValue(nullptr, ("-" + copy).c_str(), value.empty() ? nullptr : value.c_str()));
    reg.push_back({copy, name, value});
  }
  PetscFunctionReturn(0);
}

/// One -sb_ option: its name, help and the value it sets (exactly one of flag, integer, real).
struct CoreOption {
  const char* name;
  const char* help;
  PetscBool* flag = nullptr;
  PetscInt* integer = nullptr;
  PetscReal* real = nullptr;
  PetscBool* given = nullptr;  ///< set when the option is on the command line (or nullptr)
};
CoreOption flag(const char* name, const char* help, PetscBool* value, PetscBool* given = nullptr) {
  return {name, help, value, nullptr, nullptr, given};
}
CoreOption integer(const char* name, const char* help, PetscInt* value) { return {name, help, nullptr, value}; }
CoreOption real(const char* name, const char* help, PetscReal* value) { return {name, help, nullptr, nullptr, value}; }

PetscErrorCode read_core_options(MPI_Comm comm, CoreOptions* o) {
  PetscFunctionBeginUser;
  const CoreOption table[] = {
      flag("-sb_condense_directors",
           "Newton with director triads condensed to 6 unknowns per control point, updated by "
           "rotations (false: plain Newton on the full system)",
           &o->condense_directors),
      flag("-sb_exponential_update",
           "statics: turn the triads by the rotation exp(w) of the Newton step (false: the closest "
           "orthonormal frame of d + w x d)",
           &o->exponential_update),
      flag("-sb_corotate_jacobian",
           "time steps with -sb_jacobian_reuse: rotate the reused condensed Jacobian with the triads",
           &o->corotate_jacobian),
      flag("-sb_jacobian_reuse",
           "time steps: modified Newton, the Jacobian and its LU kept across iterations and steps "
           "(false: full Newton)",
           &o->jacobian_reuse, &o->jacobian_reuse_set),
      flag("-sb_newton_by_cost",
           "time steps without -sb_jacobian_reuse: modified or full Newton, each measured over a "
           "stretch of steps and the cheaper one run (iterations + 4 per Jacobian)",
           &o->newton_by_cost),
      real("-sb_jacobian_reuse_rate",
           "modified Newton: a fresh Jacobian once an iteration reduces |F| by less than this factor",
           &o->jacobian_reuse_rate),
      flag("-sb_backtrack",
           "time steps, Newton on the director manifold: halve a step that makes |F| grow, up to 6 "
           "times",
           &o->backtrack),
      flag("-sb_full_newton_after_rebuild",
           "modified Newton: finish a step with full Newton once its Jacobian had to be rebuilt",
           &o->full_newton_after_rebuild),
      flag("-sb_floor_stop",
           "time steps: stop Newton once |F| is near the roundoff floor measured on earlier steps",
           &o->floor_stop),
      flag("-sb_project_velocity",
           "project the initial velocities onto the constraints (false: as given, sliding rates 0)",
           &o->project_velocity),
      flag("-sb_schwarz",
           "time steps: GMRES + Schwarz on the model's subdomains (default: on more than one rank "
           "unless a KSP, PC or factor package is given)",
           &o->schwarz, &o->schwarz_set),
      integer("-sb_schwarz_overlap",
              "Schwarz: 0 block Jacobi, one block per rank; 1 restricted additive Schwarz with overlap",
              &o->schwarz_overlap),
      flag("-sb_schwarz_exact",
           "block Jacobi on coupled ranks: one application made exact by the correction on the "
           "ranks' interface unknowns, where no rank has more than -sb_schwarz_exact_max_interface "
           "coupled rows (false: GMRES)",
           &o->schwarz_exact),
      integer("-sb_schwarz_exact_max_interface",
              "-sb_schwarz_exact: the exact correction only while no rank has more rows coupled to "
              "another rank (its set-up solves once per interface unknown)",
              &o->schwarz_exact_max_interface),
      flag("-sb_statics_on_rank_0",
           "static analyses under mpirun on rank 0 alone by the serial solver: slidebeam run runs a "
           "static analysis there; Simulation.solve_static hands its state to every rank (false: "
           "on all ranks, MUMPS on the whole system)",
           &o->statics_on_rank_0),
      flag("-sb_equilibrium_on_rank_0",
           "the static start of a distributed dynamic run on rank 0 alone by the serial solver, "
           "bit for bit the serial run's (false: on all ranks, see -sb_equilibrium_blocks)",
           &o->equilibrium_on_rank_0),
      flag("-sb_equilibrium_blocks",
           "a distributed static start: its continuation steps on the time steps' block solve "
           "(condensed exact blocks, the coupling correction), a plain Newton polish where one is "
           "needed on MUMPS (false: MUMPS throughout)",
           &o->equilibrium_blocks),
      integer("-sb_serial_below",
              "a model with fewer unknowns is owned and solved by rank 0 alone (0: always distribute)",
              &o->partition.serial_below),
      integer("-sb_serial_above_cut",
              "a model whose split over ranks leaves a rank more control points next to another "
              "rank's is owned and solved by rank 0 alone (0: no limit)",
              &o->partition.serial_above_cut),
      flag("-sb_adapt_monitor",
           "error-controlled steps ([analysis] adapt): print each step's error estimate and the unknown that set it",
           &o->adapt_monitor),
  };
  PetscOptionsBegin(comm, nullptr, "slidebeam core options (docs/petsc-options.md)", "slidebeam");
  for (const CoreOption& c : table) {
    if (c.flag) PetscCall(PetscOptionsBool(c.name, c.help, "", *c.flag, c.flag, c.given));
    if (c.integer) PetscCall(PetscOptionsInt(c.name, c.help, "", *c.integer, c.integer, c.given));
    if (c.real) PetscCall(PetscOptionsReal(c.name, c.help, "", *c.real, c.real, c.given));
  }
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode set_solver_prefix(SNES snes, const char* prefix) {
  PetscFunctionBeginUser;
  PetscCall(inherit_plain_options(prefix));
  PetscCall(SNESSetOptionsPrefix(snes, prefix));
  PetscFunctionReturn(0);
}

bool solver_option_set(const char* prefix, const char* name) {
  PetscBool has = PETSC_FALSE;
  SB_CHECK(PetscOptionsHasName(nullptr, prefix, name, &has));
  return has == PETSC_TRUE;
}

std::vector<std::pair<std::string, std::string>> plain_option_copies() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& c : copies()) out.emplace_back(c.copy, c.source);
  return out;
}

void finalize_from_options(Model& model) {
  if (!model.finalized()) model.finalize(core_options(model.comm()).partition);
}

CoreOptions core_options(MPI_Comm comm) {
  CoreOptions o;
  SB_CHECK(read_core_options(comm, &o));
  return o;
}

}  // namespace slidebeam
