# SPDX-License-Identifier: MIT
"""The API reference and the type stubs stay in step with the code: docs/api.md is what
scripts/api_reference.py generates, its examples run, _core.pyi names exactly the public
names of the compiled module, and docs/petsc-options.md lists every -sb_ option of the core."""
from __future__ import annotations

import ast
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from slidebeam import _core

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.skip_in_parallel


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_COMM", "PMIX", "OMPI_MCA_ess", "OMPI_FILE"))}
    env["PYTHONPATH"] = str(ROOT / "python")
    return env


def test_api_page_is_the_generated_one():
    res = subprocess.run([sys.executable, str(ROOT / "scripts" / "api_reference.py"), "--check"],
                         capture_output=True, text=True, env=_env(), timeout=300)
    assert res.returncode == 0, res.stderr + "\n(run scripts/api_reference.py and commit docs/api.md)"


def examples() -> list[str]:
    text = (ROOT / "docs" / "api.md").read_text()
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def test_the_page_has_examples():
    assert len(examples()) >= 4


@pytest.mark.parametrize("k", range(len(examples())))
def test_api_example_runs(k, tmp_path):
    """Each ```python block of docs/api.md, run on its own from a folder that holds runs/."""
    (tmp_path / "runs").symlink_to(ROOT / "runs")
    script = tmp_path / f"example_{k}.py"
    script.write_text(examples()[k])
    res = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, cwd=tmp_path, env=_env(),
                         timeout=600)
    assert res.returncode == 0, f"example {k + 1} of docs/api.md failed:\n{res.stdout}\n{res.stderr}"


def _stub_names() -> tuple[set[str], dict[str, set[str]]]:
    tree = ast.parse((ROOT / "python" / "slidebeam" / "_core.pyi").read_text())
    top: set[str] = set()
    members: dict[str, set[str]] = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            top.add(node.name)
            members[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)} | \
                {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        elif isinstance(node, ast.FunctionDef):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            top.add(node.target.id)
    return top, members


def test_core_stubs_name_every_public_name_and_no_other():
    top, members = _stub_names()
    public = {n for n in dir(_core) if not n.startswith("_")}
    assert public - top == set(), "in _core but not in _core.pyi (run scripts/core_stubs.py)"
    assert top - public == set(), "in _core.pyi but not in _core"
    for name in public:
        obj = getattr(_core, name)
        if isinstance(obj, type) and not issubclass(obj, BaseException):
            defined = {m for m in obj.__dict__ if not m.startswith("_")}
            stubbed = members[name] - {"__init__"}
            assert defined == stubbed, f"_core.{name}: stubs differ by {sorted(defined ^ stubbed)}"


def test_core_stubs_are_generated():
    res = subprocess.run([sys.executable, str(ROOT / "scripts" / "core_stubs.py"), "--check"],
                         capture_output=True, text=True, env=_env(), timeout=300)
    assert res.returncode == 0, res.stderr


def _core_sb_options() -> set[str]:
    """The -sb_ options the core registers with PetscOptionsBegin (src/solvers/solver_options.cpp)."""
    text = (ROOT / "src" / "solvers" / "solver_options.cpp").read_text()
    return set(re.findall(r'(?:PetscOptions(?:Bool|Int|Real|String|Enum|EList)|flag|integer|real)\("-(sb_\w+)"', text))


def test_every_core_option_is_read_through_the_help_block():
    """No -sb_ option is read past PetscOptionsBegin (it would be missing from -help)."""
    listed = _core_sb_options()
    for path in (ROOT / "src").rglob("*.cpp"):
        for name in re.findall(r'PetscOptionsGet\w+\([^"]*"-(sb_\w+)"', path.read_text()):
            assert name in listed, f"{path.name} reads -{name}, which -help does not list"


def test_petsc_options_page_lists_every_sb_option_and_prefix():
    doc = (ROOT / "docs" / "petsc-options.md").read_text()
    documented = set(re.findall(r"^\| `-(sb_[a-z0-9_]+)`", doc, flags=re.M))
    assert documented == _core_sb_options()
    for prefix in _core.SOLVER_PREFIXES.values():
        assert f"`{prefix}`" in doc
    known = (ROOT / "python" / "slidebeam" / "petsc_options.txt").read_text().split()
    assert _core_sb_options() <= set(known), "add the new -sb_ options to petsc_options.txt"


def test_help_lists_the_core_options(run_cli):
    res = run_cli("run", str(ROOT / "runs" / "pendulum16.toml"), "--out", "res", "-q", "--set", "analysis.t_end=0.002",
                  "--set", "beam.0.spans=4", "--set", "analysis.integrator=newmark", "--", "-help")
    assert res.returncode == 0, res.stderr
    for name in _core_sb_options():
        assert f"-{name}" in res.stdout
    assert res.stdout.count("slidebeam core options") == 1
    for prefix in ("sb_static_", "sb_ts_", "sb_eq_", "sb_mass_"):
        if prefix != "sb_eq_":  # (the static start is not run here)
            assert f"-{prefix}ksp_type" in res.stdout, prefix
