// SPDX-License-Identifier: MIT
/// @file The compiled module slidebeam._core: a thin layer over the C++ core. Defaults,
/// validation and documentation for users live in the pure-Python package.

#include "petsc_casters.hpp"

#include "kernels/bspline.hpp"
#include "model/model.hpp"
#include "solvers/equilibrium_solver.hpp"
#include "solvers/solver_options.hpp"
#include "solvers/static_solver.hpp"
#include "solvers/time_integrator.hpp"
#include "time/load_stepper.hpp"
#include "time/stepper.hpp"
#include "util/cost_log.hpp"
#include "util/petsc_check.hpp"
#include "util/stop_signal.hpp"
#include "io/beam_series.hpp"
#include "io/csv_format.hpp"
#include "io/record_writer.hpp"

#include <mpi4py/mpi4py.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace slidebeam;

namespace {
MPI_Comm comm_from_py(py::object comm) {
  if (comm.is_none()) return PETSC_COMM_WORLD;
  if (import_mpi4py() != 0) throw std::runtime_error("could not import mpi4py");
  if (!PyObject_TypeCheck(comm.ptr(), &PyMPIComm_Type)) throw py::type_error("comm must be an mpi4py communicator");
  return *PyMPIComm_Get(comm.ptr());
}

kernels::StrainMeasure strain_from(const std::string& s) {
  if (s == "simo-reissner") return kernels::StrainMeasure::SimoReissner;
  if (s == "seed") return kernels::StrainMeasure::Seed;
  throw std::invalid_argument("unknown strain measure '" + s + "'");
}
py::list reaction_list(const std::vector<std::pair<int, Reaction>>& rs) {
  py::list out;
  for (const auto& [k, r] : rs)
    out.append(py::make_tuple(k, py::make_tuple(r.force[0], r.force[1], r.force[2]),
                              r.has_moment ? py::object(py::make_tuple(r.moment[0], r.moment[1], r.moment[2])) : py::none()));
  return out;
}

kernels::Quadrature quadrature_from(const std::string& s) {
  if (s == "full") return kernels::Quadrature::Full;
  if (s == "reduced") return kernels::Quadrature::Reduced;
  if (s == "assumed_strain") return kernels::Quadrature::AssumedStrain;
  throw std::invalid_argument("unknown quadrature '" + s + "'");
}

py::array_t<double> as_array(const std::vector<double>& v, py::ssize_t rows, py::ssize_t cols) {
  py::array_t<double> a({rows, cols});
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}
/// sample_beam's dict for several beams, one after the other in each array (collective: the
/// control points are gathered on every rank).
py::dict sampled_fields(const Model& s, const std::vector<int>& beams, Vec x, std::optional<Vec> v, int samples_per_span) {
  BeamSamples all;
  for (int beam : beams) {
    const auto q = s.beam_coordinates(beam, x);
    const auto qd = v ? s.beam_coordinates(beam, *v) : std::vector<double>{};
    const BeamSamples b = s.beam(beam).sample(q, qd, samples_per_span);
    for (auto [to, from] : {std::pair{&all.s, &b.s}, {&all.position, &b.position}, {&all.velocity, &b.velocity},
                            {&all.d1, &b.d1}, {&all.d2, &b.d2}, {&all.d3, &b.d3}, {&all.force, &b.force},
                            {&all.moment, &b.moment}, {&all.strain, &b.strain}, {&all.tension, &b.tension}})
      to->insert(to->end(), from->begin(), from->end());
  }
  const auto n = static_cast<py::ssize_t>(all.s.size());
  py::dict d;
  d["s"] = as_array(all.s, n, 1).attr("reshape")(n);
  for (auto [name, vec] : {std::pair{"position", &all.position}, {"velocity", &all.velocity}, {"d1", &all.d1},
                           {"d2", &all.d2}, {"d3", &all.d3}, {"force", &all.force}, {"moment", &all.moment}})
    d[name] = as_array(*vec, n, 3);
  d["strain"] = as_array(all.strain, n, 6);
  d["tension"] = as_array(all.tension, n, 1).attr("reshape")(n);
  return d;
}
}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "slidebeam C++ core (director beams, effects, PETSc assembly)";

  py::register_exception<PetscFailure>(m, "PetscFailure", PyExc_RuntimeError);
  py::register_exception<SolverFailure>(m, "SolverFailure", PyExc_RuntimeError);
  // args (key, message): the scene layer turns it into an error naming the table entry and key
  static py::exception<ParamError> param_error(m, "ParamError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr ptr) {
    try {
      if (ptr) std::rethrow_exception(ptr);
    } catch (const ParamError& e) {
      PyErr_SetObject(param_error.ptr(), py::make_tuple(e.key, e.what()).ptr());
    }
  });

  m.def(
      "bspline_basis",
      [](int n_spans, double xi) {
        const auto b = bspline::basis(n_spans, xi);
        return py::make_tuple(b.span, b.N, b.dN, b.ddN);
      },
      py::arg("n_spans"), py::arg("xi"), "(span, N[3], dN/dxi[3], d2N/dxi2[3]) at xi in [0,1]");
  m.def("python_repr", &io::python_repr, py::arg("x"), "repr(x) of a float, written by the core (tests)");
  m.def(
      "csv_rows",
      [](py::array_t<double, py::array::c_style | py::array::forcecast> values, const std::string& kinds,
         const std::vector<std::string>& text) {
        if (values.ndim() != 2 || static_cast<size_t>(values.shape(1)) != kinds.size())
          throw std::invalid_argument("csv_rows: values must be rows x len(kinds)");
        return io::csv_rows(values.data(), static_cast<size_t>(values.shape(0)), kinds, text);
      },
      py::arg("values"), py::arg("kinds"), py::arg("text") = std::vector<std::string>{},
      "CSV lines of a table: kinds[j] 'f' (repr of the float), 'i' (integer) or 's' (the row's text)");
  m.def("greville", &bspline::greville, py::arg("n_spans"), py::arg("a"));
  m.def(
      "hermite_basis",
      [](double x, double Le) {
        const auto b = kernels::ancf::hermite(x, Le);
        return py::make_tuple(b.S, b.dS, b.ddS);
      },
      py::arg("x"), py::arg("Le"),
      "ANCF cable: (S[4], dS/dx[4], d2S/dx2[4]) at x in [0, Le], order (r_1, r'_1, r_2, r'_2)");

  py::class_<Model>(m, "Model")
      .def(py::init([](py::object comm) { return std::make_unique<Model>(comm_from_py(comm)); }),
           py::arg("comm") = py::none())
      .def(
          "add_beam",
          [](Model& self, const std::string& name, int n_spans, double length, const std::map<std::string, double>& sec,
             const std::string& strain, const std::string& quadrature,
             py::array_t<double, py::array::c_style | py::array::forcecast> q_ref, const std::string& formulation,
             double unstretched_length) {
            BeamSpec spec;
            spec.name = name;
            if (formulation == "ancf") spec.formulation = Formulation::Ancf;
            else if (formulation != "director")
              throw std::invalid_argument("unknown formulation '" + formulation + "' (director, ancf)");
            spec.n_spans = n_spans;
            spec.length = length;
            auto get = [&](const char* k) {
              auto it = sec.find(k);
              if (it == sec.end()) throw std::invalid_argument(std::string("section lacks '") + k + "'");
              return it->second;
            };
            spec.section = {get("EA"), get("kGA2"), get("kGA3"), get("GJ"), get("EI2"), get("EI3"),
                            get("rhoA"), get("rhoI2"), get("rhoI3")};
            spec.strain = strain_from(strain);
            spec.quadrature = quadrature_from(quadrature);
            spec.q_ref.assign(q_ref.data(), q_ref.data() + q_ref.size());
            spec.unstretched_length = unstretched_length;
            return self.add_beam(spec);
          },
          py::arg("name"), py::arg("n_spans"), py::arg("length"), py::arg("section"), py::arg("strain"),
          py::arg("quadrature"), py::arg("q_ref"), py::arg("formulation") = "director", py::arg("unstretched_length") = 0.0,
          "add a beam: director (q_ref: (spans+2) x 12) or ANCF cable (q_ref: (spans+1) x 6, r and r'); "
          "unstretched_length > 0: a rope's stress-free state is straight, of that length (q_ref: where it starts)")
      .def(
          "add_body",
          [](Model& self, const std::string& name, double mass, const std::array<double, 9>& euler,
             const std::array<double, 12>& q_ref) {
            BeamSpec spec;
            spec.name = name;
            spec.formulation = Formulation::Rigid;
            spec.n_spans = 0;
            spec.length = 0.0;
            spec.mass = mass;
            spec.euler = euler;
            spec.q_ref.assign(q_ref.begin(), q_ref.end());
            return self.add_beam(spec);
          },
          py::arg("name"), py::arg("mass"), py::arg("euler"), py::arg("q_ref"),
          "add a rigid body: one control point (q_ref: its centre of mass phi and body frame d1, d2, d3), its mass "
          "and its Euler tensor int X X^T dm in the body frame (row-major); returns its index among the beams")
      .def(
          "add_effect",
          [](Model& self, const std::string& type, const std::map<std::string, double>& num,
             const std::map<std::string, std::vector<double>>& vec, const std::map<std::string, std::string>& str) {
            EffectParams p{num, vec, str};
            return self.add_effect(type, p);
          },
          py::arg("type"), py::arg("num") = std::map<std::string, double>{},
          py::arg("vec") = std::map<std::string, std::vector<double>>{},
          py::arg("str") = std::map<std::string, std::string>{})
      .def(
          "finalize", [](Model& m) { finalize_from_options(m); },
          "number and distribute the model, spread over the ranks as -sb_serial_below and -sb_serial_above_cut say")
      .def_property_readonly("finalized", &Model::finalized)
      .def_property_readonly("x", &Model::x, "global unknowns (petsc4py Vec, shared with the core)")
      .def_property_readonly("residual_vector", &Model::residual_vector)
      .def_property_readonly("jacobian", &Model::jacobian)
      .def("assemble_residual",
           [](const Model& s, double t, Vec x, Vec F) { SB_CHECK(s.assemble_residual(t, x, F)); })
      .def("assemble_jacobian",
           [](const Model& s, double t, Vec x, Mat J) { SB_CHECK(s.assemble_jacobian(t, x, J)); })
      .def("effect_energies", [](const Model& s, double t, Vec x) { return s.effect_energies(t, x); })
      .def("set_reference_state", [](const Model& s, Vec x) { s.set_reference_state(x); })
      .def("project_directors", [](const Model& s, Vec x) { s.project_directors(x); })
      .def("extrapolate", [](const Model& s, Vec x, Vec x_last, Vec x_prev, double alpha) {
             s.extrapolate(x, x_last, x_prev, alpha);
           }, py::arg("x"), py::arg("x_last"), py::arg("x_prev"), py::arg("alpha"),
           "load-step predictor: linear in every unknown but the director triads, which turn on")
      .def("sample_beam",
           [](const Model& s, int beam, Vec x, std::optional<Vec> v, int samples_per_span) {
             return sampled_fields(s, {beam}, x, v, samples_per_span);
           },
           py::arg("beam"), py::arg("x"), py::arg("v") = py::none(), py::arg("samples_per_span") = 4,
           "fields sampled along a beam (dict of arrays: s, position, velocity, d1, d2, d3, strain, force, "
           "moment, tension); collective")
      .def("sample_beams", &sampled_fields, py::arg("beams"), py::arg("x"), py::arg("v") = py::none(),
           py::arg("samples_per_span") = 4,
           "sample_beam's fields of several beams, one after the other in each array; collective")
      .def("static_reactions",
           [](const Model& s, double t, Vec x) { return reaction_list(s.static_reactions(t, x)); }, py::arg("t"), py::arg("x"),
           "[(effect index, force, moment or None)] of supports and joints in equilibrium at x (collective)")
      .def("effect_outputs", py::overload_cast<double, Vec>(&Model::effect_outputs, py::const_), py::arg("t"),
           py::arg("x"),
           "the values of the effects that have outputs (a contact's force and length in contact) at x, "
           "named by output_names() (collective)")
      .def("output_names", &Model::output_names, "(effect index, name) of each effect_outputs() value")
      .def("effect_history", &Model::gathered_effect_history,
           "what effects keep from step to step besides the unknowns (friction's anchors on a contact), every "
           "entry from the rank that owns it (collective): what a checkpoint keeps")
      .def("set_effect_history", &Model::set_effect_history, py::arg("values"),
           "replace the effects' history (from effect_history)")
      .def("unknown_bounds", &Model::unknown_bounds, py::arg("except_rows") = std::vector<PetscInt>{},
           "(rows, lo, hi): the extra unknowns a continuation keeps within bounds (sliders on their carriers), "
           "but the rows given")
      .def("held_at_start", &Model::held_at_start,
           "rows the equilibrium start of a dynamic run holds where they are (held sliders)")
      .def("event_message", &Model::event_message, py::arg("effect"), py::arg("index"), py::arg("value"),
           py::arg("when"), "the run's message for an event: what happened (the indicator's value at the end "
           "state), `when`, and what the run does")
      .def("event_fails_run", &Model::event_fails_run, py::arg("effect"), py::arg("index"),
           "whether the event ends the run as failed (else stopped)")
      .def("output_prefix", &Model::output_prefix, py::arg("effect"),
           "the history prefix of an effect's outputs ('': its scene label)")
      .def_property_readonly("ghost_count", &Model::ghost_count, "unknowns ghosted on this rank (owned included)")
      .def_property_readonly("cut_points", &Model::cut_points,
                             "the most control points a rank holds next to another rank's in the split over all "
                             "ranks (0: owned by one rank from the start); above -sb_serial_above_cut rank 0 owns "
                             "the model")
      .def_property_readonly("ghost_rebuilds", &Model::ghost_rebuilds,
                             "how often the ghost set was rebuilt because a sliding joint moved")
      .def("elimination_order", &Model::elimination_order,
           "permutation of the unknowns (new position -> old index) of the serial factorisation")
      .def("extra_offset",
           [](const Model& s, int effect) -> PetscInt {
             const auto* extras = part_of<ExtraUnknowns>(*s.effects().at(static_cast<size_t>(effect)));
             return extras ? extras->extra_offset() : -1;
           },
           py::arg("effect"), "global index of an effect's first extra unknown (-1: it has none)")
      .def("extra_values", [](const Model& s, int effect, Vec x) { return s.extra_values(effect, x); },
           py::arg("effect"), py::arg("x"), "values of an effect's extra unknowns (s, multipliers) on every rank (collective)")
      .def("beam_coordinates",
           [](const Model& s, int beam, Vec x) {
             const auto q = s.beam_coordinates(beam, x);
             return as_array(q, s.beam(beam).n_cp(), s.beam(beam).coordinates_per_cp());
           },
           "control point coordinates on every rank (collective): n_cp x 12 (phi, d1, d2, d3) for a "
           "director beam")
      .def("beam_first_cp", [](const Model& s, int beam) { return s.beam(beam).first_cp(); }, py::arg("beam"),
           "global index of a beam's first control point")
      .def("cp_unknowns", [](const Model& s, PetscInt cp) {
             if (cp < 0 || cp >= s.n_cp_total())
               throw py::index_error("control point " + std::to_string(cp) + " out of range: the model has " +
                                     std::to_string(s.n_cp_total()));
             const DofMap& m = s.dof_map();
             return py::make_tuple(m.q(cp, 0), m.n_coordinates(cp));
           }, py::arg("cp"), "(global index of the first unknown, number of coordinates) of a control point")
      .def_property_readonly("prescribed_rows", &Model::prescribed_rows,
                             "prescribed (support) unknowns owned by this rank, global indices");

  py::class_<SolveResult>(m, "SolveResult")
      .def_readonly("reason", &SolveResult::reason)
      .def_readonly("iterations", &SolveResult::iterations)
      .def_readonly("linear_iterations", &SolveResult::linear_iterations)
      .def_readonly("residual_norm", &SolveResult::residual_norm)
      .def_property_readonly("converged", &SolveResult::converged)
      .def_property_readonly("reason_name", [](const SolveResult& r) { return reason_name(r.reason); });

  py::class_<StaticSolver>(m, "StaticSolver")
      .def(py::init<Model&>(), py::arg("model"), py::keep_alive<1, 2>())
      .def(
          "solve",
          [](StaticSolver& s, double t, const std::string& attempts) {
            using A = ManifoldNewton::Attempts;
            if (attempts == "all") return s.solve(t, A::all);
            if (attempts == "first") return s.solve(t, A::first);
            if (attempts == "fallbacks") return s.solve(t, A::fallbacks);
            throw py::value_error("attempts: 'all', 'first' or 'fallbacks', got '" + attempts + "'");
          },
          py::arg("t"), py::arg("attempts") = "all",
          "Newton from the model's x at load time t: 'first' (Newton on the director manifold alone, "
          "ended by a zero pivot or a third of the iteration limit), 'fallbacks' (only what follows it: "
          "Newton's multipliers, then plain Newton, on the full system) or 'all'")
      .def_property("time", &StaticSolver::time, &StaticSolver::set_time)
      .def_property_readonly("snes", &StaticSolver::snes, "the SNES (petsc4py, shared with the core)");

  m.def("effect_specs_json", [] { return EffectRegistry::instance().specs_json(); },
        "every registered effect type: its scene table, parameters (kind, unit, default, bounds), role in "
        "the energy balance, as JSON");
  m.def("install_stop_handlers", &install_stop_handlers,
        "SIGINT/SIGTERM: the first is recorded (see stop_signal), the second ends the process at once");
  m.def("stop_signal", py::overload_cast<>(&stop_signal), "the signal received since install_stop_handlers, or 0");
  m.def("start_cost_log", [] { SB_CHECK(start_cost_log()); },
        "the event log of the cost table on: its events only, by a light handler (PETSc's whole log when a "
        "-log_* option asks for it)");
  m.def("event_stats", &event_stats, py::arg("name"),
        "(wall time in s, calls) of a logged event on this rank so far; (0, 0) if it was never registered");
  m.def(
      "options_left",
      [] {
        // petsc4py (3.18) has no PetscOptionsLeftGet: the options no one has queried so far
        PetscInt n = 0;
        char** names = nullptr;
        char** values = nullptr;
        SB_CHECK(PetscOptionsLeftGet(nullptr, &n, &names, &values));
        py::list out;
        for (PetscInt i = 0; i < n; ++i)
          out.append(py::make_tuple(std::string(names[i]), values[i] ? py::object(py::str(values[i])) : py::none()));
        SB_CHECK(PetscOptionsLeftRestore(nullptr, &n, &names, &values));
        return out;
      },
      "[(name without the leading dash, value or None)] of the options database's entries never queried");
  m.def("plain_option_copies", &plain_option_copies,
        "[(copy, plain option)], names without the dash: the plain solver options (-snes_rtol) copied under "
        "a solver's prefix (sb_static_snes_rtol) when it was created");
  m.attr("SOLVER_PREFIXES") = py::dict(py::arg("static") = kStaticPrefix, py::arg("equilibrium") = kEquilibriumPrefix,
                                       py::arg("time_steps") = kStepPrefix, py::arg("mass") = kMassPrefix);
  m.attr("SERIAL_ABOVE_CUT") = PartitionPolicy{}.serial_above_cut;
  // -sb_serial_below's default: the CLI decides by it before any model exists
  m.attr("SERIAL_BELOW") = PartitionPolicy{}.serial_below;
  // -sb_statics_on_rank_0's default: the CLI and Simulation.settle decide by it
  m.attr("STATICS_ON_RANK_0") = static_cast<bool>(CoreOptions{}.statics_on_rank_0);
  m.attr("EQUILIBRIUM_ON_RANK_0") = static_cast<bool>(CoreOptions{}.equilibrium_on_rank_0);

  py::class_<EquilibriumResult>(m, "EquilibriumResult")
      .def_readonly("converged", &EquilibriumResult::converged)
      .def_readonly("pseudo_steps", &EquilibriumResult::pseudo_steps)
      .def_readonly("block_steps", &EquilibriumResult::block_steps,
                    "continuation steps solved on the parallel block path (a distributed static start)")
      .def_readonly("full_system_steps", &EquilibriumResult::full_system_steps,
                    "continuation steps that needed the pivoting LU of the whole saddle-point system")
      .def_readonly("cut_steps", &EquilibriumResult::cut_steps,
                    "continuation steps whose solve failed and was retried with half the pseudo-step")
      .def_readonly("newton_iterations", &EquilibriumResult::newton_iterations)
      .def_readonly("residual0", &EquilibriumResult::residual0)
      .def_readonly("residual", &EquilibriumResult::residual)
      .def_readonly("polished", &EquilibriumResult::polished)
      .def_readonly("at_roundoff", &EquilibriumResult::at_roundoff)
      .def_readonly("interrupted", &EquilibriumResult::interrupted, "the signal that stopped it, or 0");

  py::class_<EquilibriumSolver>(m, "EquilibriumSolver")
      .def(py::init<Model&>(), py::arg("model"), py::keep_alive<1, 2>())
      .def("set_held", &EquilibriumSolver::set_held, py::arg("rows"),
           "global unknowns kept at their current values (held sliding coordinates)")
      .def("set_bounds", &EquilibriumSolver::set_bounds, py::arg("rows"), py::arg("lo"), py::arg("hi"),
           "global unknowns that must stay within [lo, hi] (free sliders' s within their carriers): a "
           "continuation step or polish leaving the range is rejected")
      .def("solve", &EquilibriumSolver::solve, py::arg("t"), py::arg("h0"), py::arg("rtol") = 1e-10,
           py::arg("max_steps") = 200,
           "pseudo-transient continuation to static equilibrium from the model's current state (collective)")
      .def_property_readonly("snes", &EquilibriumSolver::snes);

  py::class_<TimeIntegrator>(m, "TimeIntegrator")
      .def(py::init([](Model& model, const std::string& kind, double beta, double gamma, double alpha,
                       double dissipation) {
             IntegratorParams p;
             p.kind = integrator_from(kind);
             p.beta = beta;
             p.gamma = gamma;
             p.alpha = alpha;
             p.dissipation = dissipation;
             return std::make_unique<TimeIntegrator>(model, p);
           }),
           py::arg("model"), py::arg("kind"), py::arg("beta") = 0.25, py::arg("gamma") = 0.5, py::arg("alpha") = 0.0,
           py::arg("dissipation") = 0.0,
           py::keep_alive<1, 2>())
      .def("initialize", [](TimeIntegrator& s, double t, Vec x, Vec v) { s.initialize(t, x, v); },
           py::arg("t"), py::arg("x"), py::arg("v"))
      .def_property_readonly(
          "velocity_projection",
          [](const TimeIntegrator& s) {
            const auto& p = s.velocity_projection();
            py::dict d;
            d["solved"] = p.solved;
            d["failed"] = p.failed;
            d["projected"] = p.projected;
            d["size"] = p.size;
            d["change"] = p.change;
            d["largest"] = p.largest;
            d["kinetic_before"] = p.kinetic_before;
            d["kinetic_after"] = p.kinetic_after;
            return d;
          },
          "what initialize did to the initial velocity: its projection onto the constraints in the mass "
          "metric (dict: solved, failed, projected, size and change in the mass norm, largest change of a "
          "coordinate's rate, kinetic energy before and after)")
      .def("step", &TimeIntegrator::step, py::arg("h"))
      .def_property_readonly("time", &TimeIntegrator::time)
      .def_property_readonly("x", &TimeIntegrator::x, "state x_n (petsc4py Vec, shared with the core)")
      .def_property_readonly("v", &TimeIntegrator::v)
      .def_property_readonly("a", &TimeIntegrator::a)
      .def_property_readonly("sliding_rate", &TimeIntegrator::sliding_rate, "(s_n - s_n-1) / h at sliding coordinates")
      .def_property_readonly("v_prev", &TimeIntegrator::v_prev, "v_{n-1} (predictor memory)")
      .def_property_readonly("h_prev", &TimeIntegrator::h_prev, "the last step size (predictor memory)")
      .def_property_readonly("pivoting_lu", &TimeIntegrator::pivoting_lu, "time steps use the pivoting LU")
      .def_property_readonly("pivoting_lu_steps", &TimeIntegrator::pivoting_lu_steps,
                             "converged steps solved on the pivoting LU after a fall-back")
      .def("restore", &TimeIntegrator::restore, py::arg("t"), py::arg("h_prev"), py::arg("pivoting_lu"),
           py::arg("segment_start") = 0.0, py::arg("segment_steps") = 0,
           "resume from a checkpoint (the state vectors already loaded)")
      .def_property_readonly("energy_flows",
                             [](const TimeIntegrator& s) {
                               py::list out;
                               for (const auto& f : s.energy_flows())
                                 out.append(py::make_tuple(f.effect, energy_role_name(f.role), f.work));
                               return out;
                             },
                             "(effect index, role, work done on the structure since the start) of every effect "
                             "whose work is counted")
      .def("set_energy_flows", &TimeIntegrator::set_energy_flows, py::arg("work"),
           "restore the summed works (a restart), in the order of energy_flows")
      .def("forget_jacobian", &TimeIntegrator::forget_jacobian,
           "build a fresh step Jacobian at the next step (as after a restart)")
      .def_property_readonly("time_segment", &TimeIntegrator::time_segment,
                             "(start, steps) of the current run of equal steps h_prev: t = start + steps h_prev")
      .def_property_readonly("mass", &TimeIntegrator::mass)
      .def_property_readonly("snes", &TimeIntegrator::snes)
      .def_property_readonly("jacobian_evaluations", &TimeIntegrator::jacobian_evaluations)
      .def_property_readonly(
          "parallel_solves",
          [](const TimeIntegrator& s) {
            const auto& p = s.parallel_solves();
            return py::dict(py::arg("blocks") = p.blocks, py::arg("corrected") = p.corrected,
                            py::arg("krylov") = p.krylov, py::arg("coupled_rows") = p.coupled_rows);
          },
          "step Jacobians solved on the Schwarz path (several ranks) by one block application (blocks), "
          "one application plus the coupling correction (corrected) and GMRES (krylov); coupled_rows: the most "
          "rows of a rank coupled to another rank")
      .def_property_readonly("jacobian", [](const TimeIntegrator& s) { return s.jacobian(); }, "the step Jacobian (petsc4py)")
      .def("kinetic_energy", &TimeIntegrator::kinetic_energy)
      .def("motion",
           [](const TimeIntegrator& s) {
             const auto m = s.motion();
             return py::make_tuple(m.kinetic, m.momenta.linear, m.momenta.angular);
           },
           "(kinetic energy, linear momentum, angular momentum about the origin) of the current state")
      .def("constraint_residual", &TimeIntegrator::constraint_residual)
      .def("reactions", [](TimeIntegrator& s) { return reaction_list(s.reactions()); },
           "[(effect index, force, moment or None)] of supports and joints over the last step (collective)")
      .def("effect_outputs", &TimeIntegrator::effect_outputs,
           "Model.effect_outputs over the last step (rates over it), or at t_n before a step (collective)")
      .def("prepare_step", &TimeIntegrator::prepare_step, py::arg("h"))
      .def("step_residual", [](TimeIntegrator& s, Vec x, Vec F) { SB_CHECK(s.step_residual(x, F)); },
           py::arg("x"), py::arg("F"), "F = the residual of the prepared step (prepare_step) at x")
      .def("last_step_residual", &TimeIntegrator::last_step_residual, py::arg("F"),
           "F = the residual of the last converged step at the current state x (its norm is that step's "
           "residual_norm); RuntimeError before the first step")
      .def("step_jacobian", [](TimeIntegrator& s, Vec x, Mat J) { SB_CHECK(s.step_jacobian(x, J)); });


  py::class_<StepAdvance>(m, "StepAdvance", "how one Stepper.advance ended")
      .def_property_readonly("status",
                             [](const StepAdvance& a) { return to_string(a.status); },
                             "'accepted', 'cut' (Newton failed: the next step is half as long), 'failed' (failed at "
                             "dt_min) or 'event' (an indicator crossed: the step shortened to it is the run's last)")
      .def_readonly("result", &StepAdvance::result, "the accepted step's solve, or the failed attempt's")
      .def_readonly("h", &StepAdvance::h, "its step size")
      .def_readonly("rejected_attempts", &StepAdvance::rejected_attempts)
      .def_readonly("newton_iterations", &StepAdvance::newton_iterations, "over every attempt")
      .def_readonly("wall_time", &StepAdvance::wall_time, "seconds in the step's first attempt")
      .def_readonly("event", &StepAdvance::event, "'event': index into Stepper.events")
      .def_readonly("event_value", &StepAdvance::event_value, "'event': the indicator at the state it ends in")
      .def_readonly("event_step_taken", &StepAdvance::event_step_taken,
                    "'event': a shortened step was taken (else the state is at t_n)")
      .def_readonly("local_error", &StepAdvance::local_error,
                    "error control: the step's error in units of its tolerance (<= 1 accepted; -1: none)");

  py::class_<Stepper>(m, "Stepper", "step control of a dynamic run: sizes, cuts and events (src/time/stepper.hpp)")
      .def(py::init<Model&, TimeIntegrator&, double, double>(), py::arg("model"), py::arg("integrator"),
           py::arg("dt"), py::arg("dt_min"), py::keep_alive<1, 2>(), py::keep_alive<1, 3>())
      .def("advance", &Stepper::advance, py::arg("t_end"), "take the next step towards t_end (collective)")
      .def_property("dt", &Stepper::dt, &Stepper::set_dt, "the step size the next advance tries")
      .def(
          "set_error_control",
          [](Stepper& s, double rtol, double atol, double dt_max, double span, double constant) {
            s.set_error_control({rtol, atol, dt_max, span, constant});
          },
          py::arg("rtol"), py::arg("atol"), py::arg("dt_max"), py::arg("span"), py::arg("constant"),
          "choose the steps by their local error from now on (src/time/error_control.hpp): rtol on "
          "directions, atol [m] on points and sliding coordinates, for the error at the end of a run "
          "of duration span; constant: the scheme's C")
      .def("restart_error_estimate", &Stepper::restart_error_estimate,
           "begin the local error estimate afresh at the current state (checkpoints)")
      .def_property_readonly(
          "events",
          [](const Stepper& s) {
            py::list out;
            for (const auto& e : s.events()) out.append(py::make_tuple(e.effect, e.index, e.scale));
            return out;
          },
          "(model effect index, indicator index, scale) of every event indicator");
  py::class_<LoadAdvance>(m, "LoadAdvance", "how one LoadStepper.advance ended")
      .def_property_readonly("status",
                             [](const LoadAdvance& a) { return to_string(a.status); },
                             "'accepted', 'cut' (the next load step is half as long), 'failed' (failed at the "
                             "smallest increment) or 'event' (a slider beyond its carrier's end: back at the last step)")
      .def_readonly("result", &LoadAdvance::result, "the step's solve (iterations over every attempt)")
      .def_readonly("t", &LoadAdvance::t, "the load time attempted")
      .def_readonly("continued", &LoadAdvance::continued, "the pseudo-transient continuation was tried")
      .def_readonly("by_continuation", &LoadAdvance::by_continuation, "the continuation solved it")
      .def_readonly("event", &LoadAdvance::event, "'event': the model effect whose indicator crossed")
      .def_readonly("event_index", &LoadAdvance::event_index, "'event': that effect's indicator")
      .def_readonly("event_value", &LoadAdvance::event_value, "'event': its value at the rejected solution");

  py::class_<LoadStepper>(m, "LoadStepper",
                          "step control of a static run: load increments, cuts and the continuation "
                          "(src/time/load_stepper.hpp)")
      .def(py::init<Model&, StaticSolver&, double, int, int>(), py::arg("model"), py::arg("solver"),
           py::arg("t_end"), py::arg("steps"), py::arg("max_cuts"), py::keep_alive<1, 2>(), py::keep_alive<1, 3>())
      .def("advance", &LoadStepper::advance, "take the next load step (collective)")
      .def_property_readonly("time", &LoadStepper::time, "the load time of the last converged step")
      .def_property_readonly("done", &LoadStepper::done, "the last converged step is at t_end")
      .def("set_predictor", &LoadStepper::set_predictor, py::arg("on"),
           "start each load step from the secant predictor (default true)")
      .def("set_continuation_bounds", &LoadStepper::set_continuation_bounds, py::arg("rows"), py::arg("lo"),
           py::arg("hi"), "global unknowns the continuation keeps within [lo, hi]")
      .def_property_readonly("cuts", &LoadStepper::cuts, "load steps cut so far")
      .def_property_readonly("continuations", &LoadStepper::continuations,
                             "load steps that needed the continuation so far");
  py::class_<io::RecordWriter>(m, "RecordWriter",
                               "records of an XDMF time series written into an existing HDF5 file by a "
                               "background thread, one dataset /<field>/<record> per array")
      .def(py::init<const std::string&, std::size_t>(), py::arg("path"), py::arg("compact_bytes") = 32 << 10)
      .def(
          "add",
          [](io::RecordWriter& w, long record, const py::dict& fields) {
            std::vector<io::RecordField> copies;
            copies.reserve(fields.size());
            for (auto [key, value] : fields) {
              io::RecordField f;
              f.name = py::cast<std::string>(key);
              py::array a = py::cast<py::array>(value);
              f.is_int = a.dtype().is(py::dtype::of<std::int32_t>());
              if (!f.is_int)
                a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
              else
                a = py::array_t<std::int32_t, py::array::c_style>::ensure(a);
              for (py::ssize_t k = 0; k < a.ndim(); ++k) f.shape.push_back(a.shape(k));
              const auto* data = static_cast<const unsigned char*>(a.data());
              f.bytes.assign(data, data + a.nbytes());
              copies.push_back(std::move(f));
            }
            w.add(record, std::move(copies));
          },
          py::arg("record"), py::arg("fields"),
          "hand over a record: {field: array} (float64, or int32), copied; returns at once")
      .def("set_text_file", &io::RecordWriter::set_text_file, py::arg("path"), py::arg("end_mark"), py::arg("tail"),
           py::arg("head") = std::string(),
           "the file append_text writes into, the offset where its closing tags (tail) begin; end_mark 0: "
           "created as head + text + tail at the first append_text")
      .def("append_text", [](io::RecordWriter& w, py::bytes text) { w.append_text(std::string(text)); }, py::arg("text"),
           "after the records so far: flush, then write text + tail at the text file's end mark; returns at once")
      .def_property_readonly("error", &io::RecordWriter::error, "the first failure's message so far, '' if none")
      .def("wait", &io::RecordWriter::wait, py::call_guard<py::gil_scoped_release>(),
           "block until every record is written and the file flushed; the first failure's message or ''")
      .def("close", &io::RecordWriter::close, py::call_guard<py::gil_scoped_release>(),
           "wait, then close the file; the first failure's message or ''")
      .def_property_readonly("pending", &io::RecordWriter::pending, "records handed over, not yet written")
      .def_property_readonly("failed_record", &io::RecordWriter::failed_record,
                             "the record whose writing failed first, -1 if none");

  py::class_<io::BeamSeriesSampler>(m, "BeamSeriesSampler",
                                    "a record of the beams' XDMF series, sampled into the record writer")
      .def(py::init([](std::vector<int> beams, int k, py::array_t<double, py::array::c_style | py::array::forcecast> ref,
                       std::vector<double> half2, std::vector<double> half3) {
             std::vector<double> r(ref.data(), ref.data() + ref.size());
             return io::BeamSeriesSampler(std::move(beams), k, std::move(r), std::move(half2), std::move(half3));
           }),
           py::arg("beams"), py::arg("samples_per_span"), py::arg("reference"), py::arg("half2"), py::arg("half3"))
      .def(
          "record",
          [](const io::BeamSeriesSampler& s, const Model& model, Vec x, std::optional<Vec> v, io::RecordWriter* writer,
             long record) {
            std::vector<double> position;
            auto fields = s.sample(model, x, v ? *v : nullptr, position);
            if (writer) writer->add(record, std::move(fields));
            return as_array(position, static_cast<py::ssize_t>(s.points()), 3);
          },
          py::arg("model"), py::arg("x"), py::arg("v"), py::arg("writer"), py::arg("record"),
          "sample the state (collective) and hand the record to writer (None: sample only); returns the "
          "sample points (n x 3)")
      .def(
          "fields",
          [](const io::BeamSeriesSampler& s, const Model& model, Vec x, std::optional<Vec> v) {
            std::vector<double> position;
            py::dict d;
            for (auto& f : s.sample(model, x, v ? *v : nullptr, position)) {
              std::vector<py::ssize_t> shape(f.shape.begin(), f.shape.end());
              py::array_t<double> a(shape);
              std::memcpy(a.mutable_data(), f.bytes.data(), f.bytes.size());
              d[py::str(f.name)] = a;
            }
            return py::make_tuple(d, as_array(position, static_cast<py::ssize_t>(s.points()), 3));
          },
          py::arg("model"), py::arg("x"), py::arg("v"), "({field: array} as record writes them, the sample points); collective");
}
