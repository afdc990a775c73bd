"""The service's input forms, as types: one ``Input`` protocol, one class per form.

Each form owns its zenoh keys (the hot key the worker pulls from zenoh's channel, and any
side subscriptions, whose samples reach the worker through the intake), turns what
arrives into poses for the tracker, losses and counted rejections, and says its own part
of the status, the start line and the diagnosis. The worker handles any form alike: a
third form is a third class (``JsonInput`` here, ``ros_input.RosInput``), not a branch.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import zenoh

from ..contract import keys
from ..contract.keys import BodyRef
from ..contract.poses import Rejected, Rejection, decode_pose
from ..contract.schemas import Ros2Status
from ..core.records import PoseSample
from .declared_keys import DeclaredKeys
from .ledger import Ledger

log = logging.getLogger("facing_service")

#: How many distinct invalid keys are each said in a line of their own (then only counted).
SAID_KEYS = 100


@dataclass(frozen=True, slots=True)
class Loss:
    """Bodies the input says are gone, applied after the poses read before it (in order).
    ``time_went_back``: the sender's clock restarted, so older stamps are its new timeline."""

    bodies: list[BodyRef]
    time_went_back: bool = False


@dataclass(frozen=True, slots=True)
class OtherFrame:
    """A pose's key in another frame than a fixed base frame's (its payload unread)."""

    key: str


class Input(Protocol):
    def hot_key(self) -> str:
        """The key expression the worker reads straight from zenoh's channel."""
        ...

    def open(self, session: zenoh.Session, hand_off: Callable[[object], None]) -> str:
        """Declare the side subscriptions (their samples go to ``hand_off``, the intake);
        what is read, as the start line says it."""
        ...

    def read(self, item: object, poses: list[PoseSample]) -> Loss | None:
        """One sample (from the hot key or a side subscription): its poses appended to
        ``poses``, its rejections counted; a loss, which the worker applies after them.
        A sample read whole adds one to ``read_whole``."""
        ...

    @property
    def read_whole(self) -> int:
        """Samples read whole so far: the input speaking (a refused one is not; the
        worker tells a silent input by this)."""
        ...

    def origin(self, sample: PoseSample) -> str:
        """Where a pose came from, as its sender names it (for a rejection's log line)."""
        ...

    def forget(self, bodies: list[BodyRef]) -> None:
        """The tracker lost these bodies: let go of what the input holds for them."""
        ...

    def next_due(self) -> float | None:
        """When ``diagnose`` has work next (the service's clock), if ever."""
        ...

    def diagnose(self) -> None:
        """Why the input may give no results, logged when that changes; due or not."""
        ...

    def status(self) -> Ros2Status | None:
        """The input's part of the status (the robot's, for ROS 2 input)."""
        ...

    def start_line(self) -> str:
        """The input's part of the start line, after the pose keys ('' for none)."""
        ...

    def close(self) -> None: ...


class JsonInput:
    """Poses as JSON on ``NS/bodies/<id>/pose/<frame>`` (docs/contract.md); a DELETE on a
    pose key loses the body. On the side, the keys a mistyped pose lands on
    (``keys.mistyped_pose_keys``), refused as invalid keys: counted and logged like any
    other rejection. Nothing to diagnose.

    Each tracked body's pose key is declared to zenoh (``DeclaredKeys``: why), from its
    first pose until it is lost, so that poses arrive on a cached route.

    With a fixed base frame, poses in the other frames are watched for until the first
    pose in that frame arrives (``--base-frame base_lnk`` dropped every pose
    without a word): each is refused as ``other_frame``, and the frames they come in are
    said once. The watch then stops, so it costs nothing once poses flow."""

    def __init__(
        self, namespace: str, base_frame: str, max_payload_bytes: int, max_bodies: int,
        ledger: Ledger,
    ) -> None:  # fmt: skip
        self._namespace = namespace
        self._base_frame = base_frame
        self._subscription = keys.pose_subscription(namespace, base_frame)
        self._other_frames: zenoh.Subscriber[None] | None = None  # until a pose in ours
        self._said_other_frames = False
        self._limit = max_payload_bytes
        self._pose_key = keys.PoseKeyParser(namespace, 2 * max_bodies)
        self._ledger = ledger
        self._mistyped: list[zenoh.Subscriber[None]] = []
        self._said: set[str] = set()  # the invalid keys said in the log
        self._capacity = max_bodies
        self.declared_keys: DeclaredKeys | None = None  # the pose keys declared, once open
        self.read_whole = 0  # samples read whole: a pose decoded, or a DELETE of a body

    def hot_key(self) -> str:
        return self._subscription

    def open(self, session: zenoh.Session, hand_off: Callable[[object], None]) -> str:
        self.declared_keys = DeclaredKeys(session, self._capacity)
        self._mistyped = [
            session.declare_subscriber(key, hand_off, allowed_origin=zenoh.Locality.REMOTE)
            for key in keys.mistyped_pose_keys(self._namespace)
        ]
        if self._base_frame != keys.ALL_FRAMES:
            ours = f"/pose/{self._base_frame}"

            def other_frame(sample: zenoh.Sample) -> None:  # zenoh's thread: a key test only
                key = str(sample.key_expr)
                if not key.endswith(ours):
                    hand_off(OtherFrame(key))

            self._other_frames = session.declare_subscriber(
                keys.pose_subscription(self._namespace, keys.ALL_FRAMES),
                other_frame,
                allowed_origin=zenoh.Locality.REMOTE,
            )
        return self._subscription

    def read(self, item: object, poses: list[PoseSample]) -> Loss | None:
        if isinstance(item, OtherFrame):
            self._refuse_other_frame(item.key)
            return None
        assert isinstance(item, zenoh.Sample)  # the JSON input's only other items
        key = str(item.key_expr)
        parsed = self._pose_key(key)
        if item.kind == zenoh.SampleKind.DELETE:
            if parsed is None:
                self._ledger.reject(Rejection.INVALID_KEY, key, "DELETE on an invalid key")
                return None
            self.read_whole += 1
            return Loss([parsed])
        if parsed is None:
            self._ledger.reject(Rejection.INVALID_KEY, key, "not NS/bodies/<id>/pose/<frame>")
            self._say_invalid_key(key)
            return None
        limit, payload = self._limit, item.payload  # (each .payload is a new ZBytes)
        if len(payload) > limit:  # refuse before copying a huge payload
            self._ledger.reject(Rejection.PAYLOAD_TOO_LARGE, key, f"{len(payload)} bytes > {limit}")
            return None
        decoded = decode_pose(payload.to_bytes(), parsed.body_id, parsed.frame_id, limit)
        if isinstance(decoded, Rejected):
            self._ledger.reject(decoded.reason, key, decoded.detail)
            return None
        poses.append(PoseSample(parsed, decoded))
        self.read_whole += 1
        if self._other_frames is not None:  # poses flow in the frame read: no more watch
            self._stop_watching_other_frames()
        declared = self.declared_keys
        if declared is not None and key not in declared.exprs:
            declared.declare(key)
        return None

    def _refuse_other_frame(self, key: str) -> None:
        """A pose in another frame than the one read, while none has come in that one."""
        parsed = self._pose_key(key)
        frame = "?" if parsed is None else parsed.frame_id
        self._ledger.reject(
            Rejection.OTHER_FRAME, key, f"frame {frame!r}, this service reads {self._base_frame!r}"
        )
        if self._said_other_frames or self._other_frames is None:
            return
        self._said_other_frames = True
        log.warning(
            "poses arrive in frame %r, none yet in %r, the only frame this service reads "
            "(--base-frame, FACING_BASE_FRAME): is it misspelt? Refused, counted as "
            "other_frame until a pose in %r arrives",
            keys.cut(frame), self._base_frame, self._base_frame,
        )  # fmt: skip

    def _stop_watching_other_frames(self) -> None:
        if self._other_frames is not None:
            self._other_frames.undeclare()
            self._other_frames = None

    def _say_invalid_key(self, key: str) -> None:
        """Each invalid key in a line of its own, once (the rejections' periodic summary
        names only the first of each reason); at most ``SAID_KEYS`` of them."""
        if key in self._said or len(self._said) >= SAID_KEYS:
            return
        self._said.add(key)
        log.warning(
            "poses on %s are refused: the key is not %s (counted as invalid_key)",
            keys.cut(key),
            keys.pose_key(self._namespace, body_id="<id>", frame_id="<frame>"),
        )

    def origin(self, sample: PoseSample) -> str:
        return keys.pose_key(self._namespace, body_id=sample.body_id, frame_id=sample.frame_id)

    def forget(self, bodies: list[BodyRef]) -> None:
        if self.declared_keys is not None:
            for body in bodies:
                self.declared_keys.forget(
                    keys.pose_key(self._namespace, body_id=body.body_id, frame_id=body.frame_id)
                )

    def next_due(self) -> float | None:
        return None

    def diagnose(self) -> None:
        return None

    def status(self) -> Ros2Status | None:
        return None

    def start_line(self) -> str:
        return ""

    def close(self) -> None:
        for subscriber in self._mistyped:
            subscriber.undeclare()
        self._mistyped = []
        self._stop_watching_other_frames()
        if self.declared_keys is not None:
            self.declared_keys.close()
