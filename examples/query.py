"""Ask the service, in plain zenoh: everyone in a frame now, decided under a wider cone.

    .venv/bin/python examples/query.py [-e tcp/<host>:7447] [--base-frame base_link]
                                        [--threshold-deg 35]

A `get` on NS/bodies/*/facing/<frame> is answered from the service's state, with one
FacingState per body; `threshold_deg` re-decides them under another cone. A refusal is an
error reply naming why (an unknown frame names the frames the service tracks).
"""

from __future__ import annotations

import json
import sys
import time

import zenoh
from common import arguments, run, say, session_config


def main() -> int:
    args = arguments(__doc__, extra=lambda p: p.add_argument("--threshold-deg", type=float))
    selector = f"hri/bodies/*/facing/{args.frame}"
    if args.threshold_deg is not None:
        selector += f"?threshold_deg={args.threshold_deg}"
    with zenoh.open(session_config(args)) as session:
        time.sleep(0.5)  # let the session meet the service before asking
        replies = list(session.get(selector, timeout=2.0))
        refused = empty = 0
        for reply in replies:
            answer = reply.result  # a sample, or an error: nobody there, or a refusal
            if isinstance(answer, zenoh.ReplyError):
                error = json.loads(answer.payload.to_bytes())
                if nobody_there(error):
                    empty += 1
                else:
                    refused += 1
                    print(f"refused: {error['error']}: {error['detail']}", file=sys.stderr)
                continue
            result = json.loads(answer.payload.to_bytes())
            angle = result["angle_deg"]  # null when the robot is straight above the body
            say(f"{result['body_id']}: facing={result['facing']} "
                f"angle={'-' if angle is None else f'{angle:.0f}°'}")  # fmt: skip
        if empty + refused == len(replies) and empty:  # said once, however many services
            say(f"nobody in frame {args.frame} now")
    if not replies:  # no answer at all: no service (an empty one answers with nobody)
        print(f"no facing service answered {selector} within 2 s", file=sys.stderr)
        return 1
    return 1 if refused == len(replies) else 0  # every service refused: a wrong frame


def nobody_there(error: dict) -> bool:
    """An error reply that means an empty room (docs/contract.md): nobody in a frame the
    service knows, or a service that tracks nobody anywhere yet (every frame is unknown
    to it, the right one too)."""
    nothing_tracked = error["detail"].endswith("frames tracked: none")
    return error["error"] in ("empty_frame", "not_tracked") or nothing_tracked


if __name__ == "__main__":
    run(main)
