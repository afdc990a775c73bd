"""Intrinsics from a field of view and from the calibration files robots have; every bad
file one line that says what is wrong."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from facing_service.camera.intrinsics import (
    CalibrationError,
    Intrinsics,
    from_field_of_view,
    load_calibration,
)

#: The shape camera_calibration_parsers writes (ROS 2 image_pipeline's camera_info YAML;
#: a real calibration of a 640x480 webcam).
ROS_CAMERA_INFO = """\
image_width: 640
image_height: 480
camera_name: narrow_stereo
camera_matrix:
  rows: 3
  cols: 3
  data: [615.2, 0.0, 322.1, 0.0, 616.9, 238.4, 0.0, 0.0, 1.0]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [0.11, -0.23, 0.001, -0.002, 0.0]
rectification_matrix:
  rows: 3
  cols: 3
  data: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
projection_matrix:
  rows: 3
  cols: 4
  data: [620.0, 0.0, 322.0, 0.0, 0.0, 621.0, 238.0, 0.0, 0.0, 0.0, 1.0, 0.0]
"""


def test_a_field_of_view_gives_the_focal_length_that_sees_that_wide():
    camera = from_field_of_view(640, 480, 65.0)
    half_width_angle = math.degrees(math.atan((640 / 2) / camera.fx))
    assert half_width_angle == pytest.approx(32.5)
    assert (camera.cx, camera.cy, camera.fx) == (320.0, 240.0, camera.fy)


def test_a_ros_camera_info_file_is_read(tmp_path: Path):
    path = tmp_path / "webcam.yaml"
    path.write_text(ROS_CAMERA_INFO)
    assert load_calibration(path) == Intrinsics(
        615.2, 616.9, 322.1, 238.4, 640, 480, (0.11, -0.23, 0.001, -0.002, 0.0)
    )


def test_a_calibration_scales_to_frames_of_the_same_aspect_and_refuses_another():
    camera = Intrinsics(1000.0, 1000.0, 640.0, 480.0, 1280, 960)
    assert camera.for_frame(640, 480) == Intrinsics(500.0, 500.0, 320.0, 240.0, 640, 480)
    with pytest.raises(CalibrationError, match="calibrated for 1280x960, frames are 640x360"):
        camera.for_frame(640, 360)


@pytest.mark.parametrize(
    ("text", "said"),
    [
        ("image_width: [", "not YAML"),
        ("- 1\n- 2\n", "expected a camera_info mapping, found list"),
        ("image_height: 480\n", "no image_width"),
        (ROS_CAMERA_INFO.replace("image_width: 640", "image_width: -640"), "image_width must be"),
        (ROS_CAMERA_INFO.replace("[615.2, 0.0,", "[615.2,"), "camera_matrix needs 9 numbers"),
        (ROS_CAMERA_INFO.replace("615.2", "-615.2"), "needs fx, fy > 0"),
        (ROS_CAMERA_INFO.replace("322.1", "922.1"), "principal point inside the 640x480"),
        (ROS_CAMERA_INFO.replace("615.2", ".nan"), "finite numbers"),
        (ROS_CAMERA_INFO.replace("plumb_bob", "equidistant"), "'equidistant' is not supported"),
        (  # a defect found: fx = 5 px (a 178° lens) read every face 9 cm away, silently
            ROS_CAMERA_INFO.replace("615.2", "5.0").replace("616.9", "5.0"),
            "fx 5, fy 5 make a 178° x 178° field of view at 640x480: no camera",
        ),
        (ROS_CAMERA_INFO.replace("615.2", "30000"), "make a 1° x 43° field of view"),
        (ROS_CAMERA_INFO.replace("615.2", "1300"), "fx 1300 and fy 616.9 are 2.1 times apart"),
        (  # a defect found: six coefficients passed the checks and failed at the first face
            ROS_CAMERA_INFO.replace("[0.11, -0.23, 0.001, -0.002, 0.0]", "[0.1, 0, 0, 0, 0, 0]"),
            "distortion_coefficients has 6 numbers; OpenCV takes 4, 5, 8, 12, 14",
        ),
    ],
)
def test_a_bad_calibration_is_one_line_naming_the_file(tmp_path: Path, text: str, said: str):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(CalibrationError) as raised:
        load_calibration(path)
    message = str(raised.value)
    assert message.startswith(f"{path}: ") and said in message and "\n" not in message


def test_a_missing_or_binary_file_is_one_line(tmp_path: Path):
    with pytest.raises(CalibrationError, match="No such file"):
        load_calibration(tmp_path / "absent.yaml")
    (tmp_path / "photo.yaml").write_bytes(b"\xff\xd8\xff\xe0 not text")
    with pytest.raises(CalibrationError, match="not a text file"):
        load_calibration(tmp_path / "photo.yaml")
