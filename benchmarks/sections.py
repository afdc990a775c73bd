"""Measured sections of the docs, rewritten from results files between two marker lines,
so that a page's figures are generated, never copied by hand."""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

from . import results_file


def replace_section(text: str, begin: str, end: str, lines: list[str]) -> str:
    """``text`` with what stands between its ``begin`` and ``end`` lines made ``lines``."""
    head, sep, rest = text.partition(begin)
    if not sep:
        raise SystemExit(f"no '{begin}' line")
    _, sep, tail = rest.partition(end)
    if not sep:
        raise SystemExit(f"no '{end}' line after '{begin}'")
    return "\n".join([head + begin, *lines, end]) + tail


def generate(
    page: Path,
    results: Path,
    begin: str,
    end: str,
    tables: Callable[[Any], list[str]],
    check: bool,
    command: str,
) -> int:
    """Rewrite ``page``'s section between ``begin`` and ``end`` from the ``results`` JSON
    (``tables`` makes its lines); with ``check``, write nothing and return 1 when the page
    differs, saying which ``command`` regenerates it."""
    text = page.read_text()
    new = replace_section(text, begin, end, tables(json.loads(results.read_text())))
    if new == text:
        return 0
    if check:
        print(f"{page.name} is stale against {results.name} ({command})")
        return 1
    page.write_text(new)
    return 0


def measured_or_page(
    argv: list[str] | None,
    description: str,
    module: str,
    section: tuple[Path, Path, str, str],
    tables: Callable[[Any], list[str]],
    evaluate: Callable[[], Any],
) -> int:
    """The command of a benchmark a page shows: measure (``--out F`` writes the results),
    or ``--page`` rewrite the page's ``section`` (page, results, begin and end lines)
    from the committed results (``--check``: write nothing, exit 1 if it is stale)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--out", type=Path, help="write the results as JSON")
    parser.add_argument("--page", action="store_true", help=f"rewrite {section[0].name}'s table")
    parser.add_argument("--check", action="store_true", help="with --page: exit 1 if stale")
    args = parser.parse_args(argv)
    command = f"python -m {module}"
    if args.page:
        return generate(*section, tables, args.check, f"{command} --page")
    results = evaluate()
    return results_file.report(tables(results), results, args.out, command, vars(args))
