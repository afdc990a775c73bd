"""Measured sections of the docs, rewritten from results files between two marker lines,
so that a page's figures are generated, never copied by hand."""

from __future__ import annotations


def replace_section(text: str, begin: str, end: str, lines: list[str]) -> str:
    """``text`` with what stands between its ``begin`` and ``end`` lines made ``lines``."""
    head, sep, rest = text.partition(begin)
    if not sep:
        raise SystemExit(f"no '{begin}' line")
    _, sep, tail = rest.partition(end)
    if not sep:
        raise SystemExit(f"no '{end}' line after '{begin}'")
    return "\n".join([head + begin, *lines, end]) + tail
