"""A core tracker with the service's defaults, and its poses, for tests of the layers that
read it (the core, the turn's view, the outputs)."""

from __future__ import annotations

from dataclasses import replace

from facing_service.config.profiles import engagement_params
from facing_service.config.settings import Settings
from facing_service.contract.keys import BodyRef
from facing_service.contract.poses import Pose
from facing_service.contract.stamps import Time
from facing_service.core.records import PoseSample
from facing_service.core.tracker import Tracker

from poses import toward_origin_deg, yaw_quaternion


def sample(body="a", frame="cam", off_deg=0.0, sec=1, nanosec=0, x=2.0, y=0.0) -> PoseSample:
    yaw = toward_origin_deg(x, y) + off_deg
    return PoseSample(
        BodyRef(frame_id=frame, body_id=body),
        Pose(Time.of(sec, nanosec), (x, y, 0.0), yaw_quaternion(yaw)),
    )


def tracker(**kw) -> Tracker:
    """A tracker with the service's defaults (``Settings``), but what ``kw`` says."""
    defaults = Settings()
    params = {
        "threshold_deg": 20.0,
        "hysteresis_deg": 5.0,
        "stale_after_s": 2.0,
        "max_bodies": defaults.max_bodies,
        "engagement_period_s": defaults.engagement_period_s,
    } | kw
    params.setdefault(
        "engagement", replace(engagement_params(defaults), threshold_deg=params["threshold_deg"])
    )
    return Tracker(**params)
