"""The service's ROS 2 input (``--input ros2``), one ``inputs.Input``: what it keeps of the
robot, and how each of its samples becomes poses and losses for the tracker.

Owned by the worker: the robot's people (``ros2.people``: tracked lists and the TF tree),
the subscriptions to its topics (/tf is the hot key; the others come through the intake),
the form it shows (learned into ``robot.Robot``, which the ROS 2 output answers in), and
the watch that says why people may give no results (``ros2.diagnosis``), checked every
``DIAGNOSIS_PERIOD_S``.
"""

from __future__ import annotations

import logging
from collections import OrderedDict, deque
from collections.abc import Callable
from dataclasses import dataclass

import zenoh

from ..contract.keys import BodyRef
from ..contract.poses import Rejected, Rejection
from ..contract.schemas import Ros2Status
from ..core.records import PoseSample
from ..ros2.diagnosis import RobotWatch, names
from ..ros2.input import RosSample, reading, route
from ..ros2.people import People, Update, harmless
from ..ros2.types import TF_MESSAGE
from ..ros2.wire import read_attachment
from .inputs import Loss
from .ledger import Ledger
from .robot import Robot
from .ros_bus import RobotSubscriptions, received

log = logging.getLogger("facing_service")

#: How often the worker checks why people may give no results (ros2.diagnosis).
DIAGNOSIS_PERIOD_S = 1.0
#: Until /tf arrives where expected: /tf on any other key (another domain, namespace,
#: format or type hash), to say where the robot's data went.
STRAY_TF_KEYS = ("**/tf", "**/tf/tf2_msgs::msg::dds_::TFMessage_/*")
#: The topic the worker reads from zenoh's channel itself (the others stream far less, and
#: come through callbacks).
HOT_ROS_TOPIC = ("/tf", TF_MESSAGE)
#: A person who leaves a tracked list and comes back within this long flapped; this many
#: flaps within FLAPS_SHOWN_S make a finding (the list is the robot's authority, but a
#: flickering tracker, or a stranger publishing lists, should be seen).
FLAP_S = 1.0
FLAPS_SAID = 5
FLAPS_SHOWN_S = 10.0
#: Liveliness events and recently lost subjects kept between diagnoses (bounded: senders
#: choose them).
EVENTS_KEPT = 1024


@dataclass(frozen=True)
class RobotReading:
    """How the robot's topics are read: the frame people are looked up in, the bounds on
    what a robot may make the service hold, and how faces are judged (for the start line)."""

    base_frame: str
    max_ids: int
    max_frames: int
    join_wait_ns: int
    max_message_bytes: int
    head_threshold_deg: float
    head_cone: str


class RosInput:
    """The robot as the worker knows it. ``clock``: the service's monotonic clock."""

    def __init__(
        self, reading: RobotReading, robot: Robot, ledger: Ledger, clock: Callable[[], float]
    ) -> None:
        self.reading = reading
        self._clock = clock
        self._ledger = ledger
        self.wire = robot.wire
        self.form = robot.form
        self.people = People(
            reading.base_frame,
            max_ids=reading.max_ids,
            max_frames=reading.max_frames,
            join_wait_ns=reading.join_wait_ns,
        )
        self.findings: dict[str, str] = {}  # replaced whole by the worker
        self.next_diagnosis: float | None = None  # when the worker checks next
        self._watch = RobotWatch(self.wire, clock())
        self._strays: deque[str] = deque(maxlen=64)  # filled by the stray /tf callbacks
        self._tokens: deque[tuple[str, bool]] = deque(maxlen=EVENTS_KEPT)  # (key, alive)
        self._gone: OrderedDict[str, float] = OrderedDict()  # subject -> when it was lost
        self._flaps: deque[tuple[float, str]] = deque(maxlen=EVENTS_KEPT)  # (when, subject)
        self.flaps = 0  # people who left a tracked list and came back within FLAP_S
        self.read_whole = 0  # samples of the robot's topics that decoded: the robot speaking
        self._sniffers: list[zenoh.Subscriber[None]] = []
        self._token_watch: zenoh.Subscriber[None] | None = None
        self._subscriptions: RobotSubscriptions | None = None

    def hot_key(self) -> str:
        """The key of the topic the worker reads from zenoh's channel (/tf, any type)."""
        return self.wire.subscription(*HOT_ROS_TOPIC, any_type=True)

    def open(self, session: zenoh.Session, hand_off: Callable[[object], None]) -> str:
        """The robot's side topics to ``hand_off`` (the intake), and the stray /tf keys;
        what is read, as the start line says it."""
        self._subscriptions = RobotSubscriptions(
            session, self.wire, hand_off, HOT_ROS_TOPIC, self.reading.max_message_bytes
        )
        self._sniffers = [
            session.declare_subscriber(
                k,
                lambda sample: self._strays.append(str(sample.key_expr)),
                allowed_origin=zenoh.Locality.REMOTE,  # not the intake's wake-ups
            )
            for k in STRAY_TF_KEYS
        ]
        if self.wire.format.value == "rmw_zenoh":  # who publishes what: node tokens
            self._token_watch = session.liveliness().declare_subscriber(
                f"@ros2_lv/{self.wire.domain_id}/**",
                lambda sample: self._tokens.append(
                    (str(sample.key_expr), sample.kind == zenoh.SampleKind.PUT)
                ),
                history=True,
            )
        self.next_diagnosis = self._clock() + DIAGNOSIS_PERIOD_S
        return ", ".join([self.hot_key(), *self._subscriptions.keys])

    def close(self) -> None:
        if self._subscriptions is not None:
            self._subscriptions.close()
            self._subscriptions = None
        if self._token_watch is not None:
            self._token_watch.undeclare()
            self._token_watch = None
        self._stop_sniffing()

    def read(self, item: object, poses: list[PoseSample]) -> Loss | None:
        """A sample of the robot's topics (/tf from the channel, the others as RosSamples):
        poses join the batch; losses come back to be applied after the poses before them."""
        if isinstance(item, zenoh.Sample):
            if item.kind != zenoh.SampleKind.PUT:
                return None
            item = received(item, self.reading.max_message_bytes)
        assert isinstance(item, RosSample)
        update = self.route(item)
        if isinstance(update, Rejected):
            self._ledger.reject(update.reason, item.key, update.detail)
            return None
        self.read_whole += 1
        topic = self.topic(item.key)  # decoded: named as the robot names it
        for reason, what in update.refused:
            self._ledger.reject(Rejection(reason), topic, what, harmless(what))
        if update.unresolved:
            self._ledger.count("tf_lookups_unresolved", update.unresolved)
        poses.extend(update.poses)
        if not update.lost:
            return None
        base = self.people.base_frame
        bodies = [BodyRef(frame_id=base, body_id=subject) for subject in update.lost]
        return Loss(bodies, time_went_back=update.time_back_ns > 0)

    def route(self, sample: RosSample) -> Update | Rejected:
        """One sample of the robot's topics, through ``ros2.input.route`` into its people:
        the form it shows is learned once it decoded, its topic counted as seen, and time
        going back is said at once (the next diagnosis is now)."""
        now = self._clock()
        layout, gid = read_attachment(sample.attachment) or (None, None)  # read once
        limit = self.reading.max_message_bytes
        update = route(self.people, self.wire, sample, limit, now, gid)
        if isinstance(update, Rejected):
            return update  # nothing learned from what does not decode as its topic's type
        if (learned := self.form.learn(sample.key, layout, now)) is not None:
            log.log(learned[0], "%s", learned[1])
        self._watch.on_input(self.topic(sample.key), gid)
        self._flapped(update, now)
        if update.time_back_ns:
            self._watch.time_back = (now, update.time_back_ns)
            self.next_diagnosis = now
        return update

    def topic(self, key: str) -> str:
        """The robot's topic a key of a decoded sample is on (its key, if it is none)."""
        read = reading(self.wire, key)
        return key if isinstance(read, Rejected) else read[0]

    def _flapped(self, update: Update, now: float) -> None:
        """Count the people back within FLAP_S of leaving a tracked list."""
        if update.time_back_ns or not (update.lost or self._gone):
            return  # (time went back: said on its own; nobody left lately: the hot path)
        for subject in update.lost:
            self._gone[subject] = now
            self._gone.move_to_end(subject)
        while self._gone and (
            len(self._gone) > EVENTS_KEPT or now - next(iter(self._gone.values())) > FLAP_S
        ):
            self._gone.popitem(last=False)
        for pose in update.poses:
            if self._gone.pop(pose.body_id, None) is not None:
                self.flaps += 1
                self._flaps.append((now, pose.body_id))

    def diagnose(self) -> None:
        """Every DIAGNOSIS_PERIOD_S: why people may give no results. Each finding is
        logged once when it appears and once when it clears; the status shows the
        current ones."""
        now = self._clock()
        if self.next_diagnosis is None or now < self.next_diagnosis:
            return
        self.next_diagnosis = now + DIAGNOSIS_PERIOD_S
        while self._strays:
            key = self._strays.popleft()
            if isinstance(reading(self.wire, key), Rejected):  # not where /tf is read
                self._watch.on_stray(key)
        if self._watch.topics.get("/tf"):
            self._stop_sniffing()  # /tf arrives where expected: strays no longer matter
        while self._tokens:
            self._watch.on_token(*self._tokens.popleft())
        findings = self._watch.findings(self.people, now) | self._bus_findings(now)
        for code, line in findings.items():
            if code not in self.findings:
                log.warning("ROS 2 input: %s [%s]", line, code)
        for code in self.findings.keys() - findings.keys():
            log.info("ROS 2 input: %s no longer holds", code)
        self.findings = findings

    def _bus_findings(self, now: float) -> dict[str, str]:
        """What the bus itself shows: more than one form, clears refused, people flapping."""
        found = {}
        if len(self.form.present) > 1:
            forms = " and ".join(f.describe() for f in self.form.present)
            found["ros_forms_mixed"] = (
                f"publishers in more than one rmw_zenoh form ({forms}): robots or nodes of "
                "different distros on one router; answering in each (see ros2.publishers)"
            )
        if self.people.clears_refused:
            found["tf_clears_refused"] = (
                f"{self.people.clears_refused} TF buffer clears refused (time went back again "
                "within 2 s of the last clear): a publisher keeps re-sending old stamps"
            )
        recent = [who for when, who in self._flaps if now - when <= FLAPS_SHOWN_S]
        if len(recent) >= FLAPS_SAID:
            found["tracked_flapping"] = (
                f"{len(recent)} times in {FLAPS_SHOWN_S:.0f} s a person left a tracked list and "
                f"came back within {FLAP_S:.0f} s ({names(sorted(set(recent)))}): the robot's "
                "tracker flickers, or another node publishes /humans/*/tracked "
                "(see ros2.publishers)"
            )
        return found

    def _stop_sniffing(self) -> None:
        for sniffer in self._sniffers:
            sniffer.undeclare()
        self._sniffers = []

    def status(self) -> Ros2Status:
        form = self.form.current
        return Ros2Status(
            format=self.wire.format.value,
            distro=form.distro.value,
            attachment=form.attachment.value,
            forms=[f"{f.distro.value}/{f.attachment.value}" for f in self.form.forms],
            form_changes=self.form.changes,
            publishers=self._watch.publishers(),
            tf_clears=self.people.clears,
            tf_clears_refused=self.people.clears_refused,
            tracked_flaps=self.flaps,
            form_from=self.form.source,
            findings=self.findings,
        )

    def start_line(self) -> str:
        """The start line's part: what is read, and how faces are judged."""
        r, wire = self.reading, self.wire
        where = f"domain {wire.domain_id}, " if wire.format.value == "rmw_zenoh" else ""
        ns = f"namespace '{wire.namespace}'" if wire.namespace else "no namespace"
        return (
            f"; ROS 2 input in {wire.format.value} format ({where}{ns}), people looked up "
            f"in {r.base_frame}, faces facing within {r.head_threshold_deg:.1f} "
            f"deg ({r.head_cone})"
        )

    def origin(self, sample: PoseSample) -> str:
        """Where a pose came from, as the robot names it (its wire has no pose keys)."""
        frame = self.people.frame_of(sample.body_id) or "?"
        return f"/tf {sample.frame_id} -> {frame} ({sample.body_id})"

    def forget(self, bodies: list[BodyRef]) -> None:
        return None  # what it holds of people follows the robot's lists, not the tracker

    def next_due(self) -> float | None:
        return self.next_diagnosis
