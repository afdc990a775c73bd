"""The camera front end's loop: frames in, each face's head pose out as the service's input
(a pose per face per frame, a DELETE for a face lost), and a line whenever a face starts or
stops facing the camera, so what the service will decide can be read off the terminal too.
"""

from __future__ import annotations

import itertools
import json
import time
from collections.abc import Callable, Generator
from dataclasses import dataclass, field
from pathlib import Path

from ..contract import keys
from ..contract.poses import pose_dict
from ..contract.stamps import Time
from ..core.detector import classify_one
from .face_ids import FaceIds, FaceSeen
from .face_model import FaceModel, face_model
from .frames import Image, Source, frames
from .head_pose import FloatArray, HeadPose, Mount, fit_head, placed
from .intrinsics import (
    DEFAULT_FOV_DEG,
    CalibrationError,
    Intrinsics,
    from_field_of_view,
    load_calibration,
)
from .landmarks import DETECTOR_FACE_PX, DETECTOR_PX, FaceMesh, seen

Publish = Callable[[str, bytes | None], None]


#: How far faces are looked for by default: across a room, where the person to attract
#: stands in the doorway, at about twice the CPU of faces near alone.
DEFAULT_REACH_M = 5.0
#: A face's width (m): the average adult's, the size every distance here comes from.
FACE_WIDTH_M = 0.15


def farthest_reach_m(camera: Intrinsics) -> float:
    """How far a face can be and still be found: at the detector's smallest tile (its
    own input, ``DETECTOR_PX``), ``DETECTOR_FACE_PX`` wide in the frame. A longer
    ``--reach-m`` would ask for tiles smaller than the detector takes."""
    return FACE_WIDTH_M * camera.fx / DETECTOR_FACE_PX


def tile_for(camera: Intrinsics, reach_m: float) -> int | None:
    """The tiles' side that shows the detector a face ``reach_m`` away as wide as it
    finds them (``DETECTOR_FACE_PX``); None when the whole frame already does."""
    face_px = FACE_WIDTH_M * camera.fx / reach_m
    side = round(DETECTOR_PX * face_px / DETECTOR_FACE_PX)
    return None if side >= max(camera.width, camera.height) else side


@dataclass(frozen=True)
class CameraOptions:
    """What ``facing-service camera`` and ``demo --camera`` were asked for."""

    source: Source
    base_frame: str = "base_link"
    namespace: str = "hri"
    max_faces: int = 5
    id_prefix: str = "f"
    threshold_deg: float = 20.0
    hysteresis_deg: float = 5.0  # a face already facing stays so to threshold + this
    fov_deg: float = DEFAULT_FOV_DEG
    calibration: Path | None = None
    mount: Mount | None = None
    #: How far faces are looked for; None: ``DEFAULT_REACH_M``, or as far as the frame
    #: shows, unsaid (only a reach asked for is said when the frame cannot give it).
    reach_m: float | None = None


@dataclass
class CameraStats:
    """What a run did: frames read, the most faces in one, the CPU and wall time spent on
    frames (reading excluded), the faces seen, and the slowest first result (a new face's
    frame until its pose went out). A few numbers, whatever the run's length."""

    frames: int = 0
    most_faces: int = 0
    cpu_s: float = 0.0
    busy_s: float = 0.0
    faces_seen: int = 0
    slowest_first_ms: float | None = None


def _short_reach(camera: Intrinsics, reach_m: float) -> str | None:
    farthest = farthest_reach_m(camera)
    if reach_m <= farthest:
        return None
    return (
        f"--reach-m {reach_m:g} is past what {camera.width}x{camera.height} frames show: a "
        f"face beyond {farthest:.1f} m is under {DETECTOR_FACE_PX:g} px, too small for the "
        f"detector; faces are looked for to {farthest:.1f} m (a larger frame sees further)"
    )


class CameraFeed:
    """An opened camera front end: the source open, the calibration read, the models
    loaded, so that every way it can fail is said before the first frame
    (SourceError, CalibrationError); ``run`` then publishes until the source ends."""

    def __init__(self, options: CameraOptions) -> None:
        self.options = options
        calibration = load_calibration(options.calibration) if options.calibration else None
        self._frames: Generator[Image, None, None] | None = frames(options.source)
        try:
            # The first frame's size is known once the source opens: a calibration for
            # another aspect is refused now, in one line, not at the first face.
            self._first: Image | None = next(self._frames, None)
            self._camera = None if self._first is None else _intrinsics(
                self._first, calibration, options.fov_deg
            )  # fmt: skip
            #: Why faces are looked for less far than asked, in one line (None: as asked).
            reach_m = options.reach_m or DEFAULT_REACH_M
            self.reach_note = None if self._camera is None or options.reach_m is None else (
                _short_reach(self._camera, reach_m)
            )  # fmt: skip
            tile = None if self._camera is None else tile_for(self._camera, reach_m)
            self._mesh = FaceMesh(options.max_faces, tile)
        except BaseException as error:  # the capture released now, not by the collector
            self._frames.close()
            self._frames = None
            if isinstance(error, CalibrationError):  # the file named, as in its other lines
                raise CalibrationError(f"{options.calibration}: {error}") from None
            raise

    def run(
        self,
        publish: Publish,
        should_stop: Callable[[], bool] = lambda: False,
        say: Callable[[str], None] = print,
    ) -> CameraStats:
        """Until the source ends or ``should_stop``: each frame's faces published, each
        face lost (and, at the end, each still held) DELETEd."""
        options, model = self.options, face_model()
        stats, ids = CameraStats(), FaceIds(prefix=options.id_prefix)
        lines = _FacingLines(options.threshold_deg, options.hysteresis_deg, say)
        started = time.monotonic()
        first, self._first = self._first, None
        camera, mount = self._camera, options.mount  # frames share the first one's size
        try:
            for image in itertools.chain(() if first is None else (first,), self._frames or ()):
                if should_stop() or camera is None:
                    break
                wall, cpu = time.perf_counter(), time.process_time()
                heads = _heads(self._mesh(image), model, camera)
                named, lost = ids.update([face for face, _ in heads], time.monotonic())
                stamp = Time.from_seconds(time.time())
                for face_id, (_, seen_by_camera) in zip(named, heads, strict=True):
                    head = seen_by_camera if mount is None else placed(seen_by_camera, mount)
                    publish(
                        _key(options, face_id), _payload(face_id, options.base_frame, stamp, head)
                    )
                    # "facing the camera" is the camera's to say, wherever it is mounted
                    lines.said(face_id, seen_by_camera, time.monotonic() - started)
                if ids.given > stats.faces_seen:  # a face new in this frame: its first result
                    stats.faces_seen = ids.given
                    first_ms = (time.perf_counter() - wall) * 1e3
                    stats.slowest_first_ms = max(stats.slowest_first_ms or 0.0, first_ms)
                for face_id in lost:
                    publish(_key(options, face_id), None)
                    lines.left(face_id, time.monotonic() - started)
                stats.frames += 1
                stats.most_faces = max(stats.most_faces, len(heads))
                stats.busy_s += time.perf_counter() - wall
                stats.cpu_s += time.process_time() - cpu
        finally:
            try:  # each face held is said gone; publishing may fail (the session closed)
                for face_id in ids.forget_all():
                    publish(_key(options, face_id), None)
            finally:  # and the capture and the models are released all the same
                self.close()
        return stats

    def close(self) -> None:
        """Release the camera (or file) and the models; again is nothing."""
        if self._frames is not None:
            self._frames.close()  # the generator's finally releases the capture
            self._mesh.close()
            self._frames = None


def _intrinsics(image: Image, calibration: Intrinsics | None, fov_deg: float) -> Intrinsics:
    height, width = image.shape[:2]
    if calibration is not None:
        return calibration.for_frame(width, height)
    return from_field_of_view(width, height, fov_deg)


def _heads(
    found: list[FloatArray], model: FaceModel, camera: Intrinsics
) -> list[tuple[FaceSeen, HeadPose]]:
    """Each face the fit could place (in ``camera_link``), with where it is in the frame."""
    heads = []
    for landmarks in found:
        head = fit_head(landmarks, model, camera)
        if head is not None:
            heads.append((seen(landmarks), head))
    return heads


def _key(options: CameraOptions, face_id: str) -> str:
    return keys.pose_key(options.namespace, body_id=face_id, frame_id=options.base_frame)


def _payload(face_id: str, frame: str, stamp: Time, head: HeadPose) -> bytes:
    """The service's input: the face frame (REP 155, x out of the face) as the pose."""
    return json.dumps(pose_dict(face_id, frame, stamp, head.translation, head.rotation)).encode()


@dataclass
class _FacingLines:
    """One line when a face appears, turns toward the camera or away, or leaves: the
    service's own rule (``classify_one``, the angle in the ground plane) at its threshold,
    with its hysteresis (a face at the threshold flickered 19° facing, 20° not,
    20° facing, where the service said facing throughout)."""

    threshold_deg: float
    hysteresis_deg: float
    say: Callable[[str], None]
    _facing: dict[str, bool] = field(default_factory=dict)

    def said(self, face_id: str, head: HeadPose, at_s: float) -> None:
        held = self.hysteresis_deg if self._facing.get(face_id) else 0.0
        _, angle, distance, facing = classify_one(
            head.translation, head.rotation, self.threshold_deg + held
        )
        if self._facing.get(face_id) == facing:
            return
        self._facing[face_id] = facing
        where = "-" if angle is None else f"{angle:.0f}°, {distance:.2f} m"
        state = "facing the camera" if facing else "not facing the camera"
        self.say(f"{at_s:6.1f} s  {face_id} {state} ({where})")

    def left(self, face_id: str, at_s: float) -> None:
        if self._facing.pop(face_id, None) is not None:
            self.say(
                f"{at_s:6.1f} s  {face_id} not seen (turned beyond the detector's reach, or gone)"
            )
