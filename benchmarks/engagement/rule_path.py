"""hri_engagement's rule on a recording, as its node runs it (the evaluation's anchor): the
recorded TF and tracked lists through the service's own People, the rule's vote window
every 0.1 s. Its own module: the real-path evaluation (``recordings``) and the
cross-validation (``crossval``) both hold rows to it."""

from __future__ import annotations

from pathlib import Path

from facing_service.contract.levels import Level
from facing_service.core import rule
from facing_service.core.mutual_gaze import GazeParams, from_gaze_pose, votes_engaged
from facing_service.core.tf.errors import TfError
from facing_service.ros2.input import tf_inputs
from facing_service.ros2.people import People

from .bags import read_bag
from .scoring import BASE_FRAME, Timeline, ticks

#: hri_engagement 2.0.1's defaults, as the service's --engagement rule has them.
GAZE, RULE = GazeParams(), rule.RuleParams()


def rule_timelines(bag: Path, persons: list[str]) -> dict[str, Timeline]:
    """hri_engagement's rule on the recording's TF data, as its node runs it: every
    0.1 s (its timer), each tracked person with a face votes from their gaze frame looked
    up in the base frame (time 0, as libhri does); no vote when the lookup fails. The
    rule is the service's own (``core.rule``, ``core.mutual_gaze``: one code)."""
    messages = list(read_bag(bag))
    start, end = messages[0][1], messages[-1][1]
    people = People(BASE_FRAME)
    windows: dict[str, rule.Votes] = {}
    faces: dict[str, str] = {}
    tracked: list[str] = []
    timelines: dict[str, Timeline] = {p: [] for p in persons}
    i = 0
    for tick in ticks(start, end):
        while i < len(messages) and messages[i][1] <= tick:
            topic, _, message = messages[i]
            i += 1
            if topic in ("/tf", "/tf_static"):
                people.on_tf(tf_inputs(message), static=topic == "/tf_static")
            elif topic == "/humans/persons/tracked":
                tracked = list(message.ids)
            elif topic.endswith("/face_id"):
                faces[topic.split("/")[3]] = message.data
        for person in tracked:
            vote = None
            if face := faces.get(person):
                try:
                    gaze, _ = people.tf.lookup(BASE_FRAME, f"gaze_{face}", 0)
                except TfError:
                    pass
                else:
                    robot, where = from_gaze_pose(gaze.translation, gaze.rotation)
                    vote = 1 if votes_engaged(robot, where, GAZE) else -1
            windows[person] = rule.tick(windows.get(person, rule.Votes()), vote, RULE)
        for person, timeline in timelines.items():
            level = windows[person].level if person in windows else Level.UNKNOWN
            timeline.append(((tick - start) / 1e9, level))
    return timelines
