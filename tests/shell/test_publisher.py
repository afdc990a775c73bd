"""The publisher thread moves bytes: each publication to the sender of its kind, in order,
counted; every sender closed when the outbox is closed and empty."""

from __future__ import annotations

import threading
import time

import zenoh

from facing_service.shell.ledger import Ledger
from facing_service.shell.outbox import Kind, Outbox, Publication
from facing_service.shell.publisher import Publisher


class Recording:
    """A sender of our own (not a stand-in for zenoh): what it was given, in order."""

    def __init__(self, kinds: set[Kind], sent: list[tuple[str, str]], name: str) -> None:
        self.kinds = frozenset(kinds)
        self._sent, self._name = sent, name
        self.closed = False

    def send(self, publication: Publication) -> None:
        if publication.key == "fail":
            raise zenoh.ZError("refused")
        self._sent.append((self._name, publication.key))

    def close(self) -> None:
        self.closed = True


class Form:
    def __init__(self, sender: Recording) -> None:
        self._sender = sender

    def sender(self, session: zenoh.Session) -> Recording:
        assert isinstance(session, zenoh.Session)  # declared on the publisher's thread
        return self._sender


def test_each_publication_goes_to_its_senders_in_order_and_is_counted(net):
    _, ep = net.service()
    session = net.client(ep)
    sent: list[tuple[str, str]] = []
    json_sender = Recording({Kind.RESULT, Kind.FRAME}, sent, "json")
    ros_sender = Recording({Kind.ROS}, sent, "ros")
    outbox, ledger = Outbox(), Ledger(time.monotonic)
    publisher = Publisher(
        session, outbox, ledger, threading.Event(), [Form(json_sender), Form(ros_sender)]
    )
    outbox.add(
        [
            Publication("r1", b"{}", Kind.RESULT),
            Publication("/topic", b"\0", Kind.ROS, "hri_msgs/msg/IdsList"),
            Publication("fail", b"{}", Kind.FRAME),
            Publication("r1", None, Kind.RESULT),  # r1 lost: a DELETE
        ]
    )
    outbox.close()
    thread = threading.Thread(target=publisher.run)
    thread.start()
    thread.join(5)
    assert not thread.is_alive()
    assert sent == [("json", "r1"), ("ros", "/topic"), ("json", "r1")]
    counts = ledger.sent
    assert counts["results_published"] == 1 and counts["ros_published"] == 1
    assert counts["deletes_published"] == 1 and counts["publish_errors"] == 1
    assert len(outbox) == 0 and json_sender.closed and ros_sender.closed
