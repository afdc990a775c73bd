"""The ROS 2 input's own cost per /tf message, in-process: ``People.on_tf`` (TF insert,
whom it concerns, lookups, the pose) as a robot streams, one transform a message.

    python -m benchmarks.perf.people [--people 10] [--seconds 10] [--repeat 5]

Two robots: bodies alone (``body_<id>`` tracked, no persons), and persons linking a face
and a body each (the face a participant's pose, the body its stance), faces
and bodies at 30 Hz; then a tracked list changing one id a message, at ``--people`` and
at 10 000. Best of ``--repeat``, microseconds a message. To compare two trees,
run it in each, alternated (the machine is shared and noisy).
"""

from __future__ import annotations

import argparse
import time

from facing_service.contract.stamps import Time
from facing_service.core.tf.geometry import RigidTransform
from facing_service.ros2.people import People, TfInput

HZ = 30


def _message(frame: str, t: float, i: int) -> list[TfInput]:
    where = RigidTransform((2.0 + 0.01 * (i % 7), 0.1 * i, 1.0), (0.0, 0.0, 1.0, 0.0))
    return [TfInput("base_link", frame, Time.from_seconds(t), where)]


def robot(people: int, persons: bool) -> tuple[People, list[list[TfInput]]]:
    """A People that tracks ``people`` humans, and the /tf messages of their frames."""
    robot = People("base_link")
    faces = [f"f{i}" for i in range(people)] if persons else []
    bodies = [f"b{i}" for i in range(people)]
    robot.on_tracked("/humans/bodies/tracked", bodies)
    if persons:
        robot.on_tracked("/humans/faces/tracked", faces)
        for i in range(people):
            robot.on_person_link(f"p{i}", "face_id", f"f{i}")
            robot.on_person_link(f"p{i}", "body_id", f"b{i}")
        robot.on_tracked("/humans/persons/tracked", [f"p{i}" for i in range(people)])
    frames = [f"body_{b}" for b in bodies] + [f"face_{f}" for f in faces]
    return robot, [_message(frame, 1.0 + k / HZ, i) for k in range(HZ) for i, frame in
                   enumerate(frames)]  # fmt: skip


def per_message_us(people: int, persons: bool, seconds: float) -> float:
    """Microseconds ``on_tf`` takes a message, over ``seconds`` of the robot's stream."""
    subject, messages = robot(people, persons)
    rounds = max(1, round(seconds))
    started = time.perf_counter()
    for r in range(rounds):
        shift = Time.from_seconds(float(r))
        for message in messages:
            t = message[0]
            assert t.stamp is not None  # _message stamps every one
            subject.on_tf([TfInput(t.parent, t.child, Time(t.stamp + shift), t.transform)],
                          static=False)  # fmt: skip
    return (time.perf_counter() - started) / (rounds * len(messages)) * 1e6


def per_list_change_us(people: int, changes: int) -> float:
    """Microseconds a tracked list message takes when one id leaves it or comes back
    (who is there is derived again from the lists and links), at ``people`` persons each
    linking a face and a body."""
    subject, _ = robot(people, persons=True)
    faces = [f"f{i}" for i in range(people)]
    started = time.perf_counter()
    for k in range(changes):
        subject.on_tracked("/humans/faces/tracked", faces[1:] if k % 2 == 0 else faces)
    return (time.perf_counter() - started) / changes * 1e6


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--people", type=int, default=10)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    for persons, label in ((False, "bodies alone"), (True, "persons with a face and a body")):
        best = min(per_message_us(args.people, persons, args.seconds) for _ in range(args.repeat))
        print(f"{label:32} {best:6.1f} us a message ({args.people} people)", flush=True)
    for people, changes in ((args.people, 200), (10_000, 10)):
        best = min(per_list_change_us(people, changes) for _ in range(args.repeat))
        print(f"{'a list changing one id':32} {best:8.1f} us a message ({people} people)",
              flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
