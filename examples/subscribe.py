"""Every result as it is published, in plain zenoh: who faces the robot, pose by pose.

    .venv/bin/python examples/subscribe.py [-e tcp/<host>:7447] [--base-frame base_link]

A result (docs/contract.md, FacingState) goes out on NS/bodies/<id>/facing/<frame> for
every pose while anyone subscribes to results; a DELETE there says the body was lost.
"""

from __future__ import annotations

import json
import sys
import time

import zenoh
from common import arguments, run, say, session_config


def main() -> int:
    args = arguments(__doc__)

    heard: list[zenoh.SampleKind] = []

    def show(sample: zenoh.Sample) -> None:
        heard.append(sample.kind)
        if sample.kind == zenoh.SampleKind.DELETE:
            say(f"{sample.key_expr}: lost")
            return
        result = json.loads(sample.payload.to_bytes())
        said = "faces the robot" if result["facing"] else "looks elsewhere"
        far = result["distance_m"]  # null when the robot is straight above the body
        at = "" if far is None else f" ({far:.1f} m)"
        say(f"{result['body_id']} {said}{at}")

    with zenoh.open(session_config(args)) as session:
        subscriber = session.declare_subscriber(f"hri/bodies/*/facing/{args.frame}", show)
        try:
            time.sleep(1.0)  # let the session meet the service
            if not list(session.liveliness().get("hri/services/facing/*", timeout=1.0)):
                print("no facing service seen yet: results print as they come", file=sys.stderr)
            time.sleep(max(args.duration_s - 2.0, 0) if args.duration_s is not None else 1e9)
        except KeyboardInterrupt:
            pass
        finally:
            subscriber.undeclare()  # an open callback subscriber would hang the exit
    if not heard:  # a run that heard nothing says so, and fails
        print(f"heard no result on hri/bodies/*/facing/{args.frame}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    run(main)
