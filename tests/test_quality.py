"""Lint and formatting are part of the test run, so CI enforces them."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("args", [["check"], ["format", "--check"]], ids=["lint", "format"])
def test_ruff(args):
    """ruff is a test dependency; run it from this interpreter's environment."""
    proc = subprocess.run(
        [sys.executable, "-m", "ruff", *args, "."], cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr


#: Every layer is type-clean, and so are the benchmarks and the examples users copy from;
#: the pure core and the wire contract strictly so.
STRICT = ["facing_service/contract", "facing_service/core"]
EVERY = ["facing_service", "benchmarks", "examples"]


@pytest.mark.parametrize(
    "args",
    [EVERY, ["--strict", *STRICT, "--follow-imports=silent"]],
    ids=["every-layer", "strict-core-and-contract"],
)
def test_mypy_finds_nothing(args):
    """mypy is a test dependency; libraries without type hints are taken as they are."""
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", *args, "--ignore-missing-imports", "--no-error-summary"],
        cwd=ROOT, capture_output=True, text=True,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stdout + proc.stderr


def _asserts(node: ast.AST) -> bool:
    """Whether a test checks anything: an assert, a ``pytest.raises``/``warns`` block, or
    a call of a helper of ours whose name says it checks (``wait_until``, ``check_…``,
    ``assert_…``, ``expect…``, ``*.wait_for``)."""
    for child in ast.walk(node):
        if isinstance(child, ast.Assert):
            return True
        if isinstance(child, ast.Call):
            name = (
                child.func.attr
                if isinstance(child.func, ast.Attribute)
                else getattr(child.func, "id", "")
            )
            if name in {"raises", "warns", "wait_until", "wait_for", "fail"} or name.startswith(
                ("check", "assert", "expect", "wait_until")
            ):
                return True
    return False


def test_every_test_asserts_something():
    """A test that cannot fail proves nothing: each test function checks
    something itself or through a helper that does."""
    empty = []
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        tree = ast.parse(path.read_text())
        helpers = {  # the module's own functions and methods that check
            f.name for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and _asserts(f)
        }
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name.startswith("test_"):
                calls = {
                    c.func.id if isinstance(c.func, ast.Name) else c.func.attr
                    for c in ast.walk(node)
                    if isinstance(c, ast.Call) and isinstance(c.func, ast.Name | ast.Attribute)
                }
                if not _asserts(node) and not calls & helpers:
                    empty.append(f"{path.relative_to(ROOT)}::{node.name}")
    assert not empty, f"tests that check nothing: {empty}"


#: A reader of the code has its words, not the tracker's history: "issue" and a number.
ISSUE_NUMBER = re.compile(r"\b[Ii]ssues?(?: #?|\s*\n[\s#:\"']*)[0-9]+")


def test_no_code_names_an_issue_number():
    """Docstrings and comments say why in plain words; a number from the issue list means
    nothing to a newcomer (the pages in docs/ may cite them, the code may not)."""
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                             check=True).stdout.split()  # fmt: skip
    code = [p for p in tracked if p.endswith((".py", ".toml", ".sh", ".cfg", "Dockerfile"))
            or p.startswith(".ci/")]  # fmt: skip
    found = []
    for path in code:
        text = (ROOT / path).read_text(errors="replace") if (ROOT / path).is_file() else ""
        found += [f"{path}:{text.count(chr(10), 0, m.start()) + 1}: {m.group()!r}"
                  for m in ISSUE_NUMBER.finditer(text)]  # fmt: skip
    assert not found, "\n".join(found)
