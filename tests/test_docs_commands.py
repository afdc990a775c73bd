"""Every ``facing-service ...`` command the documentation shows is one the CLI accepts as
written: a reader copies them literally (the "Scaling out" diagram once showed a command
that exits 2)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from facing_service.arguments import build_parser

ROOT = Path(__file__).resolve().parent.parent
DOCS = [
    ROOT / "README.md",
    *sorted((ROOT / "docs").glob("*.md")),
    *sorted(ROOT.glob("examples/*/README.md")),
]
_CODE = re.compile(r"```[a-z0-9]*\n(.*?)```|`([^`\n]+)`", re.S)
#: facing-service where a command starts: at the line's start (after VAR=value words), after
#: a path (".venv/bin/"), as what "docker exec NAME" runs, or in a box diagram.
_COMMAND = re.compile(
    r"(?:^(?:[A-Z_]+=\S+\s+)*|/|exec\s+\S+\s+|[─┌└├│┼]\s*)facing-service((?:[ \t]+[^\s|&;)#]+)+)"
)


def documented_commands() -> list[tuple[str, str]]:
    """(where, command line) of every facing-service invocation in code in the docs."""
    found = []
    for doc in DOCS:
        for match in _CODE.finditer(doc.read_text()):
            code = (match[1] or match[2]).replace("\\\n", " ")
            for line in code.splitlines():
                for command in _COMMAND.finditer(line):
                    found.append((f"{doc.relative_to(ROOT)}: {line.strip()}", command[1].strip()))
    return found


def test_the_docs_show_commands():
    commands = [c for _, c in documented_commands()]
    assert any(c.startswith("router ") for c in commands)
    assert any(c.startswith("run ") for c in commands)


@pytest.mark.parametrize(("where", "command"), documented_commands(), ids=lambda v: v[:60])
def test_a_documented_command_parses(where, command):
    try:
        build_parser().parse_args(shlex.split(command))
    except SystemExit as exit_:
        pytest.fail(f"{where}: 'facing-service {command}' exits {exit_.code}")
