"""A Foxglove WebSocket client written from the protocol's specification
(foxglove/ws-protocol, docs/spec.md at tag releases/typescript/ws-protocol/v0.8.0,
subprotocol ``foxglove.websocket.v1``), not from the SDK, offering as the Foxglove app
does the SDK's name for the same protocol too (``foxglove.sdk.v1``:
foxglove/foxglove-sdk, rust/foxglove/src/websocket/handshake.rs at tag sdk/v0.26.0,
whose messages cite that spec), which the SDK's server requires: it reads the server's
``advertise``, subscribes to a topic, and decodes each binary Message Data frame (opcode
0x01, u32 subscription id, u64 timestamp, little-endian, then the payload) with
Google's protobuf runtime from the schema the channel advertised (a base64
FileDescriptorSet), or as JSON for a JSON channel."""

from __future__ import annotations

import asyncio
import base64
import json
import struct
import time
from collections.abc import Callable
from typing import Any

import aiohttp
from google.protobuf import descriptor_pb2, descriptor_pool, json_format, message_factory

SUBPROTOCOLS = ("foxglove.sdk.v1", "foxglove.websocket.v1")


def _decoder(channel: dict[str, Any]) -> Callable[[bytes], Any]:
    if channel["encoding"] == "json":
        return lambda payload: json.loads(payload)
    assert channel["encoding"] == "protobuf", channel
    files = descriptor_pb2.FileDescriptorSet.FromString(base64.b64decode(channel["schema"]))
    pool = descriptor_pool.DescriptorPool()
    for file in files.file:
        pool.Add(file)
    kind = message_factory.GetMessageClass(pool.FindMessageTypeByName(channel["schemaName"]))
    return lambda payload: json_format.MessageToDict(
        kind.FromString(payload), preserving_proto_field_name=True
    )


async def _watch(url: str, topic: str, done: Callable[[list[Any]], bool], timeout: float,
                 ) -> tuple[list[tuple[float, Any]], dict[str, Any]]:  # fmt: skip
    seen: list[tuple[float, Any]] = []
    deadline = time.monotonic() + timeout
    async with aiohttp.ClientSession() as http, http.ws_connect(url, protocols=SUBPROTOCOLS) as ws:
        assert ws.protocol in SUBPROTOCOLS, ws.protocol
        channel, decode = None, None
        while time.monotonic() < deadline:
            try:
                frame = await ws.receive(timeout=max(deadline - time.monotonic(), 0.01))
            except asyncio.TimeoutError:
                break
            if frame.type == aiohttp.WSMsgType.TEXT:
                message = json.loads(frame.data)
                if message["op"] == "advertise" and channel is None:
                    for advertised in message["channels"]:
                        if advertised["topic"] == topic:
                            channel, decode = advertised, _decoder(advertised)
                            subscribe = {"id": 1, "channelId": advertised["id"]}
                            await ws.send_json({"op": "subscribe",
                                                    "subscriptions": [subscribe]})  # fmt: skip
            elif frame.type == aiohttp.WSMsgType.BINARY and frame.data[0] == 0x01:
                sub, _stamp = struct.unpack_from("<IQ", frame.data, 1)
                assert sub == 1 and decode is not None
                seen.append((time.monotonic(), decode(frame.data[13:])))
                if done([m for _, m in seen]):
                    break
            elif frame.type in (aiohttp.WSMsgType.CLOSED, aiohttp.WSMsgType.ERROR):
                break
    assert channel is not None, f"no channel {topic} was advertised"
    return seen, channel


def watch(url: str, topic: str, done: Callable[[list[Any]], bool], timeout: float = 10.0,
          ) -> tuple[list[tuple[float, Any]], dict[str, Any]]:  # fmt: skip
    """Messages of ``topic`` (monotonic time received, decoded) until ``done(messages)``
    or ``timeout``; and the channel as advertised."""
    return asyncio.run(_watch(url, topic, done, timeout))
