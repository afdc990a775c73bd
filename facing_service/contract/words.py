"""How the service's lines say a count ("1 body", "3 bodies", never "1 bodies") and how
long a command runs."""

from __future__ import annotations


def counted(n: int, one: str, many: str) -> str:
    """``n`` and the word for that many."""
    return f"{n} {one if n == 1 else many}"


def for_how_long(duration_s: float | None) -> str:
    """`` for 8 s`` with ``--duration-s 8``, else `` until Ctrl-C``."""
    return f" for {duration_s:g} s" if duration_s else " until Ctrl-C"
