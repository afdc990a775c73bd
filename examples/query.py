"""Ask the service, in plain zenoh: everyone in a frame now, decided under a wider cone.

    .venv/bin/python examples/query.py [-e tcp/<host>:7447] [--frame base_link] [--threshold-deg 35]

A `get` on NS/bodies/*/facing/<frame> is answered from the service's state, with one
FacingState per body; `threshold_deg` re-decides them under another cone. A refusal is an
error reply naming why (an unknown frame names the frames the service tracks).
"""

from __future__ import annotations

import json
import sys
import time

import zenoh
from common import arguments, run, session_config


def main() -> int:
    args = arguments(__doc__, extra=lambda p: p.add_argument("--threshold-deg", type=float))
    selector = f"hri/bodies/*/facing/{args.frame}"
    if args.threshold_deg is not None:
        selector += f"?threshold_deg={args.threshold_deg}"
    with zenoh.open(session_config(args)) as session:
        time.sleep(0.5)  # let the session meet the service before asking
        replies = list(session.get(selector, timeout=2.0))
        for reply in replies:
            if reply.ok is None:
                print(f"refused: {reply.err.payload.to_string()}", file=sys.stderr)
                continue
            result = json.loads(reply.ok.payload.to_bytes())
            angle = result["angle_deg"]  # null when the robot is straight above the body
            print(f"{result['body_id']}: facing={result['facing']} "
                  f"angle={'-' if angle is None else f'{angle:.0f}°'}", flush=True)  # fmt: skip
    if not replies:  # no answer at all: no service (an empty one answers with nobody)
        print(f"no facing service answered {selector} within 2 s", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    run(main)
