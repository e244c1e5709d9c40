# SPDX-License-Identifier: MIT
"""`pip install .` as docs/install.md tells a user: into a throwaway venv made with
`/usr/bin/python3 -m venv --system-site-packages`, offline (--no-index --no-build-isolation: the
build uses Debian's setuptools), then the package and the `slidebeam` command from outside the
repository with PYTHONPATH unset.

The CMake build tree is build/python/ (setup.py), kept between runs: the first install compiles
the core (about 1.5 min on 2 cores; 20 s when scripts/setup.sh has filled ccache's cache with the
same objects), later ones only what changed."""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

pytestmark = pytest.mark.skip_in_parallel  # builds and installs once; spawns its own processes

ROOT = Path(__file__).resolve().parents[2]


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")
           and not k.startswith(("OMPI_COMM", "PMIX", "OMPI_MCA_ess", "OMPI_FILE"))}
    env.setdefault("SLIDEBEAM_BUILD_JOBS", str(min(2, os.cpu_count() or 1)))
    return env


def test_pip_install_into_venv(tmp_path):
    venv, work = tmp_path / "venv", tmp_path / "elsewhere"
    work.mkdir()
    env = _env()

    def run(*cmd: str | Path, timeout: float = 120) -> subprocess.CompletedProcess:
        return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, cwd=work, env=env,
                              timeout=timeout)

    out = run("/usr/bin/python3", "-m", "venv", "--system-site-packages", venv)
    assert out.returncode == 0, out.stderr
    python, command = venv / "bin" / "python", venv / "bin" / "slidebeam"
    out = run(python, "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-cache-dir", ROOT,
              timeout=1200)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]

    # the installed package, with the built core and its data files, not the source tree's
    out = run(python, "-c", "import slidebeam, slidebeam._core as c; print(slidebeam.__file__); print(c.__file__)")
    assert out.returncode == 0, out.stderr
    package = Path(out.stdout.split()[0]).parent
    assert package.is_relative_to(venv) and Path(out.stdout.split()[1]).parent == package
    assert (package / "effect_specs.json").is_file() and (package / "petsc_options.txt").is_file()
    assert (package / "_core.pyi").is_file() and (package / "py.typed").is_file()

    out = run(command, "--help")
    assert out.returncode == 0 and "usage: slidebeam" in out.stdout, out.stderr
    out = run(command, "check", ROOT / "runs" / "bend45.toml")
    assert out.returncode == 0 and "scene is valid" in out.stdout, out.stderr
    # a short run through the core; the misspelt PETSc option is named from petsc_options.txt
    out = run(command, "run", ROOT / "runs" / "rollup.toml", "--out", "res", "-q",
              "--set", "analysis.steps=3", "--set", "beam.0.spans=6", "--", "-snes_monitr")
    assert out.returncode == 0, out.stderr
    assert "(did you mean -snes_monitor?)" in out.stderr
    assert (work / "res" / "summary.json").is_file()
    out = run(python, "-m", "slidebeam", "--help")
    assert out.returncode == 0 and "usage: slidebeam" in out.stdout, out.stderr
    # a study starts its runs with this interpreter and package, not the source tree's wrapper
    out = run(command, "study", ROOT / "runs" / "soft_pendulum.toml", "--set", "analysis.t_end=0.05",
              "--vary", "analysis.dt=8e-3,4e-3", "--out", "st", "-q")
    assert out.returncode == 0, out.stderr
    assert (work / "st" / "study.csv").is_file()
