"""How the service's lines say a count: "1 body", "3 bodies", never "1 bodies"."""

from __future__ import annotations


def counted(n: int, one: str, many: str) -> str:
    """``n`` and the word for that many."""
    return f"{n} {one if n == 1 else many}"
