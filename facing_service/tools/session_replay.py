"""``facing-service replay SESSION.mcap``: a session recorded by ``record`` played into a
service again: its input poses, and the DELETEs of them, at the recorded pace (times
``rate``), on the keys they came on (under ``--namespace`` when the recording's was
another), with BLOCK. What the service published then stays in the file to compare with
what it publishes now (``--record``: this run's, into a second file)."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import zenoh

from .pace import RecordedPace
from .session_mcap import DELETES, PROFILE, is_input

MAGIC = b"\x89MCAP0\r\n"


def is_session(path: Path) -> bool:
    """Whether ``path`` is an MCAP file ``record`` wrote, not a ROS 2 bag's: its Header
    record's profile (opcode 1, a u64 length, then the profile as a u32-prefixed string,
    per the MCAP specification), read by hand so telling needs no extra."""
    if path.suffix != ".mcap" or not path.is_file():
        return False
    with path.open("rb") as stream:
        head = stream.read(len(MAGIC) + 1 + 8 + 4 + 64)
    at = len(MAGIC) + 1 + 8
    if not head.startswith(MAGIC) or len(head) < at + 4 or head[len(MAGIC)] != 0x01:
        return False
    size = int.from_bytes(head[at : at + 4], "little")
    return head[at + 4 : at + 4 + size] == PROFILE.encode()


@dataclass
class SessionReplayed:
    poses: int = 0
    deletes: int = 0
    duration_s: float = 0.0  # of the recording's inputs
    elapsed_s: float = 0.0


def recorded_inputs(path: Path) -> tuple[str, Iterator[tuple[int, str, bytes | None]]]:
    """The recording's namespace, and its inputs in order: ``(log time ns, key, payload)``,
    None for a DELETE."""
    from mcap.reader import make_reader

    stream = path.open("rb")
    reader = make_reader(stream)
    metadata = {m.name: m.metadata for m in reader.iter_metadata()}
    namespace = metadata.get("session", {}).get("namespace", "hri")

    def inputs() -> Iterator[tuple[int, str, bytes | None]]:
        with stream:
            for _, channel, message in reader.iter_messages(log_time_order=True):
                if channel.topic == DELETES:
                    key = json.loads(message.data)["key"]
                    if is_input(namespace, key):
                        yield message.log_time, key, None
                elif is_input(namespace, channel.topic):
                    yield message.log_time, channel.topic, message.data

    return namespace, inputs()


def play(
    session: zenoh.Session,
    path: Path,
    namespace: str,
    rate: float = 1.0,
    should_stop: Callable[[], bool] = lambda: False,
) -> SessionReplayed:
    """Send the recording's inputs on ``session`` into ``namespace``."""
    recorded, inputs = recorded_inputs(path)
    played = SessionReplayed()
    pace = RecordedPace(rate)
    block = zenoh.CongestionControl.BLOCK
    for log_time, key, payload in inputs:
        if should_stop():
            break
        pace.wait(log_time)
        key = namespace + key[len(recorded) :]
        if payload is None:
            session.delete(key, congestion_control=block)
            played.deletes += 1
        else:
            session.put(key, payload, encoding=zenoh.Encoding.APPLICATION_JSON,
                        congestion_control=block)  # fmt: skip
            played.poses += 1
        played.duration_s = pace.recorded_s(log_time)
    played.elapsed_s = pace.elapsed_s()
    return played
