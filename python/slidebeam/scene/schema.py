# SPDX-License-Identifier: MIT
"""The scene's own tables, described: every key parse.py accepts, with its meaning, SI unit,
default and allowed values.

Data only. The effect tables ([[support]], [[load]], [gravity], [[damping]], ...) are described
by the core's registry (effect_specs.json, read by effect_tables.py); the tables here are the ones
parse.py parses by hand. `scripts/scene_reference.py` writes both into docs/scene-reference.md,
and tests/python/test_scene_schema.py checks that every key parse.py accepts is described here
and that every key described here is accepted.

A key's `default` is TOML text when the default is a value ("static", 10, 1.0), prose when it
depends on other keys ("dt / 16"), and "required" when the key must be given.
"""
from __future__ import annotations

from dataclasses import dataclass

REQUIRED = "required"


@dataclass(frozen=True)
class Key:
    key: str
    meaning: str
    unit: str = ""          # SI unit ("" for dimensionless numbers, names and switches)
    default: str = ""       # TOML text, prose, REQUIRED, or "" (optional, no default: left out)
    allowed: str = ""       # allowed values or bounds ("" : any value of the key's type)


@dataclass(frozen=True)
class Table:
    name: str               # the table's path: "analysis", "beam.section", "time_function"
    header: str             # how a scene writes it: "[analysis]", "[[beam]]", "section = { ... }"
    meaning: str
    keys: tuple[Key, ...]
    variants: tuple[tuple[str, tuple[str, ...]], ...] = ()  # (variant, its keys) where `type` picks them


SCENE = Table("scene", "[scene]", "The scene's name and description (optional table).", (
    Key("name", "name of the scene: the default output folder is out/<name>", "", "the file's name without .toml"),
    Key("description", "free text describing the scene (the run does not use it; scripts/stability_table.py "
                        "lists the hard scenes by it)", "", "\"\""),
))

ANALYSIS = Table("analysis", "[analysis]", "What is solved: load stepping (static) or time stepping (dynamic).", (
    Key("type", "static: load stepping, the loads follow their time functions at t = t_end k / steps; "
                "dynamic: time integration from t = 0 to t_end", "", '"static"', '"static", "dynamic"'),
    Key("steps", "number of load steps (static)", "", "10", "integer >= 1"),
    Key("t_end", "end time (dynamic); the pseudo-time of the last load step (static)", "s", "1.0", "> 0"),
    Key("dt", "time step (dynamic); under adapt the run starts at 1/100 of it", "s",
        "required when type = \"dynamic\" (adapt: 1e-4 t_end)", "> 0 (adapt: <= adapt.dt_max)"),
    Key("adapt", "error-controlled steps, a sub-table (see [analysis.adapt]); false: fixed steps", "", "fixed steps dt",
        "table; type = \"dynamic\" only"),
    Key("dt_min", "smallest step the step control may cut to after a failed step", "s", "dt / 16 (adapt: 1e-6 dt)",
        "> 0, <= dt"),
    Key("integrator", "time integrator (dynamic)", "", '"energy-momentum"',
        '"energy-momentum", "midpoint", "newmark", "hht"'),
    Key("newmark_beta", "Newmark's beta (newmark and hht)", "", "0.25 (hht: (1 - hht_alpha)^2 / 4)", "> 0"),
    Key("newmark_gamma", "Newmark's gamma (newmark and hht)", "", "0.5 (hht: 1/2 - hht_alpha)",
        ">= 1/2 (hht: >= 1/2 - hht_alpha)"),
    Key("hht_alpha", "HHT's alpha: numerical damping of high frequencies", "", "-0.1", "[-1/3, 0]"),
    Key("em_dissipation", "xi of the energy-decaying energy-momentum variant: the averaged strain becomes "
                          "mean + xi/2 (eps_n+1 - eps_n); 0 is the conserving scheme", "", "0.0",
        "[0, 1]; integrator = \"energy-momentum\" only"),
    Key("start", "dynamic: start from the drawn state, or from the static equilibrium under the loads at t = 0 "
                 "(pseudo-transient continuation, then at rest)", "", '"reference"',
        '"reference", "equilibrium" (type = "dynamic" only)'),
))

BEAM = Table("beam", "[[beam]]", "One beam or cable. Give its reference centre line as exactly one of start + end, "
             "polyline or arc.", (
    Key("name", "the beam's name, used by every other table and by --set (beam.<name>.spans=32)", "", REQUIRED,
        "non-empty, unique"),
    Key("start", "first point of a straight beam", "m", "", "3 numbers; with end"),
    Key("end", "last point of a straight beam", "m", "", "3 numbers, not equal to start"),
    Key("polyline", "a centre line through these points (director beams; the spline interpolates them at "
                    "the Greville abscissae)", "m", "", "array of >= 2 points"),
    Key("arc", "a circular arc, a sub-table (see [beam.arc]; director beams)", "", "", "table"),
    Key("d2", "direction of the section axis d2 at the start; made orthogonal to the axis and carried along "
              "the centre line", "", "the coordinate axis after the axis' largest component (x -> y, y -> z, "
              "z -> x), made orthogonal", "3 numbers, not parallel to the axis; director beams"),
    Key("spans", "knot spans (director beam: quadratic B-spline, spans + 2 control points) or elements "
                 "(ANCF cable: spans + 1 nodes)", "", REQUIRED, "integer >= 1"),
    Key("quadrature", "stiffness quadrature: full (3 Gauss points per span), reduced (2), assumed_strain "
                      "(membrane and shear strains at the knots: no locking in slender beams and ropes; "
                      "docs/theory.md); auto: assumed_strain where a span's EA h^2/EI >= 300, else full",
        "", '"auto"', '"auto", "full", "reduced", "assumed_strain"; director beams'),
    Key("strain", "strain measure: the objective director strains of Betsch & Steinmann, or the seed paper's "
                  "Green-Lagrange-type measure", "", '"simo-reissner"', '"simo-reissner", "seed"; director beams'),
    Key("formulation", "director: geometrically exact director beam; ancf: gradient-deficient ANCF cable "
                       "(no torsion, shear or rotary inertia; a straight stress-free state: drawn straight, or an arc or a polyline with unstretched_length)", "", '"director"',
        '"director", "ancf"'),
    Key("unstretched_length", "a rope's length at rest: its stress-free state is then straight and untwisted, of "
                              "this length, and the drawn centre line only where it starts (a rope drawn straight "
                              "but longer than its chord starts as a circular arc of this length sagging along "
                              "gravity); with start = \"equilibrium\" the run finds the hanging shape "
                              "(docs/user-guide.md, \"Ropes by their unstretched length\")", "m", "the drawn length: the drawing is stress free",
        "> 0; not with pretension; strain = \"simo-reissner\" (director beams)"),
    Key("pretension", "the tension the rope has where drawn (straight: its unstretched length is the drawn "
                      "length over the stretch at which the element's law gives this tension), stress-free "
                      "straight and untwisted", "N", "",
        ">= 0, < EA; not with unstretched_length; strain = \"simo-reissner\" (director beams)"),
    Key("horizontal_tension", "a rope hung under [gravity] between the ends of its straight drawing, given by its "
                              "horizontal tension: its unstretched length is the elastic catenary's with it",
        "N", "", "> 0; one of unstretched_length, pretension, horizontal_tension, sag; needs [gravity] and mass"),
    Key("sag", "the same, given by its sag: the vertical distance between the chord and the rope at mid-span", "m",
        "", "> 0; one of unstretched_length, pretension, horizontal_tension, sag; needs [gravity] and mass"),
    Key("velocity", "initial velocity, a rigid translation (dynamic)", "m/s", "[0.0, 0.0, 0.0]", "3 numbers"),
    Key("angular_velocity", "initial angular velocity, a rigid rotation about rotation_center (dynamic)", "rad/s",
        "[0.0, 0.0, 0.0]", "3 numbers"),
    Key("rotation_center", "the point angular_velocity turns about (beams welded together and turning as one "
                           "need the same centre)", "m", "the beam's first point", "3 numbers"),
    Key("section", "the cross-section, a sub-table (see [beam.section])", "", REQUIRED, "table"),
))

BODY = Table("body", "[[body]]", "A rigid body (a cabin, hook block, platform, buoy, falling block): a mass with "
             "rotary inertia, joined to beams by [[joint]] entries at points of the body (docs/user-guide.md, "
             "\"Rigid bodies\").", (
    Key("name", "the body's name, used by [[joint]] and [output].track", "", REQUIRED,
        "non-empty, unique among beams and bodies"),
    Key("mass", "its mass", "kg", REQUIRED, "> 0"),
    Key("inertia", "its inertia tensor about the centre of mass, in the body's axes: the moments [Ixx, Iyy, Izz], "
                   "or with the products of inertia [Ixx, Iyy, Izz, Ixy, Iyz, Izx]", "kg m^2", REQUIRED,
        "3 or 6 numbers: positive definite, moments meeting the triangle inequality (Ixx <= Iyy + Izz, ...)"),
    Key("position", "its centre of mass", "m", REQUIRED, "3 numbers"),
    Key("orientation", "a rotation vector turning the global axes into the body's axes (angle in rad times the "
                       "unit axis)", "rad", "[0.0, 0.0, 0.0]", "3 numbers"),
    Key("velocity", "initial velocity of its centre of mass (dynamic)", "m/s", "[0.0, 0.0, 0.0]", "3 numbers"),
    Key("angular_velocity", "initial angular velocity (dynamic)", "rad/s", "[0.0, 0.0, 0.0]", "3 numbers"),
))

ADAPT = Table("analysis.adapt", "adapt = { rtol, atol, dt_max }",
              "Steps chosen by their local error so that the error at t_end stays near the tolerance "
              "(docs/theory.md, \"Adaptive steps\"); the run starts at 1/100 of dt and grows by the estimate.", (
    Key("rtol", "tolerance on directions (directors, ANCF slopes), and atol's scale", "", REQUIRED, "in (0, 1)"),
    Key("atol", "tolerance on points and sliding coordinates", "m", "rtol x the longest beam's length", "> 0"),
    Key("dt_max", "largest step", "s", "t_end / 10", "> 0"),
))

ARC = Table("beam.arc", "arc = { center, radius, normal, start, angle }",
            "A circular arc as a beam's reference centre line (director beams).", (
    Key("center", "centre of the circle", "m", REQUIRED, "3 numbers"),
    Key("radius", "radius", "m", REQUIRED, "> 0"),
    Key("normal", "normal of the arc's plane; the arc turns about it (right hand)", "", REQUIRED, "nonzero vector"),
    Key("start", "first point of the arc", "m", REQUIRED, "at distance radius from center, in the plane"),
    Key("angle", "angle swept (negative: the other way round)", "degree", REQUIRED, "nonzero, |angle| <= 360"),
))

SECTION = Table("beam.section", "section = { ... }",
                "Section resultants, from a shape and a material or given explicitly (not both). A director "
                "beam needs EA, kGA (or kGA2 and kGA3), GJ, EI2, EI3; an ANCF cable EA and EI. Masses are needed "
                "for dynamics (and for gravity: rhoA).", (
    Key("shape", "cross-section shape; b is its width along d2, h along d3 (an ANCF cable needs b == h)", "", "",
        '"rectangle", "circle"'),
    Key("b", "rectangle: width along d2", "m", "", "> 0"),
    Key("h", "rectangle: height along d3", "m", "", "> 0"),
    Key("r", "circle: radius", "m", "", "> 0"),
    Key("E", "Young's modulus", "Pa", "required with shape", "> 0"),
    Key("nu", "Poisson's ratio (G = E / (2 (1 + nu))); director beams", "", "required with shape", "(-1, 0.5)"),
    Key("rho", "density", "kg/m^3", "0.0", ">= 0"),
    Key("k", "shear correction factor; director beams", "", "5/6 (rectangle), 0.9 (circle)", "> 0"),
    Key("EA", "axial stiffness", "N", "required without shape", "> 0"),
    Key("kGA", "shear stiffness, both directions (director beams)", "N", "required unless kGA2 and kGA3", "> 0"),
    Key("kGA2", "shear stiffness along d2 (director beams)", "N", "kGA", "> 0"),
    Key("kGA3", "shear stiffness along d3 (director beams)", "N", "kGA", "> 0"),
    Key("GJ", "torsional stiffness (director beams)", "N m^2", "required without shape", "> 0"),
    Key("EI2", "bending stiffness about d2 (director beams)", "N m^2", "required without shape", "> 0"),
    Key("EI3", "bending stiffness about d3 (director beams)", "N m^2", "required without shape", "> 0"),
    Key("EI", "bending stiffness, every axis (ANCF cables only)", "N m^2", "required without shape", "> 0"),
    Key("rhoA", "mass per length", "kg/m", "0.0", ">= 0 (> 0 in a dynamic analysis)"),
    Key("rhoI2", "rotary inertia per length, rho I2 (director beams)", "kg m", "0.0", ">= 0"),
    Key("rhoI3", "rotary inertia per length, rho I3 (director beams)", "kg m", "0.0", ">= 0"),
))

OUTPUT = Table("output", "[output]", "What a run writes to its output folder (docs/user-guide.md, \"Output files\").", (
    Key("every", "record every this many steps (history.csv, XDMF series); the last step is always recorded",
        "", "1 (static); max(1, floor(steps / 200)) (dynamic: 200 to 399 records); under adapt: see interval",
        "integer >= 1"),
    Key("interval", "dynamic runs, instead of every: record the first step that reaches each multiple of this "
                    "time (the steps are not shortened to land on it); the last step is always recorded", "s",
        "t_end / 200 under [analysis] adapt without every; else none (records by every)", "> 0"),
    Key("track", "points whose positions go to history.csv, an array of { beam, at } (see [output].track)", "",
        "the end of every beam", "array of tables"),
    Key("samples_per_span", "points per knot span (element) in the XDMF series and final_configuration.csv",
        "", "8", "integer >= 1"),
    Key("checkpoint_every", "write checkpoint.h5 (and bring the .xdmf up to date) every this many steps; "
                            "0: only when the run ends", "", "0", "integer >= 0"),
    Key("xdmf", "write beams.xdmf/.h5 (and sliders.xdmf/.h5, masses.xdmf/.h5, bodies.xdmf/.h5) and the ParaView script view.py", "", "true", "true, false"),
    Key("warn_size_gb", "warn before a run whose results are estimated larger; 0: never", "GB", "1.0", ">= 0"),
))

TRACK = Table("output.track", "track = [{ beam = ..., at = ... }, ...]", "One tracked point: a beam's point, or a "
              "body's centre of mass ({ body = ... }).", (
    Key("beam", "the beam's name", "", "required unless body", "a beam's name"),
    Key("at", "the point: \"start\", \"end\" or an arc length", "m", "required with beam", '"start", "end" or [0, L]'),
    Key("body", "a [[body]]'s name: its centre of mass", "", "", "a body's name; not with beam or at"),
))

PETSC = Table("petsc", "[petsc]", "PETSc options for the run, written without the leading dash "
              "(snes_rtol = 1e-10, sb_jacobian_reuse = true); true gives a flag, false leaves it out. "
              "Command-line options after -- win over the options file, and the options file over this table.", (
    Key("options_file", "a file of PETSc options (one \"-option value\" a line), relative to the scene; "
                        "without it <scene>.opts beside the scene is read if present", "", "", "a file name"),
    Key("<option>", "any PETSc option (or one of slidebeam's -sb_* options), e.g. snes_rtol = 1e-10", "", "",
        "string, number or boolean"),
))

TIME_FUNCTION = Table("time_function", "time_function = { type = ..., ... }",
                      "A multiplier f(t) of a load, of gravity, of a flow or of a prescribed motion. ramp: 0 "
                      "until t0, linear to 1 at t1, then 1; smooth_ramp: the same with the blend "
                      "10u^3 - 15u^4 + 6u^5 (u from 0 at t0 to 1 at t1), whose rate and acceleration are "
                      "continuous (a driven support started without a jolt); hat: 0 until t0, up to 1 at t1, down to 0 at t2; "
                      "step: 1 on [t0, t1), else 0; sine: offset + amplitude sin(2 pi frequency t + phase), its "
                      "amplitude faded in by the smooth blend over its first `ramp` seconds if given (a motion "
                      "that starts from rest); "
                      "table: piecewise linear through (times, values), constant beyond the ends; spline: the cubic "
                      "spline through (times, values) with zero slope at both ends, constant beyond them: rate "
                      "and acceleration continuous (a winch or a support driven along a planned path without "
                      "a jolt at every point of the table).", (
    Key("type", "the kind of function", "", REQUIRED,
        '"constant", "ramp", "smooth_ramp", "hat", "step", "sine", "table", "spline"'),
    Key("t0", "ramp, smooth_ramp, hat, step: where it starts", "s", "0.0", ""),
    Key("t1", "ramp, smooth_ramp: reaches 1; hat: its peak; step: ends", "s", "required (step: inf, never ends)", "> t0"),
    Key("t2", "hat: back to 0", "s", REQUIRED, "> t1"),
    Key("amplitude", "sine: amplitude", "", "1.0", ""),
    Key("frequency", "sine: frequency", "Hz", REQUIRED, "> 0"),
    Key("phase", "sine: phase", "rad", "0.0", ""),
    Key("offset", "sine: offset", "", "0.0", ""),
    Key("ramp", "sine: the time over which the amplitude grows from 0 (10u^3 - 15u^4 + 6u^5; 0: none)", "s", "0.0",
        ">= 0"),
    Key("times", "table, spline: the times", "s", "required unless file", "strictly increasing"),
    Key("values", "table, spline: the values", "", "required unless file", "as many as times"),
    Key("file", "table, spline: a CSV file of lines \"t,value\" relative to the scene (an optional header line, # "
                "comments and blank lines allowed), instead of times and values", "", "", "a file name"),
), variants=(("constant", ()), ("ramp", ("t0", "t1")), ("smooth_ramp", ("t0", "t1")), ("hat", ("t0", "t1", "t2")), ("step", ("t0", "t1")),
             ("sine", ("amplitude", "frequency", "phase", "offset", "ramp")), ("table", ("times", "values", "file")),
             ("spline", ("times", "values", "file"))))

MOTION = Table("motion", "motion = { displacement = ..., rotation = ..., time_function = { ... } }",
               "A prescribed motion of a support ([[support]] spherical, clamp or fixed): the point moves by "
               "f(t) displacement, a clamp also turns by the rotation vector f(t) rotation, a fixed beam "
               "moves rigidly (displaced, and turned about its start). f(0) must be 0. "
               "Its work is counted in the energy balance.", (
    Key("displacement", "displacement at f = 1", "m", "[0.0, 0.0, 0.0]", "3 numbers; displacement or rotation needed"),
    Key("rotation", "rotation vector at f = 1 (clamp and fixed only)", "rad", "[0.0, 0.0, 0.0]", "3 numbers"),
    Key("time_function", "f(t), see time_function", "", REQUIRED, "f(0) = 0"),
))

# the scene's own tables, in the order the reference lists them
TABLES: tuple[Table, ...] = (SCENE, ANALYSIS, ADAPT, BEAM, ARC, SECTION, BODY, OUTPUT, TRACK, PETSC, TIME_FUNCTION, MOTION)
