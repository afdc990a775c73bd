"""tf2's LinearMath as tf2 computes it (no renormalization anywhere): a transform as a
translation and a quaternion, composition, inversion, and the interpolation lookups use
(translation lerp, rotation slerp). Tuples of floats: cheaper than numpy for one transform.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

Vec = tuple[float, float, float]
Quat = tuple[float, float, float, float]  # x, y, z, w


@dataclass(frozen=True, slots=True)
class RigidTransform:
    translation: Vec
    rotation: Quat


IDENTITY = RigidTransform((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))


def qmul(a: Quat, b: Quat) -> Quat:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by + ay * bw + az * bx - ax * bz,
        aw * bz + az * bw + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def qinv(q: Quat) -> Quat:
    """tf2's ``inverse()``: the conjugate."""
    return (-q[0], -q[1], -q[2], q[3])


def rotate(q: Quat, v: Vec) -> Vec:
    """tf2's ``quatRotate``: ``q * v * q.inverse()``."""
    x, y, z, w = q
    vx, vy, vz = v
    # q * (v, 0)
    px = w * vx + y * vz - z * vy
    py = w * vy + z * vx - x * vz
    pz = w * vz + x * vy - y * vx
    pw = -x * vx - y * vy - z * vz
    # (..) * conj(q)
    return (
        pw * -x + px * w + py * -z - pz * -y,
        pw * -y + py * w + pz * -x - px * -z,
        pw * -z + pz * w + px * -y - py * -x,
    )


def add(a: Vec, b: Vec) -> Vec:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def slerp(q1: Quat, q2: Quat, t: float) -> Quat:
    """tf2's ``Quaternion::slerp`` (shortest path, as tf2 computes it)."""
    magnitude = math.sqrt(sum(c * c for c in q1) * sum(c * c for c in q2))
    product = sum(a * b for a, b in zip(q1, q2, strict=True)) / magnitude
    if abs(product) >= 1.0:
        return q1
    sign = -1.0 if product < 0 else 1.0
    theta = math.acos(sign * product)
    s1 = math.sin(sign * t * theta)
    d = 1.0 / math.sin(theta)
    s0 = math.sin((1.0 - t) * theta)
    x1, y1, z1, w1 = q1
    x2, y2, z2, w2 = q2  # the sign is in s1 already: sin(sign * t * theta)
    return (
        (x1 * s0 + x2 * s1) * d,
        (y1 * s0 + y2 * s1) * d,
        (z1 * s0 + z2 * s1) * d,
        (w1 * s0 + w2 * s1) * d,
    )


def lerp(v1: Vec, v2: Vec, t: float) -> Vec:
    s = 1.0 - t
    return (s * v1[0] + t * v2[0], s * v1[1] + t * v2[1], s * v1[2] + t * v2[2])


def neg(v: Vec) -> Vec:
    return (-v[0], -v[1], -v[2])
