#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Regenerate python/slidebeam/petsc_options.txt: the option names a slidebeam run can use, for
the "did you mean" of unused PETSc options (python/slidebeam/run/options_check.py).

The names come from PETSc's own `-help` output of small runs that take the solver paths
slidebeam uses and the common alternatives (SuperLU, MUMPS, Schwarz, ASM, GMRES, ILU, trust
region, ...), serial and on 2 ranks, plus options PETSc reads without listing them in -help
(EXTRA below) and every "-sb_..." option the C++ core queries (grep of src/). A solver's options
are listed without its prefix (sb_ts_snes_rtol as snes_rtol): options_check adds the prefixes.

    scripts/petsc_option_names.py          (a minute or two; run after a PETSc upgrade)
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "python" / "slidebeam" / "petsc_options.txt"
SMALL = ["--set", "analysis.steps=1", "--set", "beam.0.spans=4"]
DYN = ["--set", "analysis.t_end=0.002", "--set", "analysis.dt=0.001"]
RUNS = [
    (1, ["runs/rollup.toml", *SMALL]),
    (1, ["runs/rollup.toml", *SMALL, "--", "-ksp_type", "gmres", "-pc_type", "ilu", "-snes_type", "newtontr"]),
    (1, ["runs/rollup.toml", *SMALL, "--", "-ksp_type", "fgmres", "-pc_type", "asm", "-sub_pc_type", "lu",
         "-snes_linesearch_type", "bt"]),
    (1, ["runs/rollup.toml", *SMALL, "--", "-pc_factor_mat_solver_type", "mumps"]),
    (1, ["runs/rollup.toml", *SMALL, "--", "-pc_factor_mat_solver_type", "umfpack", "-snes_linesearch_type", "l2"]),
    (1, ["runs/rollup.toml", *SMALL, "--", "-ksp_type", "bcgs", "-pc_type", "jacobi"]),
    (1, ["runs/pendulum16.toml", *DYN]),
    (1, ["runs/pendulum16_ancf.toml", *DYN]),
    (1, ["runs/cables/hanging_rope.toml", "--set", "analysis.t_end=0.002",
         "--", "-options_file", "runs/cables/iterative.opts"]),
    (2, ["runs/bend45.toml", *SMALL]),
    (2, ["runs/pendulum16.toml", *DYN]),
    (2, ["runs/pendulum16.toml", *DYN, "--", "-sb_schwarz_overlap", "1"]),
]
# Read by PETSc but not listed by -help (at initialisation, at finalize, or by the line that
# -help prints under another name).
EXTRA = """
help version options_left options_view options_file options_file_yaml options_monitor options_monitor_cancel
options_string_yaml skip_petscrc
log_view log_view_memory log_view_gpu_time log_all log_trace log_exclude log_summary log_mpe log_perfstubs
log_sync info info_exclude
malloc malloc_debug malloc_dump malloc_view malloc_view_threshold malloc_test malloc_info malloc_coalesce
malloc_requested_size malloc_hbw
memory_view objects_dump check_pointer_intensity checkstack
on_error_abort on_error_attach_debugger on_error_emacs on_error_mpiabort on_error_stop on_error_return
no_signal_handler start_in_debugger stop_for_debugger debugger_ranks debugger_pause display fp_trap
mpi_return_on_error petsc_sleep tmp shared_tmp not_shared_tmp nox nox_warning
snes_test_jacobian snes_test_jacobian_view snes_test_jacobian_display snes_test_jacobian_display_threshold
snes_monitor snes_converged_reason snes_view ksp_view ksp_monitor ksp_converged_reason mat_view vec_view
""".split()
SOLVER_PREFIXES = ("sb_static_", "sb_eq_", "sb_ts_", "sb_mass_")  # src/solvers/solver_options.hpp
OPTION = re.compile(r"^\s*-([a-z][a-z0-9_]*|sb_[A-Za-z][A-Za-z0-9_]*)(?=[\s:<]|$)")  # not lines two ranks interleaved


def help_names(ranks: int, args: list[str], out: Path) -> set[str]:
    cmd = [str(ROOT / "scripts" / "slidebeam"), "run", *args[:1], "--out", str(out), "-q", *args[1:]]
    cmd += ["-help"] if "--" in args else ["--", "-help"]
    if ranks > 1:
        cmd = ["mpirun", "--oversubscribe", "-n", str(ranks), *cmd]
    res = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, timeout=600)
    if res.returncode not in (0, 1):  # a solve that fails still lists its options
        sys.exit(f"{' '.join(cmd)} failed ({res.returncode}):\n{res.stderr}")
    return {strip_solver_prefix(m.group(1)) for line in res.stdout.splitlines() if (m := OPTION.match(line))}


def strip_solver_prefix(name: str) -> str:
    """-help lists a solver's options under its prefix (sb_ts_snes_rtol): the list holds the
    plain name, which options_check extends by the prefixes itself."""
    for prefix in SOLVER_PREFIXES:
        if name.startswith(prefix):
            return name[len(prefix):]
    return name


def source_names() -> set[str]:
    """Every "-sb_..." option the C++ core queries."""
    names = set()
    for path in (ROOT / "src").rglob("*.[ch]pp"):
        names |= set(re.findall(r'"-(sb_[A-Za-z0-9_]+)"', path.read_text())) - {"sb_"}
    return names


def main() -> None:
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    names = set(EXTRA) | source_names()
    with tempfile.TemporaryDirectory() as tmp:
        for k, (ranks, args) in enumerate(RUNS):
            names |= help_names(ranks, args, Path(tmp) / str(k))
    OUT.write_text("# PETSc and slidebeam option names (without the dash) for the \"did you mean\" of unused\n"
                   "# options; generated by scripts/petsc_option_names.py from PETSc 3.18's -help output\n"
                   + "".join(f"{n}\n" for n in sorted(names)))
    print(f"{len(names)} names -> {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
