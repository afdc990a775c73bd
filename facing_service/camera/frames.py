"""Where the frames come from: a camera (by index), a video file or a folder of images,
each opened with a one-line error for what goes wrong (no camera, a busy one, a file that
is not a video) and paced as the scene was: a camera at its own rate, a video at its
frame rate, images at ``images_fps``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Generator, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
from numpy.typing import NDArray

#: An RGB frame, height x width x 3 (OpenCV's arrays are typed loosely).
Image = NDArray[Any]
IMAGE_SUFFIXES = (".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff", ".webp")
#: When a video does not say its rate.
FALLBACK_FPS = 30.0
#: What a camera is asked for when no size is given (width, height).
CAMERA_SIZE = (640, 480)


class SourceError(RuntimeError):
    """A source of frames that cannot be used, said in one line."""


class NoSuchPath(SourceError):
    """A video or folder named that does not exist: a mistake in the command line (exit 2,
    as for any flag), where a camera that fails or a file that is no video is not."""


@dataclass(frozen=True)
class Source:
    """One of: a camera ``device`` index, a ``video`` file, a folder of ``images``."""

    device: int | None = None
    video: Path | None = None
    images: Path | None = None
    loop: bool = False
    images_fps: float = 5.0
    #: A camera is asked for frames of this size (None: 640x480); a folder's images are
    #: put on frames of it (None: the first image's own size, as its camera took it).
    width: int | None = None
    height: int | None = None

    @property
    def live(self) -> bool:
        return self.device is not None

    def describe(self) -> str:
        if self.device is not None:
            return f"camera {self.device}"
        return f"video {self.video}" if self.video is not None else f"images in {self.images}"


def source_of(text: str, **options: object) -> Source:
    """``demo --camera``'s argument: a number is a camera, a folder is images, a file a
    video."""
    if text.isdigit():
        return Source(device=int(text), **options)  # type: ignore[arg-type]
    path = Path(text)
    if path.is_dir():
        return Source(images=path, **options)  # type: ignore[arg-type]
    if path.exists():
        return Source(video=path, **options)  # type: ignore[arg-type]
    raise SourceError(f"{text}: neither a camera index nor an existing video or folder")


def frames(
    source: Source, sleep: Callable[[float], None] = time.sleep
) -> Generator[Image, None, None]:
    """The source's frames as RGB images, in real time; opening errors raise SourceError
    before the first frame."""
    if source.images is not None:
        return _images(source, sleep)
    capture = _open_camera(source) if source.device is not None else _open_video(source)
    return _captured(capture, source, sleep)


def _open_camera(source: Source) -> cv2.VideoCapture:
    index = source.device
    assert index is not None
    if sys.platform.startswith("linux") and not Path(f"/dev/video{index}").exists():
        raise SourceError(f"no camera {index}: /dev/video{index} does not exist")
    capture = cv2.VideoCapture(index)
    if not capture.isOpened():
        raise SourceError(f"camera {index} could not be opened (busy in another program?)")
    capture.set(cv2.CAP_PROP_FRAME_WIDTH, source.width or CAMERA_SIZE[0])
    capture.set(cv2.CAP_PROP_FRAME_HEIGHT, source.height or CAMERA_SIZE[1])
    return capture


def _open_video(source: Source) -> cv2.VideoCapture:
    path = source.video
    assert path is not None
    if not path.is_file():
        raise NoSuchPath(f"{path}: no such file")
    capture = cv2.VideoCapture(str(path))
    if not capture.isOpened():
        raise SourceError(f"{path}: cannot be read as a video")
    return capture


def _captured(
    capture: cv2.VideoCapture, source: Source, sleep: Callable[[float], None]
) -> Generator[Image, None, None]:
    ok, first = capture.read()
    if not ok:
        capture.release()
        hint = " (busy in another program?)" if source.live else ": cannot be read as a video"
        raise SourceError(f"{source.describe()} gave no frame{hint}")

    def read() -> Generator[Image, None, None]:
        frame: Image | None = first
        try:
            while frame is not None:
                yield cv2.cvtColor(frame, cv2.COLOR_BGR2RGB)
                ok, frame = capture.read()
                if not ok and source.loop:
                    capture.set(cv2.CAP_PROP_POS_FRAMES, 0)
                    ok, frame = capture.read()
                if not ok:
                    frame = None
        finally:
            capture.release()

    if source.live:  # a camera paces itself
        return read()
    return _paced(read(), 1.0 / (capture.get(cv2.CAP_PROP_FPS) or FALLBACK_FPS), sleep)


def _images(source: Source, sleep: Callable[[float], None]) -> Generator[Image, None, None]:
    folder = source.images
    assert folder is not None
    if not folder.is_dir():
        raise NoSuchPath(f"{folder}: no such folder")
    paths = sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
    loaded = [(p, cv2.imread(str(p), cv2.IMREAD_COLOR)) for p in paths]
    images = [image for _, image in loaded if image is not None]
    if not images:
        unread = f" ({len(paths)} could not be read)" if paths else ""
        raise SourceError(f"{folder}: no image to read{unread} ({', '.join(IMAGE_SUFFIXES)})")
    for path, image in loaded:
        if image is None:
            print(f"camera: skipped {path}: cannot be read as an image", file=sys.stderr)
    width, height = frame_size(source, images)
    readable = [on_frame(cv2.cvtColor(image, cv2.COLOR_BGR2RGB), width, height) for image in images]

    def cycle() -> Iterator[Image]:
        yield from readable
        while source.loop:
            yield from readable

    return _paced(cycle(), 1.0 / source.images_fps, sleep)


def frame_size(source: Source, images: list[Image]) -> tuple[int, int]:
    """The size of a folder's frames: the one asked for, else the first image's (a
    calibration is then judged against the images as they are). Images of
    another size are fitted onto it, said once: a calibration holds for one size."""
    first = images[0].shape[1], images[0].shape[0]
    width, height = source.width or first[0], source.height or first[1]
    other = sum((image.shape[1], image.shape[0]) != (width, height) for image in images)
    if other:
        print(
            f"camera: {other} of {len(images)} images in {source.images} are not {width}x"
            f"{height}: each is fitted onto a {width}x{height} frame (what the intrinsics "
            "describe)",
            file=sys.stderr,
        )
    return width, height


def on_frame(image: Image, width: int, height: int, scale: float | None = None) -> Image:
    """``image`` centred on a grey frame of ``width`` x ``height``, scaled to fit (or by
    ``scale``, cut to the frame): a folder's photographs of any size become frames of one
    camera, whose intrinsics hold for all of them."""
    if scale is None:
        scale = min(width / image.shape[1], height / image.shape[0])
    sized = cv2.resize(image, None, fx=scale, fy=scale, interpolation=cv2.INTER_AREA)
    rows, cols = min(sized.shape[0], height), min(sized.shape[1], width)
    top, left = (height - rows) // 2, (width - cols) // 2
    frame = np.full((height, width, 3), 110, np.uint8)
    frame[top : top + rows, left : left + cols] = sized[:rows, :cols]
    return frame


def _paced(
    images: Iterator[Image], period: float, sleep: Callable[[float], None]
) -> Generator[Image, None, None]:
    """``images`` no faster than one a ``period``, as they were recorded (a video played
    faster than real time would compress every timing the service keeps)."""
    started = time.monotonic()
    try:
        for count, image in enumerate(images, start=1):
            yield image
            ahead = started + count * period - time.monotonic()
            if ahead > 0:
                sleep(ahead)
    finally:
        if isinstance(images, Generator):
            images.close()  # a capture released now, not when collected
