// SPDX-License-Identifier: MIT
#include "util/cost_log.hpp"

#include <petscdm.h>
#include <petscis.h>
#include <petscksp.h>
#include <petscmat.h>
#include <petscsf.h>
#include <petscsnes.h>
#include <petscvec.h>

#include <ctime>
#include <vector>

namespace slidebeam {
namespace {

struct EventClock {
  double start = 0.0;
  double total = 0.0;
  long calls = 0;
  int depth = 0;  // nested begins of the same event count once, as in PETSc's log
};

std::vector<EventClock>& clocks() {
  static std::vector<EventClock> c;
  return c;
}

bool whole_log = false;

double now() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

PetscErrorCode clock_begin(PetscLogEvent e, int, PetscObject, PetscObject, PetscObject, PetscObject) {
  std::vector<EventClock>& c = clocks();
  if (static_cast<size_t>(e) >= c.size()) c.resize(static_cast<size_t>(e) + 64);
  if (c[e].depth++ == 0) c[e].start = now();
  return 0;
}

PetscErrorCode clock_end(PetscLogEvent e, int, PetscObject, PetscObject, PetscObject, PetscObject) {
  EventClock& c = clocks()[e];
  if (--c.depth == 0) {
    c.total += now() - c.start;
    ++c.calls;
  }
  return 0;
}

}  // namespace

PetscErrorCode start_cost_log() {
  PetscFunctionBeginUser;
  // (the default handler first: it sets up the event registry that every handler reads)
  PetscCall(PetscLogDefaultBegin());
  for (const char* name : {"-log_view", "-log_all", "-log_trace", "-log_summary", "-log_view_memory", "-log_sync",
                           "-log_perfstubs", "-log_mpe", "-log_nvtx"}) {
    PetscBool set = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, name, &set));
    if (set) {
      whole_log = true;
      PetscFunctionReturn(0);
    }
  }
  for (PetscClassId id : {VEC_CLASSID, PETSCSF_CLASSID, MAT_CLASSID, IS_CLASSID, DM_CLASSID, SNES_CLASSID,
                          SNESLINESEARCH_CLASSID, KSP_CLASSID, PC_CLASSID})
    PetscCall(PetscLogEventDeactivateClass(id));
  // the linear solves' row: KSPSolve and the factorisations (PCSetUp, logged apart from it)
  for (const char* name : {"KSPSolve", "PCSetUp"}) {
    PetscLogEvent e = -1;
    PetscCall(PetscLogEventGetId(name, &e));
    if (e >= 0) PetscCall(PetscLogEventActivate(e));
  }
  PetscCall(PetscLogSet(clock_begin, clock_end));
  PetscFunctionReturn(0);
}

std::pair<double, long> event_stats(const std::string& name) {
  PetscLogEvent e = -1;
  if (PetscLogEventGetId(name.c_str(), &e) != 0 || e < 0) return {0.0, 0};
  if (whole_log) {
    PetscEventPerfInfo info{};
    if (PetscLogEventGetPerfInfo(0, e, &info) != 0) return {0.0, 0};
    return {info.time, info.count};
  }
  const std::vector<EventClock>& c = clocks();
  if (static_cast<size_t>(e) >= c.size()) return {0.0, 0};
  return {c[e].total, c[e].calls};
}

}  // namespace slidebeam
