"""The camera's intrinsics: from a calibration file when there is one, else from a field of
view. Pure: parsing and arithmetic, no camera.

Two calibration files are read, the two a robot's camera is likely to have: ROS's
``camera_info`` YAML (camera_calibration_parsers, what ``camera_calibration`` writes) and
OpenCV's FileStorage YAML (``%YAML:1.0``, what OpenCV's calibration sample writes). A JSON
file of the ROS shape reads too (JSON is YAML).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

#: A laptop's built-in camera or a USB webcam sees about this wide (Logitech C920: 70.4°
#: horizontal; built-in cameras 55-70°). A wrong guess scales every distance: 60° taken
#: for 70° reads faces 21 % nearer (the focal length's ratio, tan 35° / tan 30°); the
#: head's angle barely moves (the fit's perspective, not its scale, holds it).
DEFAULT_FOV_DEG = 65.0
#: The distortion models whose coefficients OpenCV's pinhole model takes as they are.
PINHOLE_MODELS = ("plumb_bob", "rational_polynomial")
#: How many distortion coefficients OpenCV's solvePnP takes (none, or one of these).
DISTORTION_COUNTS = (4, 5, 8, 12, 14)
#: The horizontal (and vertical) fields of view a pinhole camera can have (degrees): a
#: telephoto's few degrees to a wide lens's; past 170° a lens is a fisheye, which the
#: pinhole model does not describe (fx = 5 px at 640 wide is 178°: every face read 9 cm
#: away).
FIELD_OF_VIEW_DEG = (10.0, 170.0)
#: How far apart fx and fy may be (their ratio): a camera's pixels are square or nearly
#: (anamorphic lenses squeeze 1.33 to 2, and are not what faces are filmed with).
MOST_PIXEL_ASPECT = 1.5


class CalibrationError(ValueError):
    """A calibration file that cannot be used, said in one line."""


@dataclass(frozen=True)
class Intrinsics:
    """A pinhole camera: focal lengths and principal point in pixels, for frames of
    ``width`` x ``height``, and OpenCV's distortion coefficients."""

    fx: float
    fy: float
    cx: float
    cy: float
    width: int
    height: int
    distortion: tuple[float, ...] = ()

    def for_frame(self, width: int, height: int) -> Intrinsics:
        """These intrinsics for frames of another size of the same aspect (a camera asked
        for 640x480 after a calibration at 1280x960): scaled; another aspect is an error."""
        if (width, height) == (self.width, self.height):
            return self
        sx, sy = width / self.width, height / self.height
        if abs(sx / sy - 1.0) > 0.01:
            raise CalibrationError(
                f"calibrated for {self.width}x{self.height}, frames are {width}x{height}: "
                "another aspect ratio (calibrate at this size)"
            )
        return replace(
            self, fx=self.fx * sx, fy=self.fy * sy, cx=self.cx * sx, cy=self.cy * sy,
            width=width, height=height,
        )  # fmt: skip


def from_field_of_view(width: int, height: int, fov_deg: float = DEFAULT_FOV_DEG) -> Intrinsics:
    """An ideal camera of horizontal field of view ``fov_deg``: square pixels, the principal
    point at the centre, no distortion."""
    focal = (width / 2.0) / math.tan(math.radians(fov_deg) / 2.0)
    return Intrinsics(focal, focal, width / 2.0, height / 2.0, width, height)


def load_calibration(path: Path) -> Intrinsics:
    """The intrinsics in ``path``; every way it can fail is a CalibrationError of one line."""
    try:
        text = path.read_text()
    except OSError as error:
        raise CalibrationError(f"{path}: {error.strerror}") from None
    except UnicodeDecodeError:
        raise CalibrationError(f"{path}: not a text file") from None
    return parse_calibration(text, str(path))


def parse_calibration(text: str, name: str) -> Intrinsics:
    """A ROS camera_info or OpenCV FileStorage YAML text, checked: a 3x3 camera matrix of
    positive focal lengths and a principal point inside the image, a pinhole distortion."""
    from ruamel.yaml import YAML, YAMLError  # rosbags' own YAML reader, already installed

    if text.lstrip().startswith("%YAML:1.0"):  # OpenCV's header and matrix tag, not YAML 1.1
        text = text.split("\n", 1)[1].replace("!!opencv-matrix", "")
    try:
        data = YAML(typ="safe", pure=True).load(text)
    except YAMLError as error:
        problem = str(error).splitlines()[0]
        raise CalibrationError(f"{name}: not YAML ({problem})") from None
    if not isinstance(data, dict):
        raise CalibrationError(
            f"{name}: expected a camera_info mapping, found {type(data).__name__}"
        )
    try:
        width, height = _positive_int(data, "image_width"), _positive_int(data, "image_height")
        matrix = _numbers(data, "camera_matrix", 9)
        model = str(data.get("distortion_model", "plumb_bob"))
        distortion = _numbers(data, "distortion_coefficients", None) if (
            "distortion_coefficients" in data) else []  # fmt: skip
    except (KeyError, TypeError, ValueError) as error:
        raise CalibrationError(f"{name}: {error.args[0] if error.args else error}") from None
    fx, _, cx, _, fy, cy, *_ = matrix
    if model not in PINHOLE_MODELS:
        raise CalibrationError(
            f"{name}: distortion_model '{model}' is not supported ({', '.join(PINHOLE_MODELS)})"
        )
    if distortion and len(distortion) not in DISTORTION_COUNTS:
        raise CalibrationError(
            f"{name}: distortion_coefficients has {len(distortion)} numbers; OpenCV takes "
            f"{', '.join(map(str, DISTORTION_COUNTS))} (or none)"
        )
    if not (fx > 0 and fy > 0 and 0 < cx < width and 0 < cy < height):
        raise CalibrationError(
            f"{name}: camera_matrix needs fx, fy > 0 and the principal point inside the "
            f"{width}x{height} image (fx {fx:g}, fy {fy:g}, cx {cx:g}, cy {cy:g})"
        )
    if (no_camera := impossible(fx, fy, width, height)) is not None:
        raise CalibrationError(f"{name}: {no_camera}")
    return Intrinsics(fx, fy, cx, cy, width, height, tuple(distortion))


def field_of_view_deg(focal_px: float, side_px: int) -> float:
    """The angle a side of ``side_px`` pixels spans at focal length ``focal_px``."""
    return math.degrees(2.0 * math.atan(side_px / (2.0 * focal_px)))


def impossible(fx: float, fy: float, width: int, height: int) -> str | None:
    """Why focal lengths no pinhole camera has are refused, in words; None when possible."""
    low, high = FIELD_OF_VIEW_DEG
    across, down = field_of_view_deg(fx, width), field_of_view_deg(fy, height)
    if not (low <= across <= high and low <= down <= high):
        return (
            f"fx {fx:g}, fy {fy:g} make a {across:.0f}° x {down:.0f}° field of view at "
            f"{width}x{height}: no camera this model describes ({low:g}° to {high:g}°)"
        )
    if max(fx / fy, fy / fx) > MOST_PIXEL_ASPECT:
        return (
            f"fx {fx:g} and fy {fy:g} are {max(fx / fy, fy / fx):.1f} times apart: pixels "
            f"that far from square (at most {MOST_PIXEL_ASPECT:g}) are a wrong calibration"
        )
    return None


def _positive_int(data: dict[str, Any], key: str) -> int:
    value = data[key] if key in data else _missing(key)
    if isinstance(value, bool) or not isinstance(value, int) or value <= 0:
        raise ValueError(f"{key} must be a positive whole number of pixels, not {value!r}")
    return value


def _numbers(data: dict[str, Any], key: str, count: int | None) -> list[float]:
    """The ``data`` list of a matrix entry (``{rows, cols, data: [...]}``), finite numbers."""
    entry = data[key] if key in data else _missing(key)
    values = entry.get("data") if isinstance(entry, dict) else None
    if not isinstance(values, list) or not all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in values
    ):
        raise ValueError(f"{key} needs a 'data' list of finite numbers")
    if count is not None and len(values) != count:
        raise ValueError(f"{key} needs {count} numbers in 'data', found {len(values)}")
    return [float(v) for v in values]


def _missing(key: str) -> Any:
    raise KeyError(f"no {key}")
