# SPDX-License-Identifier: MIT
"""The documentation stays inside the repository and its links resolve: no tracked file names
notes that are not in the repository, and every relative link in README.md and docs/*.md points
to an existing file (and, for links into a markdown file, to an existing heading)."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import unicodedata
from collections.abc import Iterator
from pathlib import Path
from urllib.parse import unquote

import pytest

ROOT = Path(__file__).resolve().parents[2]

# names of notes outside the repository (written in pieces, so that this file does not match itself)
OUTSIDE = ["formulation" + ".md", "benchmarks" + ".md", "../" + "shared", "shared/" + "spec",
           "locking-free-beams" + ".md", "performance-notes" + ".md", "style-anchors" + ".md"]
BINARY = {".so", ".png", ".h5", ".pdf", ".gz", ".whl", ".o", ".a"}


def _tracked_files() -> list[Path]:
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
        return [ROOT / name for name in out.decode().split("\0") if name]
    except (OSError, subprocess.CalledProcessError):  # not a git checkout: every file but the build's
        return [p for p in ROOT.rglob("*") if p.is_file()
                and not {".git", "build", "__pycache__"} & set(p.relative_to(ROOT).parts)]


def _text_lines() -> Iterator[tuple[Path, int, str]]:
    """(file, line number, line) of every tracked text file."""
    for path in _tracked_files():
        if path.suffix in BINARY or not path.is_file():
            continue
        try:
            text = path.read_text()
        except UnicodeDecodeError:
            continue
        for n, line in enumerate(text.splitlines(), 1):
            yield path, n, line


def test_no_file_points_outside_the_repository():
    hits = []
    for path, n, line in _text_lines():
        for name in OUTSIDE:
            if name in line:
                hits.append(f"{path.relative_to(ROOT)}:{n}: {name}")
    assert not hits, "files point to notes outside the repository (use docs/theory.md or docs/verification.md):\n" \
        + "\n".join(hits)


def _markdown_files() -> list[Path]:
    return [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = heading.strip().replace("`", "").replace("*", "").lower()
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    out = "".join(c for c in text if c in " -_" or unicodedata.category(c)[0] in "LN")
    return out.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    anchors: set[str] = set()
    seen: dict[str, int] = {}
    in_code = False
    for line in path.read_text().splitlines():
        if line.startswith("```"):
            in_code = not in_code
        if in_code:
            continue
        m = re.match(r"#{1,6}\s+(.*)", line)
        if m:
            slug = _slug(m.group(1))
            n = seen.get(slug, 0)
            seen[slug] = n + 1
            anchors.add(slug if n == 0 else f"{slug}-{n}")
    return anchors


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def _links(path: Path) -> list[tuple[int, str]]:
    out = []
    in_code = False
    for n, line in enumerate(path.read_text().splitlines(), 1):
        if line.startswith("```"):
            in_code = not in_code
        if in_code:
            continue
        line = re.sub(r"`[^`]*`", "", line)  # links are not written inside code
        out += [(n, m.group(1)) for m in LINK.finditer(line)]
    return out


@pytest.mark.parametrize("path", _markdown_files(), ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_resolve(path):
    broken = []
    for n, target in _links(path):
        if re.match(r"[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
            continue
        file_part, _, anchor = target.partition("#")
        dest = path if not file_part else (path.parent / unquote(file_part)).resolve()
        if not dest.exists():
            broken.append(f"{path.relative_to(ROOT)}:{n}: {target} (no such file)")
            continue
        if anchor and dest.suffix == ".md" and anchor not in _anchors(dest):
            broken.append(f"{path.relative_to(ROOT)}:{n}: {target} (no such heading)")
    assert not broken, "\n".join(broken)


def test_readme_is_a_front_door():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) <= 200
    # the two commands stay exactly as CI and users know them
    assert "scripts/setup.sh && scripts/slidebeam run runs/rollup.toml" in readme
    assert "scripts/test.sh " in readme
    assert "docs/install.md" in readme


def test_slug():
    assert _slug("Section forces: a hanging rope against Irvine's elastic catenary") == \
        "section-forces-a-hanging-rope-against-irvines-elastic-catenary"
    assert _slug("45° bend (runs/bend45.toml, P = 600): distance") == "45-bend-runsbend45toml-p--600-distance"
    assert _slug("The sliding joint and the seed's benchmark") == "the-sliding-joint-and-the-seeds-benchmark"
    assert _slug("time_function") == "time_function"
    assert _slug("Damping and the energy balance (`tests/python/test_damping.py`)") == \
        "damping-and-the-energy-balance-testspythontest_dampingpy"


SECTION_REF = re.compile(r'docs/([a-z_-]+\.md),? \(?"([^"]+)"')


def _headings(path: Path) -> list[str]:
    out, in_code = [], False
    for line in path.read_text().splitlines():
        if line.startswith("```"):
            in_code = not in_code
        m = None if in_code else re.match(r"#{1,6}\s+(.*)", line)
        if m:
            out.append(m.group(1).replace("`", "").strip())
    return out


def test_sections_named_in_files_exist():
    """A comment or docstring that names a section (docs/theory.md, "The schemes") names one
    that exists: some heading of that file begins with the name."""
    broken = []
    for path, n, line in _text_lines():
        for doc, name in SECTION_REF.findall(line):
            target = ROOT / "docs" / doc
            if not target.is_file():
                broken.append(f"{path.relative_to(ROOT)}:{n}: docs/{doc} does not exist")
            elif not any(h.startswith(name) for h in _headings(target)):
                broken.append(f"{path.relative_to(ROOT)}:{n}: docs/{doc} has no section \"{name}\"")
    assert not broken, "\n".join(broken)


@pytest.mark.skip_in_parallel
def test_the_readme_python_example_runs(tmp_path):
    """The README's "From Python" block, run as written from the repository's root (its output
    folder moved into tmp_path): it writes what its comments say."""
    text = (ROOT / "README.md").read_text()
    block = text.split("## From Python", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    assert "write_results" in block
    code = block.replace('"out/rollup"', repr(str(tmp_path / "rollup")))
    env = {**os.environ, "PYTHONPATH": str(ROOT / "python")}
    res = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    for name in ("history.csv", "final_configuration.csv", "summary.json"):
        assert (tmp_path / "rollup" / name).is_file(), name
