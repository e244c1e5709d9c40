# SPDX-License-Identifier: MIT
"""The package's dependencies run one way: no module imports, at any depth of a function, a
module that imports it back (imports under ``if TYPE_CHECKING:`` are for annotations only), and
its rooms depend on the rooms below them only: app -> plots -> output -> run -> scene."""
from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "python" / "slidebeam"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, modules: set[str]) -> set[str]:
    """The package's modules ``path`` imports at run time (relative imports; TYPE_CHECKING skipped)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for child in node.orelse:
                visit(child)
            return
        if isinstance(node, ast.ImportFrom) and node.level > 0:
            base = package.split(".") if package else []
            base = base[: len(base) - (node.level - 1)] if node.level > 1 else base
            target = [*base, *(node.module.split(".") if node.module else [])]
            found.add(".".join(target))
            found.update(".".join([*target, a.name]) for a in node.names)
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(ast.parse(path.read_text()))
    return {m for m in found if m in modules and m != name}


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out: list[list[str]] = []

    def connect(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in graph:
        if v not in index:
            connect(v)
    return out


def test_no_import_cycle():
    files = [p for p in PACKAGE.rglob("*.py")]
    modules = {_module_name(p) for p in files}
    graph = {_module_name(p): _imports(p, modules) for p in files}
    assert graph["run.simulation"] >= {"run.dynamics", "run.model", "run.options_check"}  # the graph is read at all
    assert _cycles(graph) == []


ROOMS = ["scene", "run", "output", "plots", "app"]  # each may import the rooms before it


def test_rooms_depend_on_the_rooms_below_only():
    files = [p for p in PACKAGE.rglob("*.py")]
    modules = {_module_name(p) for p in files}
    rank = {room: k for k, room in enumerate(ROOMS)}
    upward = []
    for p in files:
        name = _module_name(p)
        room = name.split(".")[0]
        if room not in rank:  # the package's own __init__, __main__, _core
            continue
        for target in _imports(p, modules):
            other = target.split(".")[0]
            if other in rank and rank[other] > rank[room]:
                upward.append(f"{name} -> {target}")
    assert sorted(modules) and not upward, upward


def test_a_cycle_is_found():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_history_results_and_checkpoints_name_no_effect():
    """history.csv, summary.json and checkpoints get every effect's values through its outputs
    (OutputSource): their writers call nothing of the sliding joint's own."""
    own = {"JointState", "joint_states", "sliding_joints", "sliding_joint_labels", "sliding_joint_effects",
           "sliding_coordinate_index", "joint_names", "sliding_joint_summary"}
    for name in ("history.py", "results.py", "checkpoint.py"):
        tree = ast.parse((PACKAGE / "output" / name).read_text())
        used = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
        used |= {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
        used |= {a.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) for a in n.names}
        used |= {n.name for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
        assert not used & own, (name, used & own)
