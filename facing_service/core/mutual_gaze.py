"""Visual social engagement (Webb & Lemaignan, RO-MAN 2022: mutual gaze x proxemics), as
hri_engagement 2.0.1 computes it (``engagement_node.py``, ``assess_engagement``): the
evidence both of the service's head machines weigh.

Pure. From a person's pose in the robot's frame (x forward): ``robot`` is the robot's
origin in the person's frame (x out of the face, REP 155; ``-R^T t``), ``person`` the
person's origin in the robot's frame (``t``). hri_engagement reads the gaze frame (optical:
z forward), whose origin is the face's: the robot's offset from the person's axis
(``sqrt(y^2 + z^2)``) is the same in either convention.

    gaze_AB = max(0, 1 - |robot off the person's axis| / (tan(fov) * robot ahead))
    gaze_BA = max(0, 1 - |person off the robot's axis| / (tan(fov) * person ahead))
    log_d   = log(max_d + 1 - d) / log(max_d + 1)
    score   = min(1, gaze_AB * gaze_BA * log_d)       (None beyond max_d)

``tan(fov)`` is hri_engagement's own: the tangent of the whole field (60 deg) where a
half-angle would be usual; kept, as it is what robots run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .detector import robot_in_body

Vector = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class GazeParams:
    """hri_engagement's parameters (``config/00-default.yaml`` of 2.0.1)."""

    field_of_view_deg: float = 60.0
    max_distance_m: float = 4.0
    threshold: float = 0.5  # engagement_threshold: the score a person "engages" above


def _within_field(ahead: float, aside: float, tan_fov: float) -> float:
    """1 on the axis, falling linearly with the offset's tangent, 0 behind."""
    return max(0.0, 1.0 - aside / (tan_fov * ahead)) if ahead > 0 else 0.0


def score(robot: Vector, person: Vector, p: GazeParams) -> float | None:
    """The visual social engagement of one person in [0, 1]; None beyond
    ``max_distance_m`` (hri_engagement then votes "not engaged" without a score)."""
    distance = math.sqrt(robot[0] ** 2 + robot[1] ** 2 + robot[2] ** 2)
    if distance > p.max_distance_m:
        return None
    tan_fov = math.tan(math.radians(p.field_of_view_deg))
    gaze_ab = _within_field(robot[0], math.hypot(robot[1], robot[2]), tan_fov)
    gaze_ba = _within_field(person[0], math.hypot(person[1], person[2]), tan_fov)
    if person[0] <= 0:  # hri_engagement's distance factor is 0 behind the robot
        return 0.0
    log_d = math.log(p.max_distance_m + 1.0 - distance) / math.log(p.max_distance_m + 1.0)
    return min(1.0, gaze_ab * gaze_ba * log_d)


def votes_engaged(robot: Vector, person: Vector, p: GazeParams) -> bool:
    """hri_engagement's vote: the score above its threshold (beyond the distance: no)."""
    s = score(robot, person, p)
    return s is not None and s > p.threshold


def from_gaze_pose(
    translation: Vector, rotation: tuple[float, float, float, float]
) -> tuple[Vector, Vector]:
    """``(robot, person)`` for ``score`` from a gaze frame's pose in the robot's frame, as
    hri_engagement reads it (optical: z forward, x right, y down): the robot in the face's
    axes (x forward), and the person where they are."""
    x, y, z = robot_in_body(np.array([translation]), np.array([rotation]))[0].tolist()
    return (z, -x, -y), translation
