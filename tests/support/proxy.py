"""A TCP proxy on loopback that can stop forwarding without closing anything: a network
partition (a cable pulled, a Wi-Fi dropout) as a link sees it, with no FIN or RST; and
forward again (a stall: TCP then delivers what waited), or reset every connection and
refuse new ones for a while (a link cut)."""

from __future__ import annotations

import contextlib
import select
import socket
import struct
import threading
import time


class Proxy:
    """Forwards ``<host>:<port>`` to ``<host>:<target>`` until ``cut()``; ``_pump`` moves
    one connection's bytes both ways (a subclass may move them otherwise)."""

    def __init__(self, target: int, host: str = "127.0.0.1") -> None:
        self.target, self.host = target, host
        self._listener = socket.create_server((host, 0))
        self.port = self._listener.getsockname()[1]
        self._forwarding = threading.Event()
        self._forwarding.set()
        self._closed = threading.Event()
        self._sockets: list[socket.socket] = []
        self._refused_until = 0.0
        self._thread = threading.Thread(target=self._accept, daemon=True)
        self._thread.start()

    def cut(self) -> None:
        """Stop forwarding; both sides keep their connection open and hear nothing."""
        self._forwarding.clear()

    def resume(self) -> None:
        """Forward again: what waited in the connections (the backlog) goes through."""
        self._forwarding.set()

    def reset(self, refuse_s: float) -> None:
        """Every connection reset (RST, as a dropped Wi-Fi association ends them), and new
        ones refused for ``refuse_s``."""
        self._refused_until = time.monotonic() + refuse_s
        sockets, self._sockets = self._sockets, []
        for s in sockets:
            _reset(s)

    def close(self) -> None:
        self._closed.set()
        self._listener.close()
        for s in self._sockets:
            s.close()
        self._thread.join(timeout=2)

    def _accept(self) -> None:
        while not self._closed.is_set():
            try:
                client, _ = self._listener.accept()
            except OSError:
                return
            if time.monotonic() < self._refused_until:  # the link is down: refused
                _reset(client)
                continue
            try:
                upstream = socket.create_connection((self.host, self.target))
            except OSError:  # nothing listens there (yet): the link is refused
                _reset(client)
                continue
            self._sockets += [client, upstream]
            threading.Thread(target=self._pump, args=(client, upstream), daemon=True).start()

    def _pump(self, a: socket.socket, b: socket.socket) -> None:
        peers = {a: b, b: a}
        while not self._closed.is_set():
            try:
                ready, _, _ = select.select([a, b], [], [], 0.1)
                if not self._forwarding.is_set():
                    continue  # partitioned: read nothing, send nothing, close nothing
                for s in ready:
                    data = s.recv(65536)
                    if not data:
                        return
                    peers[s].sendall(data)
            except OSError:
                return


def _reset(s: socket.socket) -> None:
    """Close with an RST, not a FIN: the peer learns at once that the link is gone."""
    with contextlib.suppress(OSError):
        s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    s.close()
