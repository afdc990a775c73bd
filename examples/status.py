"""Read every service's status, in plain zenoh, as `facing-service health` does.

    python examples/status.py [-e tcp/<host>:7447]

NS/services/facing/<instance>/status answers a `get` with the service's ServiceStatus:
its instance, version, uptime, bodies tracked per frame and every counter.
"""

from __future__ import annotations

import json
import time

import zenoh
from common import arguments, session_config


def main() -> None:
    args = arguments(__doc__)
    with zenoh.open(session_config(args)) as session:
        time.sleep(0.5)  # let the session meet the service before asking
        for reply in session.get("hri/services/facing/*/status", timeout=2.0):
            if reply.ok is not None:
                status = json.loads(reply.ok.payload.to_bytes())
                counters = status["counters"]
                print(f"{status['instance']}: {status['status']}, facing-service "
                      f"{status['version']}, {status['bodies_tracked_total']} bodies, "
                      f"{counters['samples_accepted']} poses accepted", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
