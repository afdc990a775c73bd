"""The bare relay: the physical limit of a one-hop Python zenoh service.

Its subscriber re-publishes every incoming pose payload, untouched, on the output key the
service would use (``.../pose/...`` -> ``.../facing/...``), straight from the callback and
with BLOCK (no loss), so it does the least a zenoh service can do per sample; with
``Session.put`` (``--style put``) or a publisher declared once per output key
(``--style publishers``): which is cheaper depends on how the tracker publishes.

    python -m benchmarks.relay -l tcp/127.0.0.1:7447 [--namespace hri] [--style put]
"""

from __future__ import annotations

import argparse
import signal

import zenoh

from facing_service.contract import keys
from facing_service.testing import loopback_config


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-l", "--listen", required=True)
    parser.add_argument("--namespace", default="hri")
    parser.add_argument("--style", choices=("put", "publishers"), default="put")
    args = parser.parse_args()
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM, signal.SIGINT})
    with zenoh.open(loopback_config(listen=[args.listen])) as session:
        publishers: dict[str, zenoh.Publisher] = {}

        def relay(sample: zenoh.Sample) -> None:
            body = keys.body_of(str(sample.key_expr))
            key = keys.facing_key(args.namespace, body.body_id, body.frame_id)
            if args.style == "put":
                session.put(
                    key,
                    sample.payload,
                    encoding=zenoh.Encoding.APPLICATION_JSON,
                    congestion_control=zenoh.CongestionControl.BLOCK,
                )
                return
            publisher = publishers.get(key)
            if publisher is None:
                publisher = publishers[key] = session.declare_publisher(
                    key,
                    encoding=zenoh.Encoding.APPLICATION_JSON,
                    congestion_control=zenoh.CongestionControl.BLOCK,
                )
            publisher.put(sample.payload)

        subscriber = session.declare_subscriber(keys.pose_key(args.namespace, "*", "*"), relay)
        # a queryable so the driver can tell when the relay is up, like the service's status
        ready = session.declare_queryable(
            keys.status_key(args.namespace, "relay"),
            lambda q: (q.reply(q.key_expr, b"{}"), q.drop()),
        )
        signal.sigwait({signal.SIGTERM, signal.SIGINT})
        ready.undeclare()
        subscriber.undeclare()
        for publisher in publishers.values():
            publisher.undeclare()


if __name__ == "__main__":
    main()
