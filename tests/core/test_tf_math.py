"""tf2's LinearMath: quaternions compose and invert, rotations keep lengths, and the
interpolation ends where it should (tf2_py, ROS's own, is the buffer tests' oracle)."""

from __future__ import annotations

import math

from hypothesis import given
from hypothesis import strategies as st

from facing_service.core.tf.geometry import lerp, qinv, qmul, rotate, slerp

unit = st.floats(-1.0, 1.0)
angles = st.floats(-math.pi, math.pi)


def yaw(a: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(a / 2), math.cos(a / 2))


def close(a, b, tol=1e-9) -> bool:
    return all(abs(x - y) <= tol for x, y in zip(a, b, strict=True))


@given(angles, angles)
def test_yaws_compose_by_adding_and_invert_by_negating(a, b):
    assert close(qmul(yaw(a), yaw(b)), yaw(a + b)) or close(qmul(yaw(a), yaw(b)), [
        -c for c in yaw(a + b)
    ])  # fmt: skip
    assert close(qmul(yaw(a), qinv(yaw(a))), (0.0, 0.0, 0.0, 1.0))


@given(angles, unit, unit, unit)
def test_a_rotation_keeps_lengths_and_a_quarter_turn_turns_x_into_y(a, x, y, z):
    turned = rotate(yaw(a), (x, y, z))
    assert math.isclose(math.hypot(*turned), math.hypot(x, y, z), abs_tol=1e-9)
    assert close(rotate(yaw(math.pi / 2), (1.0, 0.0, 0.0)), (0.0, 1.0, 0.0))


def test_interpolation_ends_at_its_ends_and_halves_in_the_middle():
    assert lerp((0.0, 0.0, 0.0), (2.0, 4.0, 6.0), 0.5) == (1.0, 2.0, 3.0)
    assert close(slerp(yaw(0.0), yaw(1.0), 0.0), yaw(0.0))
    assert close(slerp(yaw(0.0), yaw(1.0), 1.0), yaw(1.0))
    assert close(slerp(yaw(0.0), yaw(1.0), 0.5), yaw(0.5))
