"""The composition root: the one place the service is built from ``Settings``. Each part is
given only what it uses (a namespace, a bound, a robot), never the settings: below here
nothing reads them, so what a part depends on is in its signature. ``--input`` and
``--output`` become types here too: everything after works with an ``inputs.Input`` and a
list of ``outputs.Output``, never with the setting."""

from __future__ import annotations

from collections.abc import Callable

from ..config.profiles import head_profile, robot_wire, scene_params, tracker_for
from ..config.settings import Settings
from ..contract.stamps import NS_PER_S
from ..core.silence import InputSilence, SilenceParams
from ..core.social.scene import Scenes
from ..ros2.wire import FormLearner
from .decisions import Parts
from .inputs import Input, JsonInput
from .ledger import Ledger
from .outputs import JsonOutput, Output, RosTopicsOutput
from .queries import Answers
from .robot import Robot
from .ros_input import RobotReading, RosInput


def parts_for(settings: Settings, ledger: Ledger, clock: Callable[[], float]) -> Parts:
    """The tracker, the scenes, the input and the outputs a service with ``settings`` runs."""
    source, outputs = io_for(settings, ledger, clock)
    return Parts(
        tracker_for(settings), Scenes(scene_params(settings)), source, outputs,
        silence_for(settings),
    )  # fmt: skip


def io_for(
    settings: Settings, ledger: Ledger, clock: Callable[[], float]
) -> tuple[Input, list[Output]]:
    """The input, and the outputs (our JSON keys always; the robot's topics with
    ``--output ros2``). One ``Robot`` is shared when both sides speak ROS 2: the output
    answers in the forms the input learns."""
    s = settings
    answering = s.output == "ros2"
    robot = robot_for(s, answering)
    source: Input = (
        RosInput(robot_reading(s), robot, ledger, clock)
        if s.input == "ros2"
        else JsonInput(s.namespace, s.base_frame, s.max_payload_bytes, s.max_bodies, ledger)
    )
    outputs: list[Output] = [JsonOutput(s.namespace, s.instance, s.max_bodies)]
    if answering:
        outputs.append(
            RosTopicsOutput(robot, s.ros_engagement_rate_hz, s.ros_intents, s.ros_node_name)
        )
    return source, outputs


def robot_for(settings: Settings, answering: bool) -> Robot:
    """The robot both ROS 2 sides know; ``answering``: whether it is answered on its topics
    (then every form it shows is answered in, see ``ros2.wire.FormLearner``)."""
    return Robot(robot_wire(settings), FormLearner(settings.forced_distro, answering=answering))


def robot_reading(settings: Settings) -> RobotReading:
    """How the ROS 2 input reads the robot, from the settings."""
    s = settings
    return RobotReading(
        base_frame=s.ros_base_frame,
        max_ids=s.max_bodies,
        max_frames=s.ros_max_frames,
        join_wait_ns=round(s.ros_join_wait_s * NS_PER_S),
        max_message_bytes=s.ros_max_message_bytes,
        head_threshold_deg=head_profile(s).threshold_deg,
        head_cone=s.head_cone,
    )


def silence_for(settings: Settings) -> InputSilence:
    """Whether the input is silent and its people held (``core.silence``), as set: silent
    after at most half of ``--stale-after-s`` (a shorter staleness, set for a fast
    tracker, is never outrun by the silence that would hold it; said at start and shown
    in the status, ``silent_after_in_force``)."""
    return InputSilence(
        SilenceParams(
            silent_after_in_force(settings), settings.hold_silent_s, settings.stale_after_s
        )
    )


def silent_after_in_force(settings: Settings) -> float:
    """``--silent-after-s``, at most half of ``--stale-after-s``."""
    return min(settings.silent_after_s, settings.stale_after_s / 2)


def answers_for(settings: Settings, ledger: Ledger) -> Answers:
    """The queries' answerer: this service's namespace, instance and the frame it serves
    (a robot's base frame; the one --base-frame, or any)."""
    served = settings.ros_base_frame if settings.input == "ros2" else settings.base_frame
    return Answers(settings.namespace, settings.instance, ledger, served)
