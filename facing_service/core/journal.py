"""Transactions over a pure object's state: changes made inside one apply whole, or not
at all.

The state lives in ``Store``s, ordered dicts that keep their own journal: every way to
change a store, and every read inside a transaction (what is read may be a mutable
record about to be changed in place), first keeps the key's value, once per transaction.
So nothing changes a store around its journal, and no call site has to remember to ask.
A journal, not a copy: only the keys a call touches are kept (a copy of 10 000 tracks per
batch cost more than the batch). Values that are mutable records provide ``__copy__``
(kept shallow-copied); the others are immutable (kept as they are).

Order is not journaled: ``move_to_end`` only reorders, and an owner whose order means
something puts it back after a roll-back (``Journal(after_roll_back=...)``).
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Iterable
from typing import Any, Generic, TypeVar

K = TypeVar("K")
V = TypeVar("V")

_ABSENT: Any = object()  # a key that was not in the store: a roll-back removes it


class Journal:
    """The undo log of one owner's stores, open during a transaction only: each store
    keeps its own part (``Store._kept``), so a touch costs one dict lookup."""

    __slots__ = ("_after_roll_back", "_stores", "open")

    def __init__(self, after_roll_back: Callable[[], None] | None = None) -> None:
        self._stores: list[Store[Any, Any]] = []
        self._after_roll_back = after_roll_back
        self.open = False

    def transaction(self) -> _Transaction:
        """Changes made inside apply whole, or not at all: on an exception every store is
        put back as it was, then the exception goes on."""
        return _Transaction(self)

    def register(self, store: Store[Any, Any]) -> None:
        self._stores.append(store)

    def _begin(self) -> None:
        assert not self.open, "transactions do not nest"
        self.open = True
        for store in self._stores:
            store._kept = {}

    def _end(self, failed: bool) -> None:
        self.open = False
        touched = False
        for store in self._stores:
            kept, store._kept = store._kept, None
            if failed and kept:
                touched = True
                for key, value in kept.items():
                    if value is _ABSENT:
                        OrderedDict.pop(store, key, None)
                    else:
                        OrderedDict.__setitem__(store, key, value)
        if touched and self._after_roll_back is not None:
            self._after_roll_back()


class _Transaction:
    """``Journal.transaction()``. A class rather than a generator-based context manager:
    the worker opens one per tracker call, and the generator's machinery was a third of
    a one-pose transaction's cost."""

    __slots__ = ("_journal",)

    def __init__(self, journal: Journal) -> None:
        self._journal = journal

    def __enter__(self) -> None:
        self._journal._begin()

    def __exit__(self, kind: type[BaseException] | None, *_: object) -> None:
        self._journal._end(kind is not None)  # then any exception goes on


class Store(OrderedDict[K, V], Generic[K, V]):
    """An ordered dict whose every change, and every read in a transaction, is journaled
    first (see the module). Iterating (``items()``, ``values()``) is not: what is changed
    after it goes through a journaled method."""

    def __init__(self, journal: Journal, items: Iterable[tuple[K, V]] = ()) -> None:
        super().__init__()
        #: Each touched key's value before the transaction's first touch; None outside one.
        self._kept: dict[K, object] | None = None
        journal.register(self)
        for key, value in items:
            OrderedDict.__setitem__(self, key, value)

    def _keep(self, key: K) -> None:
        """``key``'s value, kept before its first touch in a transaction."""
        kept = self._kept
        if kept is None or key in kept:
            return
        value = OrderedDict.get(self, key, _ABSENT)
        copy = getattr(value, "__copy__", None)
        kept[key] = value if copy is None else copy()

    def peek(self, key: K) -> V | None:
        """A read that changes nothing through what it returns (a stamp, say): not kept."""
        return OrderedDict.get(self, key)

    def __getitem__(self, key: K) -> V:
        self._keep(key)
        return super().__getitem__(key)

    def get(self, key: K, default: Any = None) -> Any:
        kept = self._kept
        if kept is None or key in kept or key not in self:  # nothing to keep: the hot path
            return super().get(key, default)
        self._keep(key)
        return super().get(key, default)

    def __setitem__(self, key: K, value: V) -> None:
        self._keep(key)
        super().__setitem__(key, value)

    def __delitem__(self, key: K) -> None:
        self._keep(key)
        super().__delitem__(key)

    def pop(self, key: K, *default: Any) -> Any:
        self._keep(key)
        return super().pop(key, *default)

    def popitem(self, last: bool = True) -> tuple[K, V]:
        if self:
            self._keep(next(reversed(self)) if last else next(iter(self)))
        return super().popitem(last)

    def setdefault(self, key: K, default: V) -> V:
        self._keep(key)
        return super().setdefault(key, default)

    def clear(self) -> None:
        for key in list(self):
            self._keep(key)
        super().clear()

    def update(self, *_: Any, **__: Any) -> None:
        raise TypeError("Store.update: set each key (journaled) instead")
