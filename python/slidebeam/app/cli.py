# SPDX-License-Identifier: MIT
"""Command line: ``slidebeam run SCENE``, ``check SCENE``, ``study``, ``plot RUN...`` and ``render RUN``.

Exit codes: 0 success, 1 the solve failed (Newton), 2 bad input or unusable output folder,
3 internal error. Anything after ``--`` goes to the PETSc options database.
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import sys
import time
import traceback
import warnings
from pathlib import Path

from ..run import interrupts
from ..scene.effect_tables import table_specs
from ..scene.parse import Scene, SceneError, load_scene, scene_from_dict
from ..output.checkpoint import CheckpointError
from ..output.rundata import RunFolderError
from ..run.costs import output_phase
from ..run import options_check
from ..run.parallel import release_waiting_ranks, running_alone, serial_below, statics_on_rank_0, wait_sleeping
from ..run.resources import check_memory, constraint_entries, estimate, memory_line, size_text
from ..output.xdmf import NoOutput, OutputFailure, XdmfOutput, bytes_per_record

EXIT_OK, EXIT_SOLVE_FAILED, EXIT_INPUT, EXIT_INTERNAL = 0, 1, 2, 3


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="slidebeam",
        description="Flexible beams with sliding joints: director beams, B-splines, PETSc.",
        epilog="Anything after '--' is passed to PETSc, e.g. -- -snes_monitor -log_view",
    )
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run = sub.add_parser("run", help="run a scene and write results",
                         description="Run a scene; write summary.json, history.csv, final_configuration.csv, "
                                     "beams.xdmf/.h5 (ParaView) and, for dynamic runs, checkpoint.h5.",
                         epilog="Examples: slidebeam run runs/rollup.toml --out out/rollup -- -snes_monitor\n"
                                "          slidebeam run runs/seed/free_fall_1+4.toml --restart "
                                "out/free_fall_1+4/checkpoint.h5 --set analysis.t_end=2",
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("scene", help="scene file (TOML)")
    run.add_argument("--out", help="output folder (default: out/<scene name>)")
    run.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                     help="override a scene value, e.g. --set beam.0.spans=32 (repeatable)")
    run.add_argument("-q", "--quiet", action="store_true", help="no progress output")
    run.add_argument("--restart", metavar="CHECKPOINT",
                     help="continue a dynamic run from its checkpoint.h5 (results go to the checkpoint's folder "
                          "unless --out is given; the XDMF series there is continued)")
    chk = sub.add_parser("check", help="validate a scene without running it",
                         description="Validate a scene as a run would, short of solving: the file, then the "
                                    "model built from it (reference geometry, sliders placed on their carriers); "
                                    "print what it contains and any warnings.")
    chk.add_argument("scene", help="scene file (TOML)")
    chk.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override a scene value")
    st = sub.add_parser("study", help="work-precision study: a grid of variants against a reference",
                        description="Run every combination of the --vary values (each a run of its own), measure "
                                    "each run's error against a reference (--reference, or the finest run of the "
                                    "grid) in the tip trajectory, the sliding coordinate and the energy, and its "
                                    "cost. Writes study.csv, study.md and study_<quantity>.png (error against wall "
                                    "time, log-log, with observed orders) to --out.",
                        epilog="Examples:\n  slidebeam study runs/seed/free_fall_1+4.toml --vary analysis.dt=4e-3,2e-3,1e-3 "
                               "--vary analysis.integrator=energy-momentum,newmark --reference analysis.dt=2.5e-4 -j 2\n"
                               "  slidebeam study runs/studies/seed.toml        (a study file: [study] scene, vary, reference)\n"
                               "Keys varied together: --vary 'beam.AB.quadrature&beam.CM.quadrature=full,reduced'",
                        formatter_class=argparse.RawDescriptionHelpFormatter)
    st.add_argument("scene", help="scene file (TOML), or a study file with a [study] table")
    st.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...", help="a key and its values (repeatable)")
    st.add_argument("--reference", action="append", default=[], metavar="KEY=VALUE",
                    help="the reference run: the scene with these values (repeatable; default: the finest run)")
    st.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override for every run (repeatable)")
    st.add_argument("--adapt", metavar="RTOL,...", help="also run each combination of the other varied keys with "
                                                        "error-controlled steps at these tolerances instead of "
                                                        "analysis.dt (curves of their own)")
    st.add_argument("-j", "--jobs", type=int, default=None, help="runs at once (default 1, or the study file's jobs)")
    st.add_argument("--out", help="output folder (default: out/study_<name>)")
    st.add_argument("-q", "--quiet", action="store_true", help="no progress output")
    plot = sub.add_parser("plot", help="plot runs: energy, paths, tension, reactions, sliders, outputs, solver (PNG/PDF)",
                          description="Draw plots of one or more run folders (one line style per run): energy "
                                      "(energy, energy balance, momenta), paths (tracked points and point masses), "
                                      "tension (along every beam over time), reactions (supports and joints), "
                                      "sliders (sliding joints' s and speed), outputs (what effects report: a "
                                      "contact's force and length in contact), solver (Newton iterations, step size, "
                                      "rejected steps).",
                          formatter_class=argparse.RawDescriptionHelpFormatter,
                          epilog="Examples:\n"
                                 "  slidebeam plot out/ropeway                        # out/ropeway/plots/<kind>.png\n"
                                 "  slidebeam plot out/ropeway --what tension,reactions --format pdf\n"
                                 "  slidebeam plot out/ropeway --out ropeway.pdf      # every plot, one page each\n"
                                 "  slidebeam plot out/em out/midpoint --out energy.png")
    plot.add_argument("runs", nargs="+", help="run folders (with history.csv)")
    plot.add_argument("--what", metavar="KINDS",
                      help="comma-separated: energy, paths, tension, reactions, sliders, outputs, solver, or all "
                           "(default: every kind the runs have; with --out FILE.png: energy)")
    plot.add_argument("--out", help="a folder (one file per plot; default: <first run>/plots), a .png file "
                                    "(one plot) or a .pdf file (one page per plot)")
    plot.add_argument("--format", choices=("png", "pdf"), default="png", help="file format in a folder (default png)")
    plot.add_argument("--drift", action="store_true",
                      help="energy plot's momentum panels: the relative change |L(t) - L(0)| / |L(0)|, "
                           "|J(t) - J(0)| / |J(0)| on a log scale instead of the components (free-floating structures)")
    render = sub.add_parser("render", help="draw the deformed structure: pictures (PNG/PDF) or animations (GIF/MP4)",
                            description="Draw a run's beams (coloured by a field), point masses and sliders at "
                                        "chosen times, or the whole run as an animation, without a display "
                                        "(matplotlib). The camera is fixed from the structure's extent over the run.",
                            formatter_class=argparse.RawDescriptionHelpFormatter,
                            epilog="Examples:\n"
                                   "  slidebeam render out/ropeway                       # out/ropeway/render.png, last record\n"
                                   "  slidebeam render out/ropeway --time 0 3 6 --view front\n"
                                   "  slidebeam render out/ropeway --out ropeway.gif     # the whole run\n"
                                   "  slidebeam render out/ropeway --out ropeway.mp4 --fps 30   # needs ffmpeg")
    render.add_argument("run", help="run folder (with beams.xdmf)")
    render.add_argument("--time", nargs="+", type=float, metavar="T",
                        help="times to draw (the nearest records; default: the last record); one file per time "
                             "when several are given to a .png")
    render.add_argument("--out", help="file: .png or .pdf (pictures), .gif or .mp4 (animation of the whole run); "
                                      "default <run>/render.png")
    render.add_argument("--view", default="iso",
                        help="iso, front (x-z), side (y-z), top (x-y), or ELEVATION,AZIMUTH in degrees (default iso)")
    render.add_argument("--field", default="tension",
                        help="colour of the beams: tension, velocity, displacement, s, or none (default tension)")
    render.add_argument("--size", default="1280x720", metavar="WxH", help="pixels (default 1280x720)")
    render.add_argument("--fps", type=float, default=20.0, help="animation frames per second (default 20)")
    render.add_argument("--frames", type=int, default=None,
                        help="animation: at most this many frames, evenly over the run (default: every record, "
                             "up to 600)")
    return p


    return p


def _rank() -> int:
    from mpi4py import MPI

    return MPI.COMM_WORLD.Get_rank()


def _say(rank: int, text: str, stream=sys.stdout) -> None:
    if rank == 0:
        print(text, file=stream, flush=True)


# Beyond this many beams the header groups beams described alike (a net has hundreds).
BEAMS_LISTED = 12


def _beam_kind(b) -> str:
    if b.formulation == "ancf":
        return f"{b.geometry.kind}, L = {b.geometry.length:g}, ANCF cable, {b.spans} element{'' if b.spans == 1 else 's'}"
    return (f"{b.geometry.kind}, L = {b.geometry.length:g}, {b.spans} span{'' if b.spans == 1 else 's'}, "
            f"{b.quadrature} quadrature, {b.strain} strains")


def _describe(scene: Scene) -> str:
    lines = [f"scene '{scene.name}' ({scene.file}): {scene.analysis.type} analysis"]
    if len(scene.beams) <= BEAMS_LISTED:
        lines += [f"  beam {b.name}: {_beam_kind(b)}" for b in scene.beams]
    else:
        groups: dict[str, list[str]] = {}
        for b in scene.beams:
            groups.setdefault(_beam_kind(b), []).append(b.name)
        for kind, names in list(groups.items())[:BEAMS_LISTED]:
            which = names[0] if len(names) == 1 else f"{len(names)} beams ({names[0]} ... {names[-1]})"
            lines.append(f"  {which}: {kind}")
        if len(groups) > BEAMS_LISTED:
            rest = sum(len(names) for names in list(groups.values())[BEAMS_LISTED:])
            lines.append(f"  ... and {rest} more beams")
    specs = table_specs()
    lines.append("  " + (", ".join(f"[{table}]" if specs[table][0].single else f"{n} [[{table}]]"
                                   for table, n in _table_counts(scene).items()) or "no effect tables"))
    return "\n".join(lines)


def _table_counts(scene: Scene) -> dict[str, int]:
    """Entries per effect table ([[support]], [gravity], [[damping]], ...), in scene order."""
    counts: dict[str, int] = {}
    for e in scene.effects:
        counts[e.table] = counts.get(e.table, 0) + 1
    return counts


def _effects_line(effects) -> str:
    """Every effect by label; for big scenes (more than 16) the count per type."""
    if len(effects) <= 16:
        return "active effects: " + ", ".join(e.label for e in effects)
    counts: dict[str, int] = {}
    for e in effects:
        counts[e.type] = counts.get(e.type, 0) + 1
    return f"active effects ({len(effects)}): " + ", ".join(f"{t} x{n}" for t, n in counts.items())


def _is_solver_failure(err: Exception) -> bool:
    try:
        from .. import _core
    except ImportError:
        return False
    return isinstance(err, _core.SolverFailure)


def _quiet_broken_pipe() -> None:
    """`slidebeam run ... | head` should end quietly, as command-line tools do, not through
    PETSc's signal handler (which reports a crash and calls MPI_Abort)."""
    import signal

    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)


def _finish_costs(sim, summary: dict, t0: float, rank: int, quiet: bool) -> None:
    """The run's cost by effect and phase: into summary.json and, unless quiet, a table."""
    from ..run.costs import cost_breakdown, cost_table

    wall = time.perf_counter() - t0
    rows = cost_breakdown(sim, wall)
    summary["cost"] = rows
    if sim.integrator is not None:
        from ..run.costs import event_time

        summary["stepping_time_s"] = event_time("SBTimeStep")  # the time steps alone (no set-up)
        summary["contact_search_setup_s"] = event_time("SBContactSearch")  # initial slider projection
        times = sorted(sim.step_wall_times)
        if times:
            # the first step also sets up the Jacobian's pattern and the symbolic factorisation
            summary["step_time_s"] = {"first": sim.step_wall_times[0], "median": times[len(times) // 2],
                                      "max": times[-1]}
    if not quiet:
        _say(rank, "cost by phase (largest over ranks):\n" + cost_table(rows, wall))


def _history_row_bytes(scene: Scene) -> int:
    """history.csv per record: ~25 characters a value (repr of a float and a comma)."""
    values = 25 + 3 * len(scene.output.track) + 6 * constraint_entries(scene)  # a joint's s, rate, reaction; a support's reaction
    return 25 * values


def _record_spacing(scene: Scene) -> str:
    o = scene.output
    return f"output.interval (now {o.interval:g} s)" if o.interval > 0 else f"output.every (now {o.every})"


def _check_output_size(scene: Scene, out: Path, t0: float, rank: int) -> None:
    """Before the run: refuse a run whose XDMF output cannot fit on the disk, and warn (once,
    on stderr) when the results are estimated larger than output.warn_size_gb. An estimate: the
    records the run will write, one every output.every steps or output.interval seconds."""
    import shutil

    a = scene.analysis
    steps = a.steps if a.type == "static" else a.planned_steps(t0)
    records = (steps if a.type == "static" else int(scene.output.records(steps, a.t_end - t0))) + 2
    need = records * bytes_per_record(scene)
    free = shutil.disk_usage(out).free
    if need > free:
        raise OutputFailure(f"the XDMF output of this run needs about {need / 1e6:.1f} MB, but only "
                            f"{free / 1e6:.1f} MB are free in {out} (raise output.every or output.interval, or free space)")
    total = need + records * _history_row_bytes(scene)
    limit = scene.output.warn_size_gb * 1e9
    if limit > 0 and total > limit:
        _say(rank, f"slidebeam: warning: the results of this run will take about {size_text(total)} "
                   f"({records} records of {size_text(total / records)}), more than output.warn_size_gb = "
                   f"{scene.output.warn_size_gb:g}; raise {_record_spacing(scene)} to write fewer",
             sys.stderr)


def _exit_after_output_failure(code: int) -> None:
    """HDF5 (through h5py) crashes at interpreter exit once a write to a file has failed (full
    disk): finalize PETSc and MPI ourselves and leave without the interpreter's teardown."""
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        release_waiting_ranks()
        from petsc4py import PETSc

        PETSc._finalize()
        from mpi4py import MPI

        if not MPI.Is_finalized():
            MPI.Finalize()
    finally:
        os._exit(code)


# Keys a restart may change and still continue the same run (the end time, what is written)
_RESTART_CHANGES_OK = ("analysis.t_end", "output.")


def _restart_scene(args: argparse.Namespace, restart: Path, rank: int) -> Scene:
    """The scene of a restart: the file with the overrides of the run that wrote the checkpoint,
    then this command's; say what differs from that run."""
    from ..output.checkpoint import scene_differences, scene_of_checkpoint

    kept = scene_of_checkpoint(restart) if restart.is_file() else None
    if kept is None:  # a checkpoint that does not keep its scene
        return load_scene(args.scene, args.set)
    overrides, data = kept
    scene = load_scene(args.scene, [*overrides, *args.set])
    if overrides:
        _say(rank, f"restart: the checkpoint's run had --set {' --set '.join(overrides)}; applied again")
    changes = scene_differences(data, scene.data)
    if changes:
        listed = "; ".join(f"{k}: {a!r} -> {b!r}" for k, a, b in changes)
        odd = [k for k, _, _ in changes if not k.startswith(_RESTART_CHANGES_OK)]
        if odd:
            _say(rank, f"slidebeam: warning: the restarted scene differs from the run that wrote the checkpoint "
                       f"({listed}); with {', '.join(odd)} changed the run does not go on as that run would have",
                 sys.stderr)
        else:
            _say(rank, f"restart: changed since the checkpoint: {listed}")
    if not {"every", "interval"} & set(scene.data.get("output", {})):
        # the default spacing follows t_end: keep the one the checkpoint's run recorded with
        recorded = scene_from_dict(data, scene.file, scene.base_dir).output
        scene = dataclasses.replace(scene, output=dataclasses.replace(scene.output, every=recorded.every,
                                                                      interval=recorded.interval))
    return scene


def _say_run_warnings(sim, rank: int) -> None:
    """What the start of a run corrected (initial velocities), once each."""
    for w in sim.warnings:
        if w not in _said_run_warnings:
            _said_run_warnings.add(w)
            _say(rank, f"slidebeam: warning: {w}", sys.stderr)


_said_run_warnings: set[str] = set()


def _say_warnings(scene: Scene, rank: int) -> None:
    for w in scene.warnings:
        _say(rank, f"slidebeam: warning: {scene.file}: {w}", sys.stderr)


def _check(args: argparse.Namespace, rank: int) -> int:
    """Validate a scene as a run would, short of solving: the file, then the model built from it
    (reference geometry, sliders placed on their carriers)."""
    scene = load_scene(args.scene, args.set)
    import petsc4py

    petsc4py.init([sys.argv[0]])
    from ..run.model import build_model

    model, effects = build_model(scene)
    del model
    _say(rank, _describe(scene))
    _say(rank, _effects_line(effects))
    _say(rank, memory_line(check_memory(scene)))
    _say_warnings(scene, rank)
    _say(rank, "scene is valid" + (f" ({len(scene.warnings)} warning{'s' * (len(scene.warnings) > 1)})"
                                   if scene.warnings else ""))
    return EXIT_OK


def _run(args: argparse.Namespace, petsc_args: list[str], rank: int) -> int:
    restart = Path(args.restart) if args.restart else None
    scene = _restart_scene(args, restart, rank) if restart is not None else load_scene(args.scene, args.set)
    if restart is not None and scene.analysis.type != "dynamic":
        raise SceneError("--restart continues dynamic runs only", scene.file, "[analysis]", "type")
    out = Path(args.out) if args.out else (restart.parent if restart else Path("out") / scene.name)

    import petsc4py

    petsc4py.init([sys.argv[0], *petsc_args])
    options_check.remember_command_line(petsc_args)
    _quiet_broken_pipe()
    from ..run.costs import start_logging

    start_logging()
    from mpi4py import MPI

    from ..output.results import prepare_output_dir_on

    check_memory(scene)  # before the output folder: a scene that cannot fit leaves nothing behind
    comm = MPI.COMM_WORLD
    try:
        prepare_output_dir_on(comm, out)
    except OSError as err:
        _say(rank, f"slidebeam: error: {err}", sys.stderr)
        return EXIT_INPUT

    alone = None
    if comm.Get_size() > 1 and (unknowns := estimate(scene).unknowns) < (below := serial_below()):
        # too small to gain from distribution: rank 0 runs it alone, the others wait
        alone = f"{unknowns} unknowns or fewer (below -sb_serial_below {below}): rank 0 runs the scene alone"
    elif comm.Get_size() > 1 and scene.analysis.type == "static" and statics_on_rank_0():
        # statics has no distributed path that pays (MUMPS on the whole system: 2-4x slower)
        alone = "a static analysis: rank 0 runs the scene alone with the serial solver (-sb_statics_on_rank_0)"
    if alone:
        _say(rank, alone)
        if rank != 0:
            _wait_for_rank_0(comm)
            return EXIT_OK
        with running_alone():
            return _run_scene(scene, restart, out, args, rank, comm.Get_size())
    return _run_scene(scene, restart, out, args, rank, comm.Get_size())


def _wait_for_rank_0(comm) -> None:
    """The other ranks of a run on rank 0 alone: sleep (rather than poll MPI, which would keep
    their cores busy) until rank 0 is done. Stop signals are rank 0's to handle: mpirun passes
    them to every rank, and a rank that died of one would take rank 0 down before it has written
    its results."""
    import signal

    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_IGN)
    wait_sleeping(comm)


def _run_scene(scene: Scene, restart: Path | None, out: Path, args: argparse.Namespace, rank: int, ranks: int) -> int:
    """The run itself, on the run's communicator (parallel.run_comm)."""
    from ..run.simulation import ConstraintWarning, Simulation

    t0 = time.perf_counter()
    with warnings.catch_warnings():  # said below, in the command's own words
        warnings.simplefilter("ignore", ConstraintWarning)
        sim = Simulation(scene)
    _say(rank, _describe(scene))
    _say(rank, _effects_line(sim.active_effects))
    _say_warnings(scene, rank)
    if restart is None:  # (a restart's state comes from its checkpoint)
        _say_run_warnings(sim, rank)
    state = None
    if restart is not None:
        from ..output.checkpoint import read_checkpoint

        state = read_checkpoint(sim, restart)
        _say(rank, f"restarting from {restart} at t = {sim.t:.6g} (step {state.step})")
    try:
        _check_output_size(scene, out, sim.t, rank)
    except OutputFailure as err:
        _say(rank, f"slidebeam: error: {err}", sys.stderr)
        return EXIT_INPUT
    try:
        output = (XdmfOutput(sim, out, rank, resume_after=sim.t if restart else None) if scene.output.xdmf
                  else NoOutput())
        with interrupts.stop_on_signals():
            if scene.analysis.type == "dynamic":
                return _run_dynamic(sim, scene, out, args, rank, ranks, t0, output, state)
            return _run_static(sim, scene, out, args, rank, ranks, t0, output)
    except OutputFailure as err:
        _say(rank, f"slidebeam: error: {err}; the run stopped at t = {sim.t:.6g} and its results are incomplete",
             sys.stderr)
        _exit_after_output_failure(EXIT_INPUT)
        return EXIT_INPUT  # not reached


def _run_static(sim, scene: Scene, out: Path, args: argparse.Namespace, rank: int, ranks: int, t0: float,
                output: XdmfOutput) -> int:
    from ..output.results import static_summary, write_files

    def progress(rec) -> None:
        if not args.quiet:
            _say(rank, f"  step {rec.step:4d}/{scene.analysis.steps}  t = {rec.t:.6g}  newton {rec.newton_iterations:2d}"
                       f"  |F| = {rec.residual_norm:.3e}  {'' if rec.converged else 'FAILED: ' + rec.reason}"
                       f"{'(Newton failed: solved by continuation)' if rec.reason == 'CONVERGED_BY_CONTINUATION' else ''}")
        if rec.converged:
            output.write(rec.t, rec.joints)  # the record's joints: not computed again

    output.write(sim.t)  # the reference state (step 0)
    records = sim.solve_static(progress)
    with output_phase():
        output.close()
    wall = time.perf_counter() - t0
    summary = static_summary(sim, records, wall)
    complete, message = summary["complete"], summary["message"]
    _finish_costs(sim, summary, t0, rank, args.quiet)
    options_check.report_unused(sim, summary, rank)
    with output_phase():
        write_files(sim, out, records, summary, rank)
    if sim.stop_signal:
        _say(rank, f"slidebeam: {message}", sys.stderr)
        return interrupts.exit_code(sim.stop_signal)
    if complete or (sim.stopped and not sim.stop_is_failure):
        if sim.stopped:
            _say(rank, message)
        _say(rank, f"done in {wall:.3f} s: {sum(r.newton_iterations for r in records)} Newton iterations; "
                   f"results in {out}/")
        return EXIT_OK
    _say(rank, f"slidebeam: error: {message}", sys.stderr)
    return EXIT_SOLVE_FAILED


def _run_dynamic(sim, scene: Scene, out: Path, args: argparse.Namespace, rank: int, ranks: int, t0: float,
                 output: XdmfOutput, state=None) -> int:
    from ..output.checkpoint import write_checkpoint
    from ..output.results import dynamic_summary, parallel_line, write_files

    checkpoint = out / "checkpoint.h5"

    def save(st) -> None:
        with output_phase():
            output.checkpoint()  # the series on disk matches the checkpoint: a restart continues it
            write_checkpoint(sim, st, checkpoint)

    a = scene.analysis
    n_steps = a.planned_steps()
    report_every = max(1, n_steps // 20)  # about 20 progress lines per run
    next_report = [0]
    rejected = [0]  # step cuts since the last progress line

    def progress(rec) -> None:
        if rec.converged:
            output.write(rec.t, rec.joints)  # the record's joints: not computed again
        rejected[0] += rec.rejected_steps
        if args.quiet:
            return
        if rec.converged and rec.step < next_report[0] and rec.t < a.t_end * (1 - 1e-12):
            return
        next_report[0] = rec.step + report_every
        cuts = f"  {rejected[0]} steps cut" if rejected[0] else ""
        rejected[0] = 0
        _say(rank, f"  step {rec.step:6d}  t = {rec.t:10.5g}  newton {rec.newton_iterations:2d}  "
                   f"E = {rec.total_energy:.10e}  |constraints| = {rec.constraint_residual:.1e}{cuts}"
                   f"{'' if rec.converged else '  FAILED: ' + rec.reason}")

    if state is None and a.start == "equilibrium":
        from ..run.simulation import ConstraintWarning, EquilibriumFailure

        _say(rank, "static start: solving for the equilibrium under the loads at t = 0 ...")
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConstraintWarning)
                eq = sim.settle()
            _say_run_warnings(sim, rank)
        except EquilibriumFailure as err:
            return _equilibrium_failed(sim, scene, out, args, rank, ranks, t0, output, err)
        cut = f" ({eq.cut_steps} cut and retried)" if eq.cut_steps else ""
        _say(rank, f"static start: equilibrium after {eq.pseudo_steps} continuation steps{cut}, {eq.newton_iterations} "
                   f"Newton iterations (|F| {eq.residual0:.3e} -> {eq.residual:.3e})")
    outcome = sim.run_dynamic(progress, state, save)
    with output_phase():
        # The last good state, whatever ended the run. The series' writers finish while the
        # checkpoint is written; it is committed once they have: a run killed before that restarts
        # from the previous checkpoint, which rewrites the records after it.
        output.flush(wait=False)
        write_checkpoint(sim, outcome.state, checkpoint, before_commit=output.close)
    wall = time.perf_counter() - t0
    summary = dynamic_summary(sim, outcome, wall, initial_velocity=state is None)
    summary["checkpoint"] = str(checkpoint)
    _finish_costs(sim, summary, t0, rank, args.quiet)
    options_check.report_unused(sim, summary, rank)
    with output_phase():
        write_files(sim, out, outcome.records, summary, rank)
    if outcome.signal:
        _say(rank, f"slidebeam: {outcome.message}; results in {out}/", sys.stderr)
        return interrupts.exit_code(outcome.signal)
    if not outcome.failed:
        if not outcome.complete:
            _say(rank, outcome.message)
        if "parallel" in summary:
            _say(rank, parallel_line(summary))
        elif summary["pivoting_lu_steps"]:  # (0 where the user chose a pivoting solver)
            # slower, and a sign of a system the condensed LU could not factor: worth knowing
            _say(rank, f"note: {summary['pivoting_lu_steps']} steps ran on the pivoting LU (SuperLU), which is slower, "
                       "after the LU without pivoting failed on them (a zero pivot, or Newton did not converge); the "
                       "steps after each went back to it (docs/troubleshooting.md, \"Solvers\")")
        if summary["rejected_steps"] and scene.analysis.adapt is not None:
            _say(rank, f"note: {summary['rejected_steps']} steps were rejected by the error control or by Newton and "
                       "taken again smaller (history.csv rejected_steps and dt say where)")
        elif summary["rejected_steps"]:
            _say(rank, f"note: {summary['rejected_steps']} steps failed and were retried at half the step size "
                       f"(summary.json rejected_steps; history.csv rejected_steps says where): dt = "
                       f"{summary['dt']:g} is too large for parts of this run")
        _say(rank, f"done in {wall:.3f} s: {summary['steps']} steps, {summary['newton_iterations']} Newton iterations, "
                   f"{summary['jacobian_evaluations']} Jacobians; results in {out}/")
        return EXIT_OK
    _say(rank, f"slidebeam: error: {outcome.message}", sys.stderr)
    return EXIT_SOLVE_FAILED


def _likely_causes(scene: Scene) -> list[str]:
    """What most often keeps a scene from an equilibrium, as far as the scene shows it."""
    causes = []
    if not scene.supports:
        causes.append("the scene has no [[support]]: nothing holds the structure against its loads")
    soft = [b.get("name", f"#{i + 1}") for i, b in enumerate(scene.data.get("beam", []))
            if isinstance(b.get("section", {}).get("E"), (int, float)) and 0 < b["section"]["E"] < 1e6]
    if soft:
        causes.append(f"E of beam {', '.join(repr(n) for n in soft)} is below 1e6 Pa: moduli are in Pa "
                      f"(steel: E = 2.1e11), not GPa or MPa")
    causes.append("a mechanism: a beam, joint or free slider that can move without resistance "
                  "(add a support, or hold the slider with static = \"held\")")
    return causes


def _equilibrium_failed(sim, scene: Scene, out: Path, args: argparse.Namespace, rank: int, ranks: int, t0: float,
                        output: XdmfOutput, err: Exception) -> int:
    """The static start found no equilibrium: nothing is stepped; the folder still gets the XDMF
    (the initial state), a history with that state, and a summary saying what happened."""
    from ..output.results import static_start_summary, write_files

    signum = sim.settled.interrupted
    causes = [] if signum else _likely_causes(scene)
    message = (f"interrupted by {interrupts.describe(signum)} during the static start; nothing was stepped"
               if signum else f"{err}; nothing was stepped. Likely causes: " + "; ".join(causes))
    with output_phase():
        output.close()
    rec = sim.record_dynamic(0, None, 0.0, 0)
    summary = {
        "scene": scene.name, "scene_file": os.path.abspath(scene.file), "analysis": "dynamic",
        "integrator": scene.analysis.integrator, "complete": False, "converged": False, "message": message,
        "stopped": message.split(";")[0], "likely_causes": causes,
        "active_effects": [e.label for e in sim.active_effects], "t_end": scene.analysis.t_end, "t_reached": 0.0,
        "steps": 0, "unknowns": sim.x.getSize(), "ranks": ranks, "wall_time_s": time.perf_counter() - t0,
        "static_start": static_start_summary(sim),
        "checkpoint": None,
    }
    options_check.report_unused(sim, summary, rank)
    with output_phase():
        write_files(sim, out, [rec], summary, rank)
    if signum:
        _say(rank, f"slidebeam: {message} (results in {out}/ hold the initial state)", sys.stderr)
        return interrupts.exit_code(signum)
    _say(rank, f"slidebeam: error: {err}; nothing was stepped (results in {out}/ hold the initial state)",
         sys.stderr)
    for cause in causes:
        _say(rank, f"  likely cause: {cause}", sys.stderr)
    return EXIT_SOLVE_FAILED


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    petsc_args: list[str] = []
    if "--" in argv:
        i = argv.index("--")
        argv, petsc_args = argv[:i], argv[i + 1:]
    args = _parser().parse_args(argv)
    rank = _rank()
    try:
        if args.command == "plot":
            from ..plots import parse_kinds, plot

            files = plot(args.runs, parse_kinds(args.what) if args.what else None, args.out, args.format, args.drift)
            for f in files:
                _say(rank, f"wrote {f}")
            return EXIT_OK
        if args.command == "render":
            from ..plots.render import render_command

            for f in render_command(args, lambda text: _say(rank, text)):
                _say(rank, f"wrote {f}")
            return EXIT_OK
        if args.command == "study":
            from .study import main_study

            args.jobs_given = args.jobs is not None
            args.jobs = args.jobs or 1
            return main_study(args, petsc_args)
        if args.command == "check":
            return _check(args, rank)
        return _run(args, petsc_args, rank)
    except SceneError as err:
        _say(rank, f"slidebeam: error: {err}", sys.stderr)
        return EXIT_INPUT
    except (FileNotFoundError, CheckpointError, RunFolderError) as err:
        _say(rank, f"slidebeam: error: {err}", sys.stderr)
        return EXIT_INPUT
    except (ValueError, TypeError) as err:  # the core's invalid_argument arrives as ValueError
        _say(rank, f"slidebeam: error: {err}", sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        _say(rank, "slidebeam: interrupted", sys.stderr)
        return 130
    except Exception as err:  # noqa: BLE001 - last line of defence: a message, not a trace
        if _is_solver_failure(err):  # the input cannot be solved (e.g. a singular system)
            _say(rank, f"slidebeam: error: {err}", sys.stderr)
            return EXIT_SOLVE_FAILED
        _say(rank, f"slidebeam: internal error: {type(err).__name__}: {err}", sys.stderr)
        if os.environ.get("SLIDEBEAM_DEBUG"):
            traceback.print_exc()
        return EXIT_INTERNAL
