"""Journaled stores (core.journal): every change, and every record read in a transaction,
is undone when the transaction raises; nothing changes a store around its journal."""

from __future__ import annotations

import copy
from dataclasses import dataclass

import pytest
from hypothesis import given
from hypothesis import strategies as st

from facing_service.core.journal import Journal, Store


@dataclass
class Record:
    """A mutable value, kept by ``__copy__`` as the tracker's tracks are."""

    n: int

    def __copy__(self) -> Record:
        return Record(self.n)


def failing(journal: Journal, change) -> None:
    with pytest.raises(RuntimeError), journal.transaction():
        change()
        raise RuntimeError("a bug after the change")


def test_every_way_to_change_a_store_is_undone():
    journal = Journal()
    store: Store[str, int] = Store(journal, [("a", 1), ("b", 2), ("c", 3)])
    before = dict(store)

    def change() -> None:
        store["a"] = 10
        store["new"] = 4
        del store["b"]
        store.pop("c")
        store.setdefault("d", 5)
        store.popitem()
        store.popitem(last=False)
        store.clear()

    failing(journal, change)
    assert dict(store) == before


def test_a_record_read_in_a_transaction_and_changed_in_place_is_put_back():
    journal = Journal()
    store: Store[str, Record] = Store(journal, [("a", Record(1)), ("b", Record(2))])

    def change() -> None:
        store["a"].n = 10  # read, then changed in place: no call to remember
        if (b := store.get("b")) is not None:
            b.n = 20

    failing(journal, change)
    assert store == {"a": Record(1), "b": Record(2)}


def test_a_transaction_that_succeeds_keeps_its_changes_and_its_journal_is_gone():
    journal = Journal()
    store: Store[str, Record] = Store(journal, [("a", Record(1))])
    with journal.transaction():
        store["a"].n = 2
        store["b"] = Record(3)
    assert store == {"a": Record(2), "b": Record(3)}
    store["a"].n = 5  # outside a transaction: nothing kept, nothing to undo later
    failing(journal, lambda: None)
    assert store["a"] == Record(5)


def test_two_stores_share_a_journal_and_the_owner_puts_its_order_back():
    orders = []
    journal = Journal(after_roll_back=lambda: orders.append("sorted"))
    first: Store[str, int] = Store(journal, [("x", 1)])
    second: Store[str, int] = Store(journal)

    def change() -> None:
        first["x"] = 2
        second["y"] = 3
        first.move_to_end("x")

    failing(journal, change)
    assert (dict(first), dict(second), orders) == ({"x": 1}, {}, ["sorted"])


def test_transactions_do_not_nest_and_update_is_refused():
    journal = Journal()
    store: Store[str, int] = Store(journal)
    with journal.transaction(), pytest.raises(AssertionError), journal.transaction():
        pass
    with pytest.raises(TypeError):
        store.update({"a": 1})


OPS = st.lists(
    st.tuples(
        st.sampled_from(["set", "del", "pop", "popitem", "popfirst", "setdefault", "bump"]),
        st.sampled_from("abcde"),
        st.integers(0, 9),
    ),
    max_size=30,
)


@given(start=st.dictionaries(st.sampled_from("abcde"), st.integers(0, 9)), ops=OPS)
def test_any_sequence_of_changes_is_undone_whole(start, ops):
    journal = Journal()
    store: Store[str, Record] = Store(journal, [(k, Record(v)) for k, v in start.items()])
    before = copy.deepcopy(dict(store))

    def change() -> None:
        for op, key, value in ops:
            if op == "set":
                store[key] = Record(value)
            elif op == "del" and key in store:
                del store[key]
            elif op == "pop":
                store.pop(key, None)
            elif op == "popitem" and store:
                store.popitem()
            elif op == "popfirst" and store:
                store.popitem(last=False)
            elif op == "setdefault":
                store.setdefault(key, Record(value))
            elif op == "bump" and (record := store.get(key)) is not None:
                record.n += value

    failing(journal, change)
    assert dict(store) == before


def test_a_peek_keeps_nothing_and_a_later_change_is_still_undone():
    """``peek`` is for reads that change nothing (the tracker reads a last stamp): the
    first real touch after it still keeps the value as it was."""
    journal = Journal()
    store: Store[str, Record] = Store(journal, [("a", Record(1))])

    def change() -> None:
        assert store.peek("a") == Record(1) and store.peek("nobody") is None
        assert store._kept == {}
        store["a"].n = 10

    failing(journal, change)
    assert store["a"] == Record(1)
