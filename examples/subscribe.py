"""Every result as it is published, in plain zenoh: who faces the robot, pose by pose.

    python examples/subscribe.py [-e tcp/<host>:7447] [--frame base_link]

A result (docs/contract.md, FacingState) goes out on NS/bodies/<id>/facing/<frame> for
every pose while anyone subscribes to results; a DELETE there says the body was lost.
"""

from __future__ import annotations

import json
import time

import zenoh
from common import arguments, session_config


def main() -> None:
    args = arguments(__doc__)

    def show(sample: zenoh.Sample) -> None:
        if sample.kind == zenoh.SampleKind.DELETE:
            print(f"{sample.key_expr}: lost", flush=True)
            return
        result = json.loads(sample.payload.to_bytes())
        said = "faces the robot" if result["facing"] else "looks elsewhere"
        print(f"{result['body_id']} {said} ({result['distance_m']:.1f} m)", flush=True)

    with zenoh.open(session_config(args)) as session:
        subscriber = session.declare_subscriber(f"hri/bodies/*/facing/{args.frame}", show)
        try:
            time.sleep(args.duration_s if args.duration_s is not None else 1e9)
        except KeyboardInterrupt:
            pass
        finally:
            subscriber.undeclare()  # an open callback subscriber would hang the exit


if __name__ == "__main__":
    main()
