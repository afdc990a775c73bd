"""The camera front end's cost, its reach and its answers on real photographs,
in the camera extra's environment:

    .venv-camera/bin/python -m benchmarks.camera --out benchmarks/results/camera.json

On one core (the process pinned to CPU 0, MediaPipe's threads with it). **Speed**: frames
of 640x480 and 1280x720 with 1, 3 and 5 faces (scikit-image's astronaut, tiled, moved a
pixel a frame so no frame repeats) through the front end's whole per-frame work (detector
on the frame and its tiles, mesh, fit, ids), frames a second and CPU per frame, at the
default reach (5 m) and at 2 m (the whole frame only, as before the tiling); each face's
first result after its first frame, from a fresh front end. **Reach**: a frontal face (the
astronaut) and a turned one (the cameraman, three-quarter view), each also mirrored, scaled
to a 15 cm face at 1 to 8 m for a 65° camera and pasted at six places of a frame (a
coffee cup's photograph behind); each placement held 8 frames (a person standing a
moment: the tiles take turns); found and said facing (frontal), found and said not facing
(turned). Then the photographs: the frontal face's angle, the three-quarter one's, a
mirror's sign, a half-size face's distance.
"""

from __future__ import annotations

import argparse
import itertools
import math
import os
import statistics
import time
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import skimage.data

from facing_service.camera.face_ids import FaceIds
from facing_service.camera.face_model import face_model
from facing_service.camera.frames import on_frame as placed
from facing_service.camera.frontend import DEFAULT_REACH_M, FACE_WIDTH_M, tile_for
from facing_service.camera.head_pose import HeadPose, fit_head
from facing_service.camera.intrinsics import from_field_of_view
from facing_service.camera.landmarks import TILES_PER_FRAME, FaceMesh, seen, tiles
from facing_service.camera.native_log import without_native_chatter
from facing_service.core.detector import classify_one, robot_in_body

from . import results_file

SIZES = ((640, 480), (1280, 720))
SPOTS = [(10, 10), (10, 225), (10, 440), (250, 115), (250, 330)]  # in 640x480
CAMERA = from_field_of_view(640, 480)
REACHES = (DEFAULT_REACH_M, None)  # the default; the whole frame only
DISTANCES_M = (1, 2, 3, 4, 5, 6, 7, 8)
#: Where a face is put in the reach's frames (shares of the width and height).
PLACES = [(fx, fy) for fx in (0.2, 0.5, 0.8) for fy in (0.35, 0.65)]
HELD = 8  # frames each placement is held at the least: the tiles take turns


def astronaut_face() -> np.ndarray:
    return np.ascontiguousarray(skimage.data.astronaut()[0:320, 80:370])


def cameraman_face() -> np.ndarray:
    return np.ascontiguousarray(np.stack([skimage.data.camera()[50:300, 120:360]] * 3, -1))


def tiled(faces: int, size: tuple[int, int]) -> np.ndarray:
    """``faces`` astronauts as large as in a 640x480 frame at 1 m, in a frame of ``size``."""
    width, height = size
    scale = min(width / 640, height / 480)
    face = cv2.resize(astronaut_face(), (round(190 * scale), round(210 * scale)))
    frame = np.full((height, width, 3), 110, np.uint8)
    for row, col in SPOTS[:faces]:
        r, c = round(row * height / 480), round(col * width / 640)
        frame[r : r + face.shape[0], c : c + face.shape[1]] = face
    return frame


def per_frame(mesh: FaceMesh, frame: np.ndarray, ids: FaceIds, now: float) -> int:
    """The front end's work on one frame; the faces placed."""
    camera = from_field_of_view(frame.shape[1], frame.shape[0])
    heads = [(seen(lm), fit_head(lm, face_model(), camera)) for lm in mesh(frame)]
    ids.update([face for face, head in heads if head is not None], now)
    return sum(head is not None for _, head in heads)


def front_end(size: tuple[int, int], reach_m: float | None, faces: int = 5) -> FaceMesh:
    """The front end's face finder for a camera of ``size`` (65°) and a reach (None: the
    whole frame only, as before the tiling)."""
    tile = None if reach_m is None else tile_for(from_field_of_view(*size), reach_m)
    return FaceMesh(faces, tile)


def held(size: tuple[int, int], reach_m: float | None) -> int:
    """How many frames a placement is held: every tile's turn, and a frame more."""
    tile = None if reach_m is None else tile_for(from_field_of_view(*size), reach_m)
    return max(HELD, math.ceil(len(tiles(*size, tile)) / TILES_PER_FRAME) + 1) if tile else HELD


def speed(faces: int, frames: int, size: tuple[int, int], reach_m: float | None) -> dict[str, Any]:
    frame = tiled(faces, size)
    mesh = front_end(size, reach_m)
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
        "size": f"{size[0]}x{size[1]}",
        "reach_m": reach_m,
        "faces": faces,
        "found_mean": statistics.fmean(found),
        "first_frame_found": first_found,
        "first_result_ms": round(first_ms, 1),
        "fps": round(frames / wall, 1),
        "cpu_ms_per_frame": round(cpu / frames * 1e3, 1),
    }


def reach(size: tuple[int, int], reach_m: float | None) -> list[dict[str, Any]]:
    """Per distance: the share of frontal faces found and said facing, of turned ones found
    and said not facing (a face not found is neither)."""
    width, height = size
    camera = from_field_of_view(width, height)
    background = cv2.resize(skimage.data.coffee(), (width, height))
    faces = {"frontal": astronaut_face(), "turned": cameraman_face()}
    box = {name: face_width_px(face) for name, face in faces.items()}
    rows = []
    for distance in DISTANCES_M:
        px = FACE_WIDTH_M * camera.fx / distance
        said = {}
        for name, face in faces.items():
            right = 0
            for (fx, fy), mirror in itertools.product(PLACES, (False, True)):
                scaled = cv2.resize(face, None, fx=px / box[name], fy=px / box[name],
                                    interpolation=cv2.INTER_AREA)  # fmt: skip
                frame = pasted(background, scaled[:, ::-1] if mirror else scaled, fx, fy)
                mesh = front_end(size, reach_m)
                for _ in range(held(size, reach_m)):
                    found = mesh(frame)
                mesh.close()
                verdicts = [
                    classify_one(h.translation, h.rotation, 20.0)[3]
                    for h in (fit_head(lm, face_model(), camera) for lm in found)
                    if h is not None
                ]
                right += bool(verdicts) and verdicts[0] == (name == "frontal")
            said[name] = right / (len(PLACES) * 2)
        rows.append({"distance_m": distance, "face_px": round(px, 1), **said})
    return rows


def face_width_px(face: np.ndarray) -> float:
    """The face's width in its photograph, as the detector boxes it (the 15 cm a face at a
    distance is scaled to)."""
    import mediapipe as mp

    with mp.solutions.face_detection.FaceDetection(model_selection=1) as detector:
        (found,) = detector.process(face).detections
    return float(found.location_data.relative_bounding_box.width * face.shape[1])


def pasted(background: np.ndarray, face: np.ndarray, fx: float, fy: float) -> np.ndarray:
    frame = background.copy()
    height, width = frame.shape[:2]
    top, left = max(0, (face.shape[0] - height) // 2), max(0, (face.shape[1] - width) // 2)
    face = face[top : top + height, left : left + width]  # a photo larger than the frame
    h, w = face.shape[:2]
    x = min(max(0, round(width * fx) - w // 2), width - w)
    y = min(max(0, round(height * fy) - h // 2), height - h)
    frame[y : y + h, x : x + w] = face
    return frame


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


def _reach(reach_m: float | None) -> str:
    return "whole frame" if reach_m is None else f"{reach_m:g} m"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=200, help="frames per row (200)")
    parser.add_argument("--out", type=Path, help="write the results here (JSON)")
    args = parser.parse_args()
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one core, threads included
    with without_native_chatter():
        rows = [speed(faces, args.frames, size, reach_m)
                for size in SIZES for reach_m in REACHES for faces in (1, 3, 5)]  # fmt: skip
        reached = {f"{w}x{h} {_reach(r)}": reach((w, h), r) for w, h in SIZES for r in REACHES}
        reached["1280x720 8 m"] = reach((1280, 720), 8.0)
        answers = photographs()
    print("size | reach m | faces | found | fps (one core) | CPU ms a frame | first result ms")
    for row in rows:
        print(f"{row['size']} | {_reach(row['reach_m'])} | {row['faces']} | "
              f"{row['found_mean']:.2f} | {row['fps']} | {row['cpu_ms_per_frame']} | "
              f"{row['first_result_ms']}")  # fmt: skip
    for name, by_distance in reached.items():
        print(name, " ".join(f"{r['distance_m']} m {r['frontal']:.0%}/{r['turned']:.0%}"
                             for r in by_distance))  # fmt: skip
    for name, value in answers.items():
        print(f"{name}: {value}")
    if args.out:
        parameters = {**vars(args), "fov_deg": 65.0}
        results = {"speed": rows, "reach": reached, "photographs": answers}
        results_file.write(args.out, results, "python -m benchmarks.camera", parameters)


if __name__ == "__main__":
    main()
