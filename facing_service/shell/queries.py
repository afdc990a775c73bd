"""Queries on the service's output key spaces, answered by the worker in order with the
samples (a query sent after a pose sees its result) from the turn's snapshot of the tracker
and the scenes (as everything else the service says is read), never the network."""

from __future__ import annotations

from dataclasses import dataclass

import zenoh

from ..contract import keys
from ..contract.errors import unknown_frame_detail
from ..contract.schemas import QueryError
from ..contract.stamps import ZERO
from ..core.records import frame_facing
from ..core.snapshot import TurnSnapshot
from ..core.social.scene import nobody
from .json_sender import JSON
from .ledger import Ledger
from .publications import (
    SCENE_SPACES,
    QuerySpace,
    Speaker,
    frame_json,
    query_replies,
    threshold_parameter,
)


@dataclass(frozen=True)
class QueryItem:
    query: zenoh.Query
    space: QuerySpace  # which output key space it reached us through


class Answers:
    """Answers the worker's queries as this service (``namespace``, ``instance``), counted
    in ``ledger``; ``served``: the one base frame it reads, known before anyone is in it
    (``*``: any)."""

    def __init__(self, namespace: str, instance: str, ledger: Ledger, served: str) -> None:
        self.us = Speaker(namespace, instance)
        self._ledger = ledger
        self._served = served

    def __call__(self, item: QueryItem, snapshot: TurnSnapshot) -> None:
        answer(item, snapshot, self._ledger, self.us, self._served)


def answer(
    item: QueryItem, snapshot: TurnSnapshot, ledger: Ledger, us: Speaker, served: str
) -> None:
    """Reply with the current state of every matching key, one reply per key."""
    query = item.query
    try:
        threshold = threshold_parameter(
            dict(query.parameters),  # type: ignore[call-overload]  # (stubs: no __iter__)
            item.space,
        )
    except ValueError as error:
        ledger.count("queries_refused")  # before the reply: a status read after it agrees
        query.reply_err(
            QueryError(error="bad_parameter", detail=str(error)).model_dump_json(),
            encoding=JSON,
        )
        query.drop()
        return
    states, frames = (
        (snapshot.states, snapshot.frames) if threshold is None else snapshot.evaluate(threshold)
    )
    engagements = snapshot.engagements if item.space is QuerySpace.ENGAGEMENT else []
    replies = [
        (key, payload)
        for key, payload in query_replies(
            item.space, us, states, frames, engagements, snapshot.scenes
        )
        if query.key_expr.intersects(zenoh.KeyExpr(key))
    ]
    if not replies:
        selector = str(query.key_expr)
        replies, refusal = _nothing_matched(item.space, selector, snapshot, us, served)
    else:
        refusal = None
    ledger.count("queries_answered")  # before the replies: a status read after them agrees
    if refusal is not None:
        query.reply_err(refusal.model_dump_json(), encoding=JSON)
    for key, payload in replies:
        query.reply(key, payload, encoding=JSON)
    query.drop()


def _nothing_matched(
    space: QuerySpace, selector: str, snapshot: TurnSnapshot, us: Speaker, served: str
) -> tuple[list[tuple[str, bytes]], QueryError | None]:
    """A query that names one frame (its last chunk) and matched nothing still gets an
    answer, so "no service", "nobody there" and "wrong frame" differ: a frame this service
    knows (has seen, or reads alone: ``served``, before anyone is there)
    answers with its empty list (groups, who faces whom, the frame's facing list) or, on
    per-body keys, ``empty_frame`` (nobody there) or ``not_tracked`` (others are); any
    other ``unknown_frame``, naming the frames tracked.
    A wildcard frame that matches nothing stays unanswered (a ``**`` query reaches every
    queryable, and would collect one refusal from each)."""
    frame = selector.rsplit("/", 1)[-1]
    if "*" in frame or "$" in frame:
        return [], None
    ns, instance = us
    empty = snapshot.empty_scene(frame)
    if empty is None and frame not in snapshot.tracked and frame != served:
        detail = unknown_frame_detail(frame, snapshot.tracked)
        return [], QueryError(error="unknown_frame", detail=detail)
    scene = empty or nobody(frame, ZERO)
    if space in SCENE_SPACES:
        return query_replies(space, us, (), (), (), [scene]), None
    if space is QuerySpace.FRAME:
        said = frame_json(
            frame_facing(frame, empty.stamp if empty is not None else None, [], []), instance
        )
        return [(keys.frame_key(ns, frame), said)], None
    if snapshot.tracked.get(frame, 0):  # others are there: the body asked for is not
        detail = f"no body matching {selector!r} is tracked in frame {frame!r} now"
        return [], QueryError(error="not_tracked", detail=detail)
    detail = f"nobody is tracked in frame {frame!r} now"
    return [], QueryError(error="empty_frame", detail=detail)
