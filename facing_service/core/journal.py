"""Transactions over a pure object's dict stores: changes made inside one apply whole, or
not at all. A journal, not a copy: only the keys a call touches are kept, each once,
before its first change (a copy of 10 000 tracks per batch cost more than the batch)."""

from __future__ import annotations

from contextlib import AbstractContextManager
from typing import ClassVar


class Journaled:
    """Base of an object whose state is dicts named in ``STORES``. Each mutator calls
    ``_keep(store, key)`` before changing ``key``; ``transaction()`` puts every kept value
    back when the block raises. Values that are mutable records provide ``__copy__``
    (kept shallow-copied); the others are immutable (kept as they are)."""

    STORES: ClassVar[tuple[str, ...]] = ()
    _journal: dict[str, dict[object, object]] | None = None

    def transaction(self) -> AbstractContextManager[None]:
        """Changes made inside apply whole, or not at all: on an exception every store is
        put back as it was, then the exception goes on."""
        return _Transaction(self)

    def _keep(self, store: str, key: object) -> None:
        """Journal ``key``'s value in ``store`` before its first change in a transaction."""
        journal = self._journal
        if journal is not None and key not in (kept := journal[store]):
            value = getattr(self, store).get(key)
            copy = getattr(value, "__copy__", None)
            kept[key] = value if copy is None else copy()

    def _roll_back(self, journal: dict[str, dict[object, object]]) -> None:
        for store, kept in journal.items():
            values = getattr(self, store)
            for key, value in kept.items():
                if value is None:
                    values.pop(key, None)
                else:
                    values[key] = value
        self._rolled_back()

    def _rolled_back(self) -> None:
        """After a roll-back: put back what the stores' order means (none by default)."""


class _Transaction:
    """``Journaled.transaction()``. A class rather than a generator-based context manager:
    the worker opens one per tracker call, and the generator's machinery was a third of
    a one-pose transaction's cost."""

    __slots__ = ("_owner",)

    def __init__(self, owner: Journaled) -> None:
        self._owner = owner

    def __enter__(self) -> None:
        assert self._owner._journal is None, "transactions do not nest"
        self._owner._journal = {store: {} for store in self._owner.STORES}

    def __exit__(self, kind: type[BaseException] | None, *_: object) -> None:
        journal, self._owner._journal = self._owner._journal, None
        if kind is not None and journal is not None:
            self._owner._roll_back(journal)  # then the exception goes on
