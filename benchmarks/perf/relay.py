"""The bare relay: the physical limit of a one-hop Python zenoh service.

Its subscriber re-publishes every incoming pose payload, untouched, on the output key the
service would use (``.../pose/...`` -> ``.../facing/...``), straight from the callback and
with BLOCK (no loss), so it does the least a zenoh service can do per sample, in one of
three ways (``--style``): ``put``, ``Session.put`` on the key string; ``publishers``, a
publisher declared once per output key; ``keys``, ``Session.put`` on key expressions
declared once for both the output key and the input key (zenoh then routes both from its
cache: the cheapest in nearly every cell of the grid, docs/performance.md).

    python -m benchmarks.perf.relay -l tcp/127.0.0.1:7447 [--namespace hri] [--style put]
"""

from __future__ import annotations

import argparse
import signal

import zenoh

from facing_service.contract import keys
from facing_service.testing import loopback_config

JSON = zenoh.Encoding.APPLICATION_JSON
BLOCK = zenoh.CongestionControl.BLOCK


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-l", "--listen", required=True)
    parser.add_argument("--namespace", default="hri")
    parser.add_argument("--style", choices=("put", "publishers", "keys"), default="put")
    args = parser.parse_args()
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM, signal.SIGINT})
    with zenoh.open(loopback_config(listen=[args.listen])) as session:
        outputs: dict[str, zenoh.Publisher | zenoh.KeyExpr | str] = {}  # by input key
        declared: list[zenoh.KeyExpr] = []

        def output(key: str) -> zenoh.Publisher | zenoh.KeyExpr | str:
            body = keys.body_of(key)
            out = keys.facing_key(args.namespace, body_id=body.body_id, frame_id=body.frame_id)
            if args.style == "publishers":
                return session.declare_publisher(out, encoding=JSON, congestion_control=BLOCK)
            if args.style == "keys":
                declared.extend((session.declare_keyexpr(out), session.declare_keyexpr(key)))
                return declared[-2]
            return out

        def relay(sample: zenoh.Sample) -> None:
            key = str(sample.key_expr)
            if (out := outputs.get(key)) is None:
                out = outputs[key] = output(key)
            if isinstance(out, zenoh.Publisher):
                out.put(sample.payload)
            else:
                session.put(out, sample.payload, encoding=JSON, congestion_control=BLOCK)

        subscriber = session.declare_subscriber(
            keys.pose_key(args.namespace, body_id="*", frame_id="*"), relay
        )
        # a queryable so the driver can tell when the relay is up, like the service's status
        ready = session.declare_queryable(
            keys.status_key(args.namespace, "relay"),
            lambda q: (q.reply(q.key_expr, b"{}"), q.drop()),
        )
        signal.sigwait({signal.SIGTERM, signal.SIGINT})
        ready.undeclare()
        subscriber.undeclare()
        for out in outputs.values():
            if isinstance(out, zenoh.Publisher):
                out.undeclare()
        for key_expr in declared:
            session.undeclare(key_expr)


if __name__ == "__main__":
    main()
