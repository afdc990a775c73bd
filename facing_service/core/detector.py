"""Which bodies are oriented toward the robot: pure, vectorized geometry (REP 155).

The input is the pose of each ``body_<id>`` frame in the base frame (libhri's
``Body::transform()``), as translations ``t`` (N, 3) and unit quaternions ``q`` (N, 4) in
``(x, y, z, w)`` order. Inverting the pose puts the robot origin in the body frame,
``r = -R(q)^T t``; with REP 155's body frame (x out of the chest, z up) the body faces the
robot when ``r`` lies ahead (``r.x > 0``) within a horizontal cone around x.

``classify`` works on whole arrays, one call for a batch of bodies; ``classify_one`` is the
same formula on floats, which the service uses per body for batches below ``SMALL_BATCH``
(nearly all of a robot's: numpy's per-call cost dominates a few bodies).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]

#: Below this horizontal distance (metres) the direction to the robot is undefined: the
#: robot is straight above or below the body, or the tracker published the origin.
DEGENERATE_DISTANCE_M = 1e-9
#: Below this many bodies, ``classify_one`` per body beats ``classify`` with its array
#: building and unpacking: per body, 0.8 us on floats whatever N, against 9.8, 3.0, 1.3
#: and 1.0 us vectorized at N = 4, 16, 64 and 128 (2-core CI machine, Python 3.11;
#: crossover near 200). A robot's batches are nearly always below it.
SMALL_BATCH = 160


@dataclass(frozen=True)
class Classification:
    """Per-body results, index-aligned with the input arrays.

    ``angle_deg`` and ``distance_m`` are NaN exactly where ``defined`` is False; callers
    that leave the process turn those into ``null`` (no NaN ever goes on the wire).
    """

    robot_in_body: FloatArray  # (N, 3)
    angle_deg: FloatArray  # (N,)
    distance_m: FloatArray  # (N,)
    defined: BoolArray  # (N,)
    facing: BoolArray  # (N,)


def robot_in_body(translations: FloatArray, quaternions: FloatArray) -> FloatArray:
    """Robot origin in each body frame: ``r = -R(q)^T t``, for (N, 3) and (N, 4) arrays.

    ``R^T t`` is ``t`` rotated by the conjugate quaternion: with ``u`` the vector part,
    ``R^T t = t - 2w (u x t) + 2 u x (u x t)``. Written out per component on columns, it
    costs a few dozen elementwise operations and no (N, 3, 3) matrices; ``np.cross`` is
    avoided on purpose, since its per-call overhead dominated small batches (47 us for one
    body, measured).
    """
    t = np.asarray(translations, dtype=np.float64)
    q = np.asarray(quaternions, dtype=np.float64)
    tx, ty, tz = t[:, 0], t[:, 1], t[:, 2]
    ux, uy, uz, w = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    cx = uy * tz - uz * ty  # c = u x t
    cy = uz * tx - ux * tz
    cz = ux * ty - uy * tx
    r = np.empty_like(t)
    r[:, 0] = 2.0 * (w * cx - (uy * cz - uz * cy)) - tx  # -(t - 2w c + 2 u x c)
    r[:, 1] = 2.0 * (w * cy - (uz * cx - ux * cz)) - ty
    r[:, 2] = 2.0 * (w * cz - (ux * cy - uy * cx)) - tz
    return r


def classify(
    translations: FloatArray,
    quaternions: FloatArray,
    threshold_deg: float | FloatArray,
    cone3d: bool | BoolArray = False,
) -> Classification:
    """Classify N bodies at once.

    ``threshold_deg`` is a scalar or one value per body; the tracker passes a widened
    threshold for bodies already facing, which is how hysteresis stays out of the geometry.
    Quaternions must be unit length (the schemas normalize them at the boundary).

    ``cone3d`` (scalar or per body) measures the angle between the frame's x axis and the
    robot in 3D, ``atan2(hypot(r.y, r.z), r.x)``, instead of in the horizontal plane: a
    head that looks down at a camera is not facing it, where a chest's pitch is noise.
    """
    r = robot_in_body(translations, quaternions)
    x = r[:, 0]
    y = r[:, 1]
    distance = np.hypot(x, y)
    defined = distance >= DEGENERATE_DISTANCE_M
    lateral = np.abs(y)
    if np.any(cone3d):
        lateral = np.where(cone3d, np.hypot(y, r[:, 2]), lateral)
    angle = np.arctan2(lateral, x)
    angle *= 180.0 / np.pi
    facing = (angle < threshold_deg) & (x > 0.0) & defined
    if not defined.all():  # rare: only then pay for masking
        angle[~defined] = np.nan
        distance[~defined] = np.nan
    return Classification(
        robot_in_body=r, angle_deg=angle, distance_m=distance, defined=defined, facing=facing
    )


def heading_deg(quaternion: tuple[float, float, float, float]) -> float:
    """Where a frame's x axis points in the base frame's ground plane: its yaw, degrees
    (one body, on floats; ``headings`` for many)."""
    x, y, z, w = quaternion
    return math.degrees(math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z)))


def headings(quaternions: FloatArray) -> FloatArray:
    """``heading_deg`` of N frames at once ((N, 4) -> (N,)), in radians."""
    x, y, z, w = np.asarray(quaternions, dtype=np.float64).T
    result: FloatArray = np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return result


def classify_one(
    translation: tuple[float, float, float],
    quaternion: tuple[float, float, float, float],
    threshold_deg: float,
    cone3d: bool = False,
) -> tuple[tuple[float, float, float], float | None, float | None, bool]:
    """``classify`` for a single body, on plain floats: ``(r, angle, distance, facing)``,
    with ``None`` for an undefined angle and distance.

    The same formula, for the same results; it exists because most batches at robot scale
    are a few bodies, where numpy's per-call overhead would dominate (see SMALL_BATCH).
    """
    tx, ty, tz = translation
    ux, uy, uz, w = quaternion
    cx = uy * tz - uz * ty
    cy = uz * tx - ux * tz
    cz = ux * ty - uy * tx
    x = 2.0 * (w * cx - (uy * cz - uz * cy)) - tx
    y = 2.0 * (w * cy - (uz * cx - ux * cz)) - ty
    z = 2.0 * (w * cz - (ux * cy - uy * cx)) - tz
    distance = math.hypot(x, y)
    if distance < DEGENERATE_DISTANCE_M:
        return (x, y, z), None, None, False
    lateral = math.hypot(y, z) if cone3d else abs(y)
    angle = math.atan2(lateral, x) * (180.0 / math.pi)
    return (x, y, z), angle, distance, angle < threshold_deg and x > 0.0


def facing_matrix(
    translations: FloatArray,
    quaternions: FloatArray,
    threshold_deg: float | FloatArray,
    cone3d: bool = False,
) -> BoolArray:
    """Who faces whom among N people (poses in one base frame): ``[a, b]`` is True when b
    is in a's cone, the tutorial's rule with b in place of the robot (b's position in a's
    frame, ``R_a^T (t_b - t_a)``, is ``classify``'s ``-R^T t`` with ``t = t_a - t_b``).
    ``threshold_deg`` is one cone, or one per pair ((N, N): widened where a pair already
    faces, the hysteresis). The diagonal is False. The robot is a participant like any
    other: put its pose (the base frame's origin, identity rotation) among the N."""
    t = np.asarray(translations, dtype=np.float64)
    q = np.asarray(quaternions, dtype=np.float64)
    n = len(t)
    if n == 0:
        return np.zeros((0, 0), dtype=np.bool_)
    rel = (t[:, None, :] - t[None, :, :]).reshape(n * n, 3)
    threshold = np.broadcast_to(np.asarray(threshold_deg, dtype=np.float64), (n, n)).ravel()
    result = classify(rel, np.repeat(q, n, axis=0), threshold, cone3d)
    facing = result.facing.reshape(n, n)
    np.fill_diagonal(facing, False)
    return facing
