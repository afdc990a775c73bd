"""REFERENCE MODELS, not our method: ROS4HRI hri_engagement's rule, re-implemented to
compare against (benchmarks.engagement, benchmarks.recordings). Not shipped in the
package: nothing the service runs uses them."""

from __future__ import annotations

import math

from facing_service.contract.levels import Level


class VoteWindow:
    """REFERENCE MODEL, not our method: ROS4HRI hri_engagement's rule, re-implemented for
    comparison (benchmarks/engagement.py). Every 1/rate s a vote of +1 (engaged) or -1; the
    level moves on the mean of the last ``window_s`` of votes, once half of it is filled:
    DISENGAGED -> ENGAGING above -0.4; ENGAGING -> ENGAGED above 0.5 or -> DISENGAGED below
    -0.6; ENGAGED -> DISENGAGING below 0.4; DISENGAGING -> ENGAGED above 0.6 or ->
    DISENGAGED below -0.5."""

    def __init__(self, rate_hz: float = 10.0, window_s: float = 10.0) -> None:
        self.size = int(rate_hz * window_s)
        self.min_samples = int(0.5 * self.size)
        self.votes: list[int] = []
        self.level = Level.UNKNOWN

    def vote(self, engaged: bool | None) -> Level:
        """One tick: a vote (None when the tick had no observation, as hri_engagement's
        timer does when it cannot see the face: the level still moves on the window)."""
        if engaged is not None:
            self.votes = [*self.votes[-(self.size - 1) :], 1 if engaged else -1]
        if len(self.votes) < self.min_samples:
            return self.level
        mean = sum(self.votes) / len(self.votes)
        level = self.level
        if level is Level.UNKNOWN:
            level = Level.DISENGAGED
        elif level is Level.DISENGAGED and mean > -0.4:
            level = Level.ENGAGING
        elif level is Level.ENGAGING:
            if mean < -0.6:
                level = Level.DISENGAGED
            elif mean > 0.5:
                level = Level.ENGAGED
        elif level is Level.ENGAGED and mean < 0.4:
            level = Level.DISENGAGING
        elif level is Level.DISENGAGING:
            if mean > 0.6:
                level = Level.ENGAGED
            elif mean < -0.5:
                level = Level.DISENGAGED
        self.level = level
        return level


def visual_social_engagement(
    gaze_translation: tuple[float, float, float],
    gaze_rotation: tuple[float, float, float, float],
    field_of_view_deg: float = 60.0,
    max_distance_m: float = 4.0,
) -> float | None:
    """REFERENCE MODEL, not our method: hri_engagement's "visual social engagement" (Webb &
    Lemaignan, RO-MAN 2022: mutual gaze x proxemics) of one person, from the pose of their
    gaze frame (optical convention: z forward) in the robot's reference frame (x forward).
    None when the person is farther than ``max_distance_m`` (hri_engagement then votes
    "not engaged" without computing the score)."""
    qx, qy, qz, qw = gaze_rotation
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    qx, qy, qz, qw = qx / n, qy / n, qz / n, qw / n
    tx, ty, tz = gaze_translation
    # The robot in the gaze frame: -R^T t (the inverse of the person's pose).
    r = (
        (1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)),
        (2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)),
        (2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)),
    )
    rx, ry, rz = (-(r[0][i] * tx + r[1][i] * ty + r[2][i] * tz) for i in range(3))
    d_ab = math.sqrt(rx * rx + ry * ry + rz * rz)
    if d_ab > max_distance_m:
        return None
    tan_fov = math.tan(math.radians(field_of_view_deg))
    xb, yb, zb = rz, rx, ry  # optical axes to the paper's (x forward)
    gaze_ab = max(0.0, 1 - math.sqrt(yb * yb + zb * zb) / (tan_fov * xb)) if xb > 0 else 0.0
    xa, ya, za = tx, ty, tz
    gaze_ba, log_d_ab = 0.0, 0.0
    if xa > 0:
        gaze_ba = max(0.0, 1 - math.sqrt(ya * ya + za * za) / (tan_fov * xa))
        log_d_ab = math.log(-d_ab + max_distance_m + 1) / math.log(max_distance_m + 1)
    return min(1.0, gaze_ab * gaze_ba * log_d_ab)
