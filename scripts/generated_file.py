# SPDX-License-Identifier: MIT
"""Shared by the scripts that generate a committed file (docs/api.md, docs/scene-reference.md,
python/slidebeam/_core.pyi): write it, or with --check only say whether it is current."""
from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def write_or_check(out: Path, text: str, script: str, check: bool) -> int:
    """Exit code: 0 written or current, 1 out of date (--check)."""
    if check:
        current = out.read_text() if out.is_file() else ""
        if current != text:
            print(f"{out.relative_to(ROOT)} is out of date: run scripts/{script}", file=sys.stderr)
            return 1
        return 0
    out.write_text(text)
    print(f"wrote {out.relative_to(ROOT)}")
    return 0
