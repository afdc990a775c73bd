"""``facing-service record OUT.mcap``: a running session kept as MCAP while it runs: every
input pose and everything the service publishes in its namespace (results, engagement,
events, groups, who faces whom) as JSON with its JSON Schema, and its status once a
second. Written by Foxglove's SDK (its MCAP writer, in Rust, chunked and compressed), so
the Foxglove app opens it as it is and ``replay`` plays its poses into a service again.

A client of the namespace like ``watch``: it costs the service one more subscriber. The
callback only hands each sample to the writer (microseconds; the SDK buffers), so it
never holds up the session.
"""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path
from typing import Any

import zenoh

from ..client.health import ask
from ..contract import keys
from .session_mcap import DELETES, PROFILE, schema_bytes, schema_file

STATUS_EVERY_S = 1.0


def missing_extra() -> str | None:
    """Why sessions cannot be written or read here (the optional extra), or None."""
    try:
        import foxglove  # noqa: F401
        import mcap  # noqa: F401
    except ImportError as error:
        return (
            f"needs the foxglove extra ({error.name} is not installed): "
            "pip install 'facing-service[foxglove]'"
        )
    return None


class SessionRecorder:
    """Records ``namespace`` from ``session`` into the new file ``out`` until ``close``."""

    def __init__(self, session: zenoh.Session, namespace: str, out: Path) -> None:
        import foxglove  # the extra: only for the commands that record

        self.session = session
        self.namespace = namespace
        self._foxglove = foxglove
        self._context = foxglove.Context()
        options = foxglove.mcap.MCAPWriteOptions(profile=PROFILE)
        self._writer = foxglove.open_mcap(out, context=self._context, writer_options=options)
        self._writer.write_metadata("session", {"namespace": namespace})
        self._channels: dict[str, Any] = {}
        self._lock = threading.Lock()
        self.messages = self.inputs = self.deletes = self.skipped = 0
        self._stop = threading.Event()
        self._subscriber = session.declare_subscriber(f"{namespace}/**", self._on_sample)
        self._status = threading.Thread(target=self._ask_status, name="facing-record-status")
        self._status.start()

    def _channel(self, topic: str, schema: str) -> Any:
        channel = self._channels.get(topic)
        if channel is None:
            fox = self._foxglove
            channel = self._channels[topic] = fox.Channel(
                topic,
                schema=fox.Schema(
                    name="delete" if schema == DELETES else schema.removesuffix(".schema.json"),
                    encoding="jsonschema",
                    data=schema_bytes(schema),
                ),
                message_encoding="json",
                context=self._context,
            )
        return channel

    def _log(self, topic: str, schema: str, payload: bytes) -> None:
        with self._lock:
            self._channel(topic, schema).log(payload, log_time=time.time_ns())
            self.messages += 1

    def _on_sample(self, sample: zenoh.Sample) -> None:
        key = str(sample.key_expr)
        if (schema := schema_file(self.namespace, key)) is None:
            self.skipped += 1  # not the contract's: the service's wake-ups, strangers
            return
        if sample.kind == zenoh.SampleKind.DELETE:
            self.deletes += 1
            self._log(DELETES, DELETES, json.dumps({"key": key}).encode())
            return
        self.inputs += schema == "pose.schema.json"
        self._log(key, schema, sample.payload.to_bytes())

    def _ask_status(self) -> None:
        """The status of each service in the namespace, once a second."""
        while not self._stop.wait(STATUS_EVERY_S):
            try:
                statuses = ask(self.session, self.namespace, "*", STATUS_EVERY_S * 0.8)
            except (zenoh.ZError, ValueError):
                continue
            for status in statuses:
                key = keys.status_key(self.namespace, status.instance)
                self._log(key, "status.schema.json", status.model_dump_json().encode())

    def close(self) -> tuple[int, int]:
        """Stop and finish the file: ``(messages, topics)``."""
        self._subscriber.undeclare()
        self._stop.set()
        self._status.join(STATUS_EVERY_S * 2)
        with self._lock:
            self._writer.close()
            return self.messages, len(self._channels)
