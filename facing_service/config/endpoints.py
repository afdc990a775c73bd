"""Zenoh endpoints checked before zenoh tries them: zenoh only finds a bad one out when it
connects, and a peer then retries forever in silence."""

from __future__ import annotations

#: zenoh's link protocols; those of them that take ``host:port``.
_PROTOCOLS = {"tcp", "udp", "tls", "quic", "ws", "unixsock-stream", "unixpipe", "serial", "vsock"}
_HOST_PORT = {"tcp", "udp", "tls", "quic", "ws"}


def endpoint_problem(endpoint: str, *, listen: bool = False) -> str | None:
    """Why zenoh could never use ``endpoint`` (zenoh itself only finds out when it tries,
    and a peer then retries forever in silence), or None."""
    locator = endpoint.split("#", 1)[0].split("?", 1)[0]
    protocol, sep, address = locator.partition("/")
    if not sep or protocol not in _PROTOCOLS:
        hint = f" (tcp/{endpoint}?)" if not sep and ":" in endpoint else ""
        return f"not <protocol>/<address>{hint}, protocol one of {', '.join(sorted(_PROTOCOLS))}"
    if protocol not in _HOST_PORT:
        return None if address else "no address"
    host, colon, port = address.rpartition(":")
    if not colon or not host or not port.isdigit():
        return "not <protocol>/<host>:<port>"
    if not (0 if listen else 1) <= int(port) <= 65535:
        return f"port {port} out of range"
    if host.startswith("[") != host.endswith("]"):
        return "an IPv6 address goes in [brackets]"
    return None
