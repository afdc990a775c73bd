"""Read every service's status, in plain zenoh, as `facing-service health` does.

    .venv/bin/python examples/status.py [-e tcp/<host>:7447]

NS/services/facing/<instance>/status answers a `get` with the service's ServiceStatus:
its instance, version, uptime, bodies tracked per frame and every counter.
"""

from __future__ import annotations

import json
import sys
import time

import zenoh
from common import arguments, run, say, session_config


def main() -> int:
    args = arguments(__doc__, frame=False)
    with zenoh.open(session_config(args)) as session:
        time.sleep(0.5)  # let the session meet the service before asking
        answered = 0
        for reply in session.get("hri/services/facing/*/status", timeout=2.0):
            if reply.ok is not None:
                answered += 1
                status = json.loads(reply.ok.payload.to_bytes())
                counters = status["counters"]
                say(f"{status['instance']}: {status['status']}, facing-service "
                    f"{status['version']}, {status['bodies_tracked_total']} bodies, "
                    f"{counters['samples_accepted']} poses accepted")  # fmt: skip
    if not answered:
        print("no facing service answered its status within 2 s", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    run(main)
