"""The camera front end's cost and its answers on real photographs (issue 62), in the camera
extra's environment:

    .venv-camera/bin/python -m benchmarks.camera --out benchmarks/results/camera.json

On one core (the process pinned to CPU 0, MediaPipe's threads with it): frames of 640x480
with 1, 3 and 5 faces (scikit-image's astronaut, tiled, moved a pixel a frame so no frame
repeats) through the front end's whole per-frame work (detector, mesh, fit, ids), frames a
second and CPU per frame; each face's first result after its first frame, from a fresh
front end (its models' first run included). Then the photographs: the frontal face's angle,
the three-quarter one's, a mirror's sign, a half-size face's distance.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time
from pathlib import Path

import cv2
import numpy as np
import skimage.data

from facing_service.camera.face_ids import FaceIds
from facing_service.camera.face_model import face_model
from facing_service.camera.frames import on_frame as placed
from facing_service.camera.head_pose import HeadPose, fit_head
from facing_service.camera.intrinsics import from_field_of_view
from facing_service.camera.landmarks import FaceMesh, seen
from facing_service.camera.native_log import without_native_chatter
from facing_service.core.detector import classify_one, robot_in_body

from . import results_file

FRAME = (480, 640)
SPOTS = [(10, 10), (10, 225), (10, 440), (250, 115), (250, 330)]
CAMERA = from_field_of_view(640, 480)


def tiled(faces: int) -> np.ndarray:
    face = cv2.resize(np.ascontiguousarray(skimage.data.astronaut()[0:320, 80:370]), (190, 210))
    frame = np.full((*FRAME, 3), 110, np.uint8)
    for row, col in SPOTS[:faces]:
        frame[row : row + 210, col : col + 190] = face
    return frame


def per_frame(mesh: FaceMesh, frame: np.ndarray, ids: FaceIds, now: float) -> int:
    """The front end's work on one frame; the faces placed."""
    heads = [(seen(lm), fit_head(lm, face_model(), CAMERA)) for lm in mesh(frame)]
    ids.update([face for face, head in heads if head is not None], now)
    return sum(head is not None for _, head in heads)


def speed(faces: int, frames: int) -> dict[str, float]:
    frame = tiled(faces)
    mesh = FaceMesh(max_faces=5)
    started = time.perf_counter()
    first_found = per_frame(mesh, frame, FaceIds(), 0.0)
    first_ms = (time.perf_counter() - started) * 1e3
    ids, found = FaceIds(), []
    wall, cpu = time.perf_counter(), time.process_time()
    for index in range(frames):
        found.append(per_frame(mesh, np.roll(frame, index % 8, axis=1), ids, index / 30))
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    mesh.close()
    return {
        "faces": faces,
        "found_mean": statistics.fmean(found),
        "first_frame_found": first_found,
        "first_result_ms": round(first_ms, 1),
        "fps": round(frames / wall, 1),
        "cpu_ms_per_frame": round(cpu / frames * 1e3, 1),
    }


def signed_angle(head: HeadPose) -> float:
    r = robot_in_body(np.array([head.translation]), np.array([head.rotation]))[0]
    return math.degrees(math.atan2(r[1], r[0]))


def photographs() -> dict[str, float | bool]:
    mesh = FaceMesh(max_faces=1)
    astronaut = np.ascontiguousarray(skimage.data.astronaut())
    cameraman = np.ascontiguousarray(np.stack([skimage.data.camera()] * 3, -1))

    def head(frame: np.ndarray) -> HeadPose:
        (landmarks,) = mesh(frame)
        fitted = fit_head(landmarks, face_model(), CAMERA)
        assert fitted is not None
        return fitted

    frontal, turned = head(placed(astronaut, 640, 480, 1.0)), head(placed(cameraman, 640, 480, 1.0))
    mirrored = head(placed(np.ascontiguousarray(cameraman[:, ::-1]), 640, 480, 1.0))
    near, far = head(placed(astronaut, 640, 480, 0.9)), head(placed(astronaut, 640, 480, 0.45))
    mesh.close()
    return {
        "astronaut_angle_deg": round(signed_angle(frontal), 1),
        "astronaut_facing": classify_one(frontal.translation, frontal.rotation, 20.0)[3],
        "astronaut_distance_m": round(float(np.linalg.norm(frontal.translation)), 2),
        "cameraman_angle_deg": round(signed_angle(turned), 1),
        "cameraman_facing": classify_one(turned.translation, turned.rotation, 20.0)[3],
        "cameraman_mirrored_angle_deg": round(signed_angle(mirrored), 1),
        "half_size_distance_ratio": round(
            float(np.linalg.norm(far.translation) / np.linalg.norm(near.translation)), 3
        ),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=300, help="frames per face count (300)")
    parser.add_argument("--out", type=Path, help="write the results here (JSON)")
    args = parser.parse_args()
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one core, threads included
    with without_native_chatter():
        rows = [speed(faces, args.frames) for faces in (1, 3, 5)]
        answers = photographs()
    print("faces | found | fps (one core) | CPU ms a frame | first result ms (fresh models)")
    for row in rows:
        print(f"{row['faces']} | {row['found_mean']:.2f} | {row['fps']} | "
              f"{row['cpu_ms_per_frame']} | {row['first_result_ms']}")  # fmt: skip
    for name, value in answers.items():
        print(f"{name}: {value}")
    if args.out:
        parameters = {**vars(args), "frame": "640x480", "fov_deg": 65.0}
        results = {"speed": rows, "photographs": answers}
        results_file.write(args.out, results, "python -m benchmarks.camera", parameters)


if __name__ == "__main__":
    main()
