# SPDX-License-Identifier: MIT
"""A scene's PETSc options: put into the options database (:func:`apply_scene_options`), and
typos in any option: every option a run was given that nothing ever read.

PETSc accepts any name into its options database and ignores the ones no solver asks for, so
``-snes_monitr`` or ``snes_rtoll = 1e-8`` in a scene's [petsc] table have no effect and no
word is said. After a run, :func:`report_unused` asks PETSc which entries were never queried
(``PetscOptionsLeftGet``; an option read on any rank counts as read), keeps those the user gave
(not the ones slidebeam sets itself, e.g. MUMPS's workspace), and warns on rank 0, once, with
where each came from and the closest known option name (``petsc_options.txt``: the names in
PETSc's ``-help`` output of the solver paths slidebeam uses, plus the core's ``-sb_`` options;
regenerate with scripts/petsc_option_names.py).

Each solver reads its options under a prefix of ours (``sb_static_``, ``sb_eq_``, ``sb_ts_``,
``sb_mass_``; docs/petsc-options.md); a plain solver option (``-snes_rtol``) is copied under the
prefixes of the SNES solvers when they are created. A plain option counts as read when any of
its copies was read, and a prefixed name is checked against the known plain names.

Options PETSc reads only at PetscFinalize (``-options_left``, ``-options_view``) or that change
nothing about the solve are never reported (:data:`READ_AT_FINALIZE`).
"""
from __future__ import annotations

import difflib
import os
import shlex
from dataclasses import asdict, dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

from .parallel import run_comm
from ..scene.parse import Scene, SceneError

# Read at PetscFinalize or at start-up only, or harmless: never "unused" in a useful sense.
READ_AT_FINALIZE = frozenset("""
options_left options_view options_monitor options_monitor_cancel options_file options_file_yaml
options_suppress_deprecated_warnings skip_petscrc help version
log_view log_all log_trace log_exclude log_view_memory log_view_gpu_time log_sync log_summary
malloc malloc_debug malloc_dump malloc_view malloc_view_threshold malloc_test malloc_info malloc_coalesce
malloc_requested_size memory_view objects_dump check_pointer_intensity checkstack fp_trap
on_error_abort on_error_attach_debugger on_error_emacs on_error_mpiabort on_error_stop on_error_return
no_signal_handler start_in_debugger stop_for_debugger debugger_ranks debugger_pause display petsc_sleep
""".split())

# The database as petsc4py.init left it (command line, options files, PETSC_OPTIONS, .petscrc)
# and the command line's own tokens: set by remember_command_line().
_initial: dict[str, str] | None = None
_command_line: list[str] = []


@dataclass(frozen=True)
class UnusedOption:
    option: str  # as the user wrote it: "-snes_monitr", or "snes_rtoll" in a [petsc] table
    value: str | None
    source: str  # "the command line", "the [petsc] table of runs/x.toml", "the options file a.opts"
    known: bool  # a known option name, read only by solvers or code paths this run did not take
    did_you_mean: str | None  # the closest known name, if not known itself

    def warning(self) -> str:
        if self.known:
            hint = "it applies to a solver or code path this run does not use"
        elif self.did_you_mean is None:
            hint = "no known option is close to it"
        else:
            hint = f"did you mean {self.did_you_mean}?"
        return f"slidebeam: warning: PETSc option {self.option} from {self.source} was never used ({hint})"


@lru_cache(maxsize=1)
def known_options() -> tuple[str, ...]:
    """Option names (without the dash) a slidebeam run may read: PETSc's and the core's."""
    text = (Path(__file__).parents[1] / "petsc_options.txt").read_text()
    return tuple(line.strip() for line in text.splitlines() if line.strip() and not line.startswith("#"))


# The solvers' options prefixes (src/solvers/solver_options.hpp)
SOLVER_PREFIXES = ("sb_static_", "sb_eq_", "sb_ts_", "sb_mass_")


def closest(name: str) -> str | None:
    """The known option name closest to `name` (without dash), `name` itself if known, or None.
    A name under a solver's prefix (sb_ts_snes_rtoll) is matched without it, and the prefix
    kept (sb_ts_snes_rtol)."""
    for prefix in SOLVER_PREFIXES:
        if name.lower().startswith(prefix) and len(name) > len(prefix):
            near = _closest(name[len(prefix):])
            return None if near is None else name[:len(prefix)] + near
    return _closest(name)


def _closest(name: str) -> str | None:
    known = known_options()
    lowered = {k.lower(): k for k in known}
    if name.lower() in lowered:
        return lowered[name.lower()]
    match = difflib.get_close_matches(name.lower(), list(lowered), n=1, cutoff=0.75)
    return lowered[match[0]] if match else None


def remember_command_line(petsc_args: list[str]) -> None:
    """Call right after petsc4py.init(petsc_args): what the database holds before any scene."""
    from petsc4py import PETSc

    global _initial, _command_line
    _initial = {k.lower(): v for k, v in PETSc.Options().getAll().items()}
    _command_line = list(petsc_args)


def _option_tokens(tokens: list[str]) -> list[str]:
    """Option names (without dash) among command-line-like tokens; negative numbers are values."""
    names = []
    for tok in tokens:
        if tok.startswith("-") and len(tok) > 1 and not is_number(tok):
            names.append(tok.lstrip("-"))
    return names


def is_number(text: str) -> bool:
    """Whether an options-file token is a value (a negative number) rather than an option."""
    try:
        float(text)
        return True
    except ValueError:
        return False


def _file_tokens(path: Path) -> list[str]:
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError):
        return []
    tokens: list[str] = []
    for line in text.splitlines():
        try:
            tokens += shlex.split(line.split("#", 1)[0])
        except ValueError:
            tokens += line.split("#", 1)[0].split()
    return tokens


def _sources(scene) -> list[tuple[str, set[str], bool]]:
    """(where, option names in lower case, written with a dash) in the order that wins: the
    command line over its options files over the scene's options file over its [petsc] table."""
    out: list[tuple[str, set[str], bool]] = []
    names = _option_tokens(_command_line)
    out.append(("the command line", {n.lower() for n in names if n.lower() != "options_file"}, True))
    files = [_command_line[i + 1] for i, tok in enumerate(_command_line[:-1])
             if tok.lstrip("-").lower() == "options_file"]
    for f in files:
        out.append((f"the options file {f}", {n.lower() for n in _option_tokens(_file_tokens(Path(f)))}, True))
    if scene is not None:
        scene_file = options_file_of(scene)
        if scene_file is not None:
            out.append((f"the options file {_show_path(scene_file)} of the scene",
                        {n.lower() for n in _option_tokens(_file_tokens(scene_file))}, True))
        out.append((f"the [petsc] table of {scene.file}", {k.lower() for k in scene.petsc_options}, False))
    if os.environ.get("PETSC_OPTIONS"):
        out.append(("PETSC_OPTIONS", {n.lower() for n in _option_tokens(os.environ["PETSC_OPTIONS"].split())}, True))
    return out


def _show_path(path: Path) -> str:
    try:
        return str(Path(path).resolve().relative_to(Path.cwd()))
    except ValueError:
        return str(path)


def unused_options(scene=None, comm=None) -> list[UnusedOption]:
    """The options given to this run that no rank has read (collective over comm, default
    the run's: parallel.run_comm). Given: on the command line, in its options files, in PETSC_OPTIONS or a
    .petscrc (what the database held when remember_command_line was called) and the scene's
    [petsc] table and options file."""
    from .. import _core

    comm = comm or run_comm()
    left = {name.lower(): (name, value) for name, value in _core.options_left()}
    unread_everywhere = set(left)
    for other in comm.allgather(set(left)):
        unread_everywhere &= other
    copies: dict[str, list[str]] = {}  # plain option -> its copies under the solvers' prefixes
    for copy, plain in _core.plain_option_copies():
        copies.setdefault(plain.lower(), []).append(copy.lower())
    given = set(_initial or {}) | {k.lower() for k in _scene_option_keys}
    result = []
    sources = _sources(scene)
    for key in sorted(unread_everywhere & given):
        name, value = left[key]
        if key in READ_AT_FINALIZE:
            continue
        if any(c not in unread_everywhere for c in copies.get(key, [])):  # read by a solver under its prefix
            continue
        where, dash = "an options file, PETSC_OPTIONS or a .petscrc file", True
        for label, names, with_dash in sources:
            if key in names:
                where, dash = label, with_dash
                break
        prefix = "-" if dash else ""
        near = closest(name)
        known = near is not None and near.lower() == key
        result.append(UnusedOption(prefix + name, value, where, known,
                                   prefix + near if near and not known else None))
    return result


def report_unused(sim, summary: dict[str, Any], rank: int) -> list[UnusedOption]:
    """Warn (stderr, rank 0) about every unused option and list them in the summary
    (``unused_petsc_options``). Collective."""
    import sys

    unused = unused_options(sim.scene if sim is not None else None)
    summary["unused_petsc_options"] = [asdict(u) for u in unused]
    if rank == 0:
        for u in unused:
            print(u.warning(), file=sys.stderr, flush=True)
    return unused


def warnings_of_runs(summaries) -> list[str]:
    """The distinct unused-option warnings of several runs (a study's), each once, from their
    summaries' ``unused_petsc_options``."""
    lines: list[str] = []
    for summary in summaries:
        for entry in summary.get("unused_petsc_options", []):
            try:
                line = UnusedOption(**entry).warning()
            except TypeError:  # a summary written by another version
                continue
            if line not in lines:
                lines.append(line)
    return lines


def options_file_of(scene: Scene) -> Path | None:
    """The scene's PETSc options file: `[petsc] options_file`, else `<scene>.opts` beside it."""
    if scene.petsc_options_file:
        return Path(scene.petsc_options_file)
    if scene.file and not scene.file.startswith("<"):
        beside = Path(scene.file).with_suffix(".opts")
        if beside.is_file():
            return beside
    return None


# Options the last scene put into the database (not the user's): the next Simulation removes
# them first, so that one scene's [petsc] table does not leak into the next scene of a script.
_scene_option_keys: set[str] = set()


def apply_scene_options(scene: Scene) -> None:
    """Scene options (file first, then [petsc]) fill the options database; anything already set,
    i.e. given on the command line, wins. They stay in place for the life of the Simulation
    (solvers read some only at their first solve) until the next Simulation is built."""
    from petsc4py import PETSc

    opts = PETSc.Options()
    for key in _scene_option_keys:
        opts.delValue(key)
    _scene_option_keys.clear()
    pairs: list[tuple[str, str]] = []
    options_file = options_file_of(scene)
    if options_file:
        tokens = []
        for line in options_file.read_text().splitlines():
            tokens += shlex.split(line.split("#", 1)[0])
        i = 0
        while i < len(tokens):
            key = tokens[i]
            if not key.startswith("-"):
                raise SceneError(f"expected an option starting with '-', got {key!r}", file=str(options_file))
            value = ""
            if i + 1 < len(tokens) and not (tokens[i + 1].startswith("-") and not is_number(tokens[i + 1])):
                value = tokens[i + 1]
                i += 1
            pairs.append((key[1:], value))
            i += 1
    pairs += list(scene.petsc_options.items())
    for key, value in pairs:
        if not opts.hasName(key):
            opts.setValue(key, value)
            _scene_option_keys.add(key)
