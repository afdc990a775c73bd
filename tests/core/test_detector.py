"""The geometry core, against hand-computed cases and an independent reference."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from facing_service.core.detector import classify, classify_one, robot_in_body

from poses import toward_origin_deg, yaw_quaternion


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """Textbook rotation matrix of a unit quaternion (x, y, z, w): the reference."""
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def near_degenerate(horizontal: np.ndarray | float) -> np.ndarray | bool:
    """Within rounding of the 1e-9 m boundary, two correct computations may disagree."""
    return np.abs(np.asarray(horizontal) - 1e-9) < 1e-11


def reference(t: np.ndarray, q: np.ndarray, threshold_deg: float) -> tuple:
    """The tutorial's per-body rule, written independently: r = -R^T t, acos(r.x/|r.xy|)."""
    r = -rotation_matrix(q).T @ t
    horizontal = math.hypot(r[0], r[1])
    if horizontal < 1e-9:
        return r, None, None, False
    angle = math.degrees(math.acos(max(-1.0, min(1.0, r[0] / horizontal))))
    return r, angle, horizontal, bool(r[0] > 0 and angle < threshold_deg)


def one(t, q, threshold_deg=20.0):
    result = classify(np.array([t], float), np.array([q], float), threshold_deg)
    angle = None if not result.defined[0] else float(result.angle_deg[0])
    distance = None if not result.defined[0] else float(result.distance_m[0])
    return result.robot_in_body[0], angle, distance, bool(result.facing[0])


def test_body_in_front_looking_at_robot_is_facing():
    r, angle, distance, facing = one((2.0, 0.0, 0.0), yaw_quaternion(180.0))
    assert facing
    assert angle == pytest.approx(0.0, abs=1e-9)
    assert distance == pytest.approx(2.0)
    np.testing.assert_allclose(r, (2.0, 0.0, 0.0), atol=1e-12)


def test_body_in_front_with_its_back_turned_is_not_facing():
    """In front of the robot is not facing the robot: the robot is behind this body."""
    r, angle, distance, facing = one((2.0, 0.0, 0.0), yaw_quaternion(0.0))
    assert not facing
    assert angle == pytest.approx(180.0)
    assert distance == pytest.approx(2.0)
    assert r[0] == pytest.approx(-2.0)


@pytest.mark.parametrize(("off", "expected"), [(15.0, True), (19.9, True), (20.1, False)])
def test_cone_edge(off, expected):
    x, y = 1.5, -2.5
    _, angle, _, facing = one((x, y, 0.3), yaw_quaternion(toward_origin_deg(x, y) + off))
    assert angle == pytest.approx(abs(off))
    assert facing is expected


def test_body_beside_robot_is_not_facing_at_ninety_degrees():
    _, angle, _, facing = one((0.0, 2.0, 0.0), yaw_quaternion(0.0))
    assert angle == pytest.approx(90.0)
    assert not facing


def optical_quaternion_of_person_facing_camera() -> tuple[float, float, float, float]:
    """Body axes in a camera optical frame (z forward, x right, y down) for a person facing
    the camera: body x = -z_opt, body z (up) = -y_opt, body y = z cross x = +x_opt."""
    m = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]])  # columns x, y, z
    w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + m[0, 0] - m[1, 1] - m[2, 2])) / 2, m[2, 1] - m[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - m[0, 0] + m[1, 1] - m[2, 2])) / 2, m[0, 2] - m[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - m[0, 0] - m[1, 1] + m[2, 2])) / 2, m[1, 0] - m[0, 1])
    q = np.array([x, y, z, w])
    np.testing.assert_allclose(rotation_matrix(q), m, atol=1e-12)
    return tuple(q)


def test_parent_is_a_camera_optical_frame():
    q = optical_quaternion_of_person_facing_camera()
    r, angle, distance, facing = one((0.0, 0.0, 3.0), q)
    np.testing.assert_allclose(r, (3.0, 0.0, 0.0), atol=1e-12)
    assert facing and angle == pytest.approx(0.0, abs=1e-9) and distance == pytest.approx(3.0)
    # 1 m to the camera's right, still looking along -z_opt: 18.4 degrees off axis.
    _, angle, _, facing = one((1.0, 0.0, 3.0), q)
    assert angle == pytest.approx(math.degrees(math.atan2(1.0, 3.0)))
    assert facing
    assert not one((1.0, 0.0, 3.0), q, threshold_deg=15.0)[3]
    # Camera height does not matter: the person 0.8 m below the optical axis.
    _, angle, distance, facing = one((0.0, 0.8, 3.0), q)
    assert facing and angle == pytest.approx(0.0, abs=1e-9) and distance == pytest.approx(3.0)


@pytest.mark.parametrize(
    "t",
    [(0.0, 0.0, 0.0), (0.0, 0.0, -1.5), (0.0, 0.0, 2.0), (1e-10, -1e-10, 1.0)],
    ids=["origin", "robot-above", "robot-below", "almost-above"],
)
def test_degenerate_poses_are_not_facing_and_have_no_angle(t):
    result = classify(np.array([t]), np.array([[0.0, 0.0, 0.0, 1.0]]), 20.0)
    assert not result.defined[0]
    assert not result.facing[0]
    assert np.isnan(result.angle_deg[0]) and np.isnan(result.distance_m[0])
    assert np.all(np.isfinite(result.robot_in_body))


def test_threshold_can_differ_per_body():
    t = np.array([[2.0, 0.0, 0.0]] * 2)
    q = np.array([yaw_quaternion(180.0 + 22.0)] * 2)
    result = classify(t, q, np.array([20.0, 25.0]))
    assert result.facing.tolist() == [False, True]


def test_empty_batch():
    result = classify(np.zeros((0, 3)), np.zeros((0, 4)), 20.0)
    assert result.facing.shape == (0,)


# --- properties -------------------------------------------------------------------

coords = st.floats(-50.0, 50.0, allow_nan=False)
translations = arrays(np.float64, (3,), elements=coords)


@st.composite
def unit_quaternions(draw) -> np.ndarray:
    q = draw(arrays(np.float64, (4,), elements=st.floats(-1.0, 1.0)))
    norm = np.linalg.norm(q)
    if norm < 1e-3:
        q, norm = np.array([0.0, 0.0, 0.0, 1.0]), 1.0
    return q / norm


scenes = st.lists(st.tuples(translations, unit_quaternions()), min_size=1, max_size=20)
thresholds = st.floats(1.0, 179.0)


def arrays_of(scene):
    return np.array([t for t, _ in scene]), np.array([q for _, q in scene])


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return np.array(
        [
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz,
        ]
    )


@settings(max_examples=200)
@given(scenes, thresholds)
def test_matches_the_per_body_reference(scene, threshold):
    t, q = arrays_of(scene)
    result = classify(t, q, threshold)
    for i, (ti, qi) in enumerate(scene):
        r, angle, distance, facing = reference(ti, qi, threshold)
        np.testing.assert_allclose(result.robot_in_body[i], r, atol=1e-9)
        if near_degenerate(math.hypot(r[0], r[1])):
            continue
        if angle is None:
            assert not result.defined[i] and not result.facing[i]
            continue
        # acos loses digits as the horizontal part shrinks; atan2 (the core) does not.
        assert result.angle_deg[i] == pytest.approx(angle, abs=1e-6 + 1e-9 / distance)
        assert result.distance_m[i] == pytest.approx(distance, abs=1e-9)
        on_edge = abs(angle - threshold) < 1e-6 + 1e-9 / distance or abs(r[0]) < 1e-9
        if not on_edge:
            assert bool(result.facing[i]) is facing


@settings(max_examples=200)
@given(scenes, st.floats(-math.pi, math.pi))
def test_rotating_the_scene_about_base_z_changes_nothing(scene, theta):
    t, q = arrays_of(scene)
    c, s = math.cos(theta), math.sin(theta)
    rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    qz = np.array([0.0, 0.0, math.sin(theta / 2), math.cos(theta / 2)])
    turned = classify(t @ rz.T, np.array([quaternion_product(qz, qi) for qi in q]), 20.0)
    base = classify(t, q, 20.0)
    np.testing.assert_allclose(turned.robot_in_body, base.robot_in_body, atol=1e-9)
    horizontal = np.hypot(base.robot_in_body[:, 0], base.robot_in_body[:, 1])
    clear = ~near_degenerate(horizontal)
    # the angle's digits shrink with the horizontal part, as in the test above (hypothesis
    # found 1.3e-6 degrees at a horizontal part near the degenerate bound)
    a, b = turned.angle_deg[clear], base.angle_deg[clear]
    close = np.abs(a - b) <= 1e-6 + 1e-9 / np.maximum(horizontal[clear], 1e-12)
    assert (close | (np.isnan(a) & np.isnan(b))).all(), (a, b)
    clear &= np.abs(np.nan_to_num(base.angle_deg) - 20.0) > 1e-6
    assert (turned.facing == base.facing)[clear].all()


@settings(max_examples=200)
@given(scenes)
def test_mirroring_y_keeps_the_angle(scene):
    """Reflecting the scene in the base xz-plane maps R to M R M (q -> (-x, y, -z, w)) and
    t to M t, so r -> M r: the same angle, distance and decision, with r.y negated."""
    t, q = arrays_of(scene)
    mirror = np.array([1.0, -1.0, 1.0])
    base = classify(t, q, 20.0)
    mirrored = classify(t * mirror, q * np.array([-1.0, 1.0, -1.0, 1.0]), 20.0)
    np.testing.assert_allclose(mirrored.robot_in_body, base.robot_in_body * mirror, atol=1e-9)
    clear = ~near_degenerate(np.hypot(base.robot_in_body[:, 0], base.robot_in_body[:, 1]))
    np.testing.assert_allclose(mirrored.angle_deg[clear], base.angle_deg[clear], atol=1e-6)
    np.testing.assert_array_equal(mirrored.defined[clear], base.defined[clear])


@settings(max_examples=200)
@given(scenes, thresholds)
def test_outputs_are_nan_only_where_undefined(scene, threshold):
    t, q = arrays_of(scene)
    result = classify(t, q, threshold)
    assert np.all(np.isfinite(result.robot_in_body))
    assert np.array_equal(np.isnan(result.angle_deg), ~result.defined)
    assert np.array_equal(np.isnan(result.distance_m), ~result.defined)
    defined = result.angle_deg[result.defined]
    assert np.all((defined >= 0.0) & (defined <= 180.0))
    assert not np.any(result.facing & ~result.defined)


def test_robot_in_body_is_minus_r_transpose_t_for_a_known_rotation():
    q = np.array([yaw_quaternion(90.0)])
    np.testing.assert_allclose(robot_in_body(np.array([[1.0, 2.0, 3.0]]), q), [[-2.0, 1.0, -3.0]])


@settings(max_examples=300)
@given(scenes, thresholds)
def test_the_per_body_path_agrees_with_the_vectorized_core(scene, threshold):
    """The tracker uses classify_one for small batches: it must decide identically."""
    t, q = arrays_of(scene)
    result = classify(t, q, threshold)
    for i, (ti, qi) in enumerate(scene):
        r, angle, distance, facing = classify_one(
            tuple(map(float, ti)), tuple(map(float, qi)), threshold
        )
        np.testing.assert_allclose(r, result.robot_in_body[i], rtol=0, atol=1e-12)
        assert (angle is None) == (not result.defined[i])
        if angle is not None:
            assert angle == pytest.approx(result.angle_deg[i], abs=1e-9)
            assert distance == pytest.approx(result.distance_m[i], abs=1e-12)
            if abs(angle - threshold) > 1e-9:
                assert facing is bool(result.facing[i])
        else:
            assert facing is False


def test_who_faces_whom_is_the_tutorials_rule_between_people():
    """A at the origin facing +x, B 2 m ahead facing A, C 2 m to A's left facing +x, and
    the robot (the origin, identity rotation) as a participant."""
    from facing_service.core.detector import facing_matrix

    def yaw(deg: float) -> tuple[float, float, float, float]:
        return (0.0, 0.0, math.sin(math.radians(deg) / 2), math.cos(math.radians(deg) / 2))

    t = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 0.0]])
    q = np.array([yaw(0), yaw(180), yaw(0), (0.0, 0.0, 0.0, 1.0)])
    assert facing_matrix(t, q, 20.0).tolist() == [
        [False, True, False, False],  # A faces B; the robot stands on A's spot: undefined
        [True, False, False, True],  # B faces A and the robot; C is 45 deg off
        [False, False, False, False],  # C faces +x: nobody ahead of it
        [False, True, False, False],  # the robot faces B
    ]
    # B faces "the robot" exactly when the robot rule says so
    assert bool(classify(t[[1]], q[[1]], 20.0).facing[0])
    assert facing_matrix(np.zeros((0, 3)), np.zeros((0, 4)), 20.0).shape == (0, 0)
