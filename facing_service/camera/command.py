"""``facing-service camera`` and ``demo --camera``'s front end: the flags made into options,
the front end opened (every failure one line), run against a zenoh session, and what it did
said at the end."""

from __future__ import annotations

import argparse
import sys
import threading

import zenoh

from ..client.presence import ServiceWatch
from ..client.sim import TrackerPublisher, nobody_heard
from ..config.disclosure import zenoh_failure
from ..config.session import zenoh_config
from ..config.settings import Settings
from ..contract import keys
from ..contract.words import counted
from .frames import NoSuchPath, Source, SourceError, source_of
from .frontend import CameraFeed, CameraOptions, CameraStats
from .head_pose import Mount
from .intrinsics import CalibrationError
from .native_log import without_native_chatter


def options_of(args: argparse.Namespace, settings: Settings, source: Source) -> CameraOptions:
    """The front end's options from ``camera``'s (or ``demo``'s) flags."""
    return CameraOptions(
        source=source,
        base_frame=args.base_frame,
        namespace=settings.namespace,
        max_faces=args.max_faces,
        id_prefix=args.id_prefix,
        threshold_deg=settings.threshold_deg,
        hysteresis_deg=settings.hysteresis_deg,
        fov_deg=args.fov_deg,
        calibration=args.calibration,
        mount=Mount.of(*args.camera_pose) if args.camera_pose else None,
        reach_m=args.reach_m,
    )


def source_from_flags(args: argparse.Namespace) -> Source:
    """``camera``'s source: ``--video``, ``--images`` or ``--device`` (0 when none)."""
    shape = {"loop": args.loop, "images_fps": args.images_fps, "width": args.width,
             "height": args.height}  # fmt: skip
    if args.video is not None:
        return Source(video=args.video, **shape)
    if args.images is not None:
        return Source(images=args.images, **shape)
    return Source(device=args.device, **shape)


def demo_source(text: str) -> Source:
    """``demo --camera``'s source: a camera index, a video or a folder, played in a loop."""
    return source_of(text, loop=True)


def open_feed(options: CameraOptions, command: str) -> CameraFeed | int:
    """The opened front end, or the exit code after one line saying why not: 2 for what
    the command line got wrong (a calibration, a path that does not exist), whichever
    command was given it; 1 for a source that fails (a camera, a file that is no video)."""
    try:
        feed = CameraFeed(options)
    except CalibrationError as error:
        print(f"facing-service {command}: --calibration: {error}", file=sys.stderr)
        return 2
    except SourceError as error:
        print(f"facing-service {command}: {error}", file=sys.stderr)
        return 2 if isinstance(error, NoSuchPath) else 1
    if feed.reach_note is not None:
        print(f"facing-service {command}: {feed.reach_note}", file=sys.stderr, flush=True)
    return feed


def run_camera_command(args: argparse.Namespace, settings: Settings, stop: threading.Event) -> int:
    """``facing-service camera``: publish the faces until the source ends or Ctrl-C."""
    with without_native_chatter():
        return _publish_faces(args, settings, stop)


def _publish_faces(args: argparse.Namespace, settings: Settings, stop: threading.Event) -> int:
    feed = open_feed(options_of(args, settings, source_from_flags(args)), "camera")
    if isinstance(feed, int):
        return feed
    key = keys.pose_key(settings.namespace, body_id="<id>", frame_id=args.base_frame)
    print(f"camera: faces of {feed.options.source.describe()} as poses on {key} (Ctrl-C ends)",
          flush=True)  # fmt: skip
    try:
        session = zenoh.open(zenoh_config(settings))
    except zenoh.ZError as error:
        feed.close()
        print(zenoh_failure("camera", error), file=sys.stderr)
        return 1
    watch = ServiceWatch(session, "camera", settings.namespace, settings.connect, _warn)
    with session, watch:
        publish = TrackerPublisher(session)
        try:
            stats = feed.run(publish, stop.is_set, _say)
        finally:
            publish.close()
    print(summary(stats), flush=True)
    print(f"published {publish.poses} poses and {publish.deletes} deletes, {publish.heard} heard "
          "by a subscriber")  # fmt: skip
    if publish.poses and not publish.heard:
        nobody = nobody_heard("camera", key, settings.namespace, settings.connect)
        print(f"{nobody} (demo --camera runs one beside the camera)", file=sys.stderr)
        return 1
    return 0


def summary(stats: CameraStats) -> str:
    """One line of what the front end did and what it cost."""
    if not stats.frames:
        return "camera: no frame read"
    per_frame = stats.busy_s / stats.frames
    first = stats.slowest_first_ms
    return (
        f"camera: {stats.frames} frames, {1 / per_frame if per_frame else 0:.0f} a second of "
        f"work ({stats.cpu_s / stats.frames * 1e3:.1f} ms CPU a frame), up to "
        f"{counted(stats.most_faces, 'face', 'faces')} at once, {stats.faces_seen} seen"
        + (f" (slowest first result {first:.0f} ms)" if first is not None else "")
    )


def _say(line: str) -> None:
    print(line, flush=True)


def _warn(line: str) -> None:
    print(line, file=sys.stderr, flush=True)
