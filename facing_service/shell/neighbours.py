"""Another facing service in this one's namespace whose frames overlap: said in the log.

Two services reading the same poses answer twice: every result arrives twice on
``NS/bodies/*/facing/*`` and nothing said so. Services in one namespace are
fine when sharded by frame (``--base-frame map`` beside ``--base-frame camera_left``).
Each service holds a liveliness token, so each learns when another appears (the newer one
from the token's history): it then asks the statuses in the namespace and warns, once per
other service, when that one reads frames this one reads too. Two given the same
``--instance`` (two containers with one ``FACING_INSTANCE``; two in one process) share
one token: the older one sees no new token then, so the statuses are also asked every
``PERIOD_S``; services are told apart by their zenoh id.
"""

from __future__ import annotations

import logging
import threading

import zenoh

from ..contract import keys
from ..contract.schemas import ServiceStatus

log = logging.getLogger("facing_service")

#: How long the statuses are waited for, after a token appeared.
ASK_S = 2.0
#: How often they are asked all the same (a second service of the same instance name).
PERIOD_S = 10.0
#: The first asks come sooner: a service just started asks before its session has met the
#: others (its own token's history wakes it at once), and would otherwise learn of them
#: only a period later (seen in CI under load: not within 15 s).
FIRST_WAITS_S = (1.0, 2.0)


def overlapping(ours: str, theirs: str) -> bool:
    """Whether two services' base frames share poses (``*``: every frame)."""
    return keys.ALL_FRAMES in (ours, theirs) or ours == theirs


class Neighbours:
    """Watches the namespace's service tokens on ``session`` and says each other service
    whose frames overlap ``base_frame`` (once per zenoh id; one that reads other frames
    at info level, once: that the question was asked and answered)."""

    def __init__(self, session: zenoh.Session, namespace: str, base_frame: str) -> None:
        self._session, self._namespace, self._base_frame = session, namespace, base_frame
        self._said: set[str] = set()
        self._due = threading.Event()
        self._closing = threading.Event()
        self._thread = threading.Thread(target=self._run, name="facing-neighbours", daemon=True)
        self._tokens = session.liveliness().declare_subscriber(
            keys.service_token(namespace, "*"), self._on_token, history=True
        )
        self._thread.start()

    def close(self) -> None:
        """Undeclared at once; a question in flight ends with the session (the thread is
        a daemon, not waited for: SIGTERM's 2 s are the service's)."""
        self._closing.set()
        self._due.set()
        self._tokens.undeclare()

    def _on_token(self, sample: zenoh.Sample) -> None:  # zenoh's thread: a flag only
        if sample.kind == zenoh.SampleKind.PUT:
            self._due.set()

    def _run(self) -> None:
        waits = iter(FIRST_WAITS_S)
        while not self._closing.is_set():
            self._due.wait(next(waits, PERIOD_S))
            self._due.clear()
            if self._closing.is_set():
                return
            try:
                self._ask()
            except zenoh.ZError:  # the session closing under the question
                return

    def _ask(self) -> None:
        own = str(self._session.zid())
        selector = keys.status_key(self._namespace, "*")
        for reply in self._session.get(selector, timeout=ASK_S):
            replier = reply.replier_id
            if reply.ok is None or replier is None or str(replier.zid) in self._said | {own}:
                continue
            try:
                other = ServiceStatus.model_validate_json(reply.ok.payload.to_bytes())
            except ValueError:
                continue
            theirs = str(other.config.get("base_frame", keys.ALL_FRAMES))
            self._said.add(str(replier.zid))
            if not overlapping(self._base_frame, theirs):  # sharded by frame: fine, said once
                log.info(
                    "another facing service in namespace %r reads other frames: instance "
                    "%s (base frame %s; this one's %s)",
                    self._namespace, other.instance, theirs, self._base_frame,
                )  # fmt: skip
                continue
            log.warning(
                "another facing service reads the same poses in namespace %r: instance %s "
                "(zenoh id %s, base frame %s; this one's %s): consumers get every result "
                "twice. Give each its own --namespace, or --base-frame (docs/operations.md, "
                "two services in one namespace)",
                self._namespace, other.instance, replier.zid, theirs, self._base_frame,
            )  # fmt: skip
