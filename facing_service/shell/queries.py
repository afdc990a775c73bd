"""Queries on the service's output key spaces, answered by the worker in order with the
samples (a query sent after a pose sees its result) from the tracker's and the scenes'
state, never the network."""

from __future__ import annotations

from dataclasses import dataclass

import zenoh

from ..config.settings import Settings
from ..contract.schemas import QueryError
from ..core.scene import Scenes
from ..core.tracker import Tracker
from .ledger import Ledger
from .publications import query_replies, threshold_parameter
from .publisher import JSON


@dataclass(frozen=True)
class QueryItem:
    query: zenoh.Query
    space: str  # which output key space it reached us through (publications.QUERY_SPACES)


def answer(
    item: QueryItem, tracker: Tracker, scenes: Scenes, ledger: Ledger, settings: Settings
) -> None:
    """Reply with the current state of every matching key, one reply per key."""
    query = item.query
    try:
        threshold = threshold_parameter(dict(query.parameters), item.space)
    except ValueError as error:
        query.reply_err(
            QueryError(error="bad_parameter", detail=str(error)).model_dump_json(),
            encoding=JSON,
        )
        query.drop()
        ledger.count("queries_refused")
        return
    # The status then agrees with the answer (a client reading it next sees the same).
    ledger.tracked = tracker.tracked_per_frame()
    if threshold is None:
        states, frames = tracker.states(), tracker.frames()
    else:
        states, frames = tracker.evaluate(threshold)
    engagements = tracker.engagements() if item.space == "engagement" else []
    ns, me = settings.namespace, settings.instance
    replies = query_replies(item.space, ns, me, states, frames, engagements, scenes.current())
    for key, payload in replies:
        if query.key_expr.intersects(zenoh.KeyExpr(key)):
            query.reply(key, payload, encoding=JSON)
    query.drop()
    ledger.count("queries_answered")
