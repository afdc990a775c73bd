"""A lossy, jittery link between a tracker and the service, made by the test itself.

A network namespace joined to the host by a veth pair: what runs in the namespace (``ip
netns exec``) reaches the host only across the pair. Loss: tc netem where the kernel has
it; else nftables in the namespace, dropping packets at random (the same loss at the IP
level: TCP retransmits, as over a bad Wi-Fi). Either way each direction loses that share.
Jitter: netem's delay where it exists; else a forwarding proxy on the host side that
holds each chunk a random 0-50 ms, in order (the delay variation the service sees; it
is not in the pair's round trip, so TCP's own pace is not slowed by it, which netem's
would be: see docs/operations.md).

Root and iproute2 are needed; ``unavailable()`` says why a machine cannot make one.
"""

from __future__ import annotations

import os
import random
import re
import socket
import subprocess
import threading
import time
from collections import deque

from proxy import Proxy
from system_packages import require

NFT_LOSS = """table inet lossy {{
  chain input {{ type filter hook input priority 0;
    numgen random mod 1000 < {per_mille} counter drop; }}
  chain output {{ type filter hook output priority 0;
    numgen random mod 1000 < {per_mille} counter drop; }}
}}"""


def _run(*cmd: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(cmd, capture_output=True, text=True, check=False)


def unavailable() -> str | None:
    """Why this machine cannot make the link (None: it can)."""
    if os.geteuid() != 0:
        return "making a network namespace needs root"
    require("iproute2")
    require("nftables")
    return None


class JitterProxy(Proxy):
    """A ``Proxy`` that holds each chunk a random 0..``jitter_s`` s, never letting one
    overtake another (a TCP stream stays in order); cut, it reads nothing until resumed
    (a stall), and reset, its connections end (a cut link)."""

    def __init__(self, target: int, host: str, jitter_s: float, seed: int = 45) -> None:
        self._jitter, self._rng = jitter_s, random.Random(seed)  # before connections come
        super().__init__(target, host)

    def _pump(self, a: socket.socket, b: socket.socket) -> None:
        for source, sink in ((a, b), (b, a)):
            threading.Thread(target=self._delayed, args=(source, sink), daemon=True).start()

    def _delayed(self, source: socket.socket, sink: socket.socket) -> None:
        held: deque[tuple[float, bytes]] = deque()
        more = threading.Condition()
        last_release = 0.0

        def release() -> None:
            while not self._closed.is_set():
                with more:
                    while not held and not self._closed.is_set():
                        more.wait(0.1)
                    if not held:
                        return
                    at, chunk = held[0]
                wait = at - time.monotonic()
                if wait > 0:
                    time.sleep(wait)
                with more:
                    held.popleft()
                try:
                    sink.sendall(chunk)
                except OSError:
                    return

        threading.Thread(target=release, daemon=True).start()
        while not self._closed.is_set():
            if not self._forwarding.wait(0.1):
                continue  # stalled: nothing read, the sender's backlog waits in TCP
            try:
                chunk = source.recv(65536)
            except OSError:
                return
            if not chunk:
                return
            at = max(last_release, time.monotonic() + self._rng.uniform(0, self._jitter))
            last_release = at
            with more:
                held.append((at, chunk))
                more.notify()


class LossyLink:
    """``with LossyLink(loss_pct, jitter_s) as link``: ``link.host`` is the host's address
    on the pair, ``link.run_inside(...)`` runs a command in the namespace, ``link.how``
    says how loss and jitter are made."""

    def __init__(self, loss_pct: float, jitter_s: float) -> None:
        n = os.getpid() % 200 + 20
        self.ns, self._host_if, self._ns_if = f"fslossy{n}", f"fsl{n}a", f"fsl{n}b"
        self.host, self.inside = f"10.213.{n}.1", f"10.213.{n}.2"
        self.loss_pct, self.jitter_s = loss_pct, jitter_s
        self.netem = False
        self.how = ""

    def __enter__(self) -> LossyLink:
        self._cleanup()
        steps = [
            ("ip", "netns", "add", self.ns),
            ("ip", "link", "add", self._host_if, "type", "veth", "peer", "name", self._ns_if),
            ("ip", "link", "set", self._ns_if, "netns", self.ns),
            ("ip", "addr", "add", f"{self.host}/24", "dev", self._host_if),
            ("ip", "link", "set", self._host_if, "up"),
            *(("ip", "netns", "exec", self.ns, *c) for c in (
                ("ip", "addr", "add", f"{self.inside}/24", "dev", self._ns_if),
                ("ip", "link", "set", self._ns_if, "up"),
                ("ip", "link", "set", "lo", "up"),
            )),
        ]  # fmt: skip
        for step in steps:
            if (done := _run(*step)).returncode != 0:
                self._cleanup()
                raise OSError(f"{' '.join(step)}: {done.stderr.strip()}")
        half_ms = self.jitter_s * 1000 / 2
        netem = ("netem", "delay", f"{half_ms:.0f}ms", f"{half_ms:.0f}ms",
                 "loss", f"{self.loss_pct:g}%")  # fmt: skip
        on_host = _run("tc", "qdisc", "add", "dev", self._host_if, "root", *netem)
        if on_host.returncode == 0:
            _run("ip", "netns", "exec", self.ns, "tc", "qdisc", "add", "dev", self._ns_if,
                 "root", *netem)  # fmt: skip
            self.netem = True
            self.how = f"netem: {self.loss_pct}% loss and {self.jitter_s * 1000:.0f} ms jitter"
            return self
        nft = NFT_LOSS.format(per_mille=round(self.loss_pct * 10))
        loaded = subprocess.run(["ip", "netns", "exec", self.ns, "nft", "-f", "-"], input=nft,
                                capture_output=True, text=True, check=False)  # fmt: skip
        if loaded.returncode != 0:
            self._cleanup()
            raise OSError(f"nft in the namespace: {loaded.stderr.strip()}")
        self.how = (
            f"no netem in this kernel ({on_host.stderr.strip()}): {self.loss_pct}% packet "
            f"loss each way by nftables, {self.jitter_s * 1000:.0f} ms jitter by a proxy"
        )
        return self

    def dropped(self) -> int:
        """Packets the nftables rules dropped so far (0 with netem: it keeps no count here)."""
        listed = _run("ip", "netns", "exec", self.ns, "nft", "list", "table", "inet", "lossy")
        return sum(int(n) for n in re.findall(r"counter packets (\d+)", listed.stdout))

    def run_inside(self, *cmd: str, **kw: object) -> subprocess.Popen[str]:
        return subprocess.Popen(["ip", "netns", "exec", self.ns, *cmd], text=True, **kw)  # type: ignore[call-overload]

    def _cleanup(self) -> None:
        _run("ip", "netns", "del", self.ns)
        _run("ip", "link", "del", self._host_if)

    def __exit__(self, *_: object) -> None:
        self._cleanup()


def pose_of(body: int, tick: int) -> tuple[float, float, float]:
    """(x, y, yaw in degrees) of body ``body`` at ``tick``: the tracker in the namespace
    and the test's expectation compute the same poses."""
    rng = random.Random(body * 100_003 + tick)
    return rng.uniform(0.5, 5.0), rng.uniform(-3.0, 3.0), rng.uniform(-180.0, 180.0)


#: The tracker the namespace runs: ``python -c TRACKER <endpoint> <bodies> <hz> <seconds>``
#: (with this folder on its path); prints how many poses it sent and how long it took.
TRACKER = """
import json, sys, time
import zenoh
from facing_service.contract.poses import pose_dict, yaw_rotation
from facing_service.contract.stamps import Time
from lossy_link import pose_of
ep, bodies, hz, seconds = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
conf = zenoh.Config()
conf.insert_json5("mode", '"peer"')
conf.insert_json5("scouting/multicast/enabled", "false")
conf.insert_json5("connect/endpoints", json.dumps([ep]))
with zenoh.open(conf) as session:
    publishers = [session.declare_publisher(f"hri/bodies/b{i}/pose/cam",
                  congestion_control=zenoh.CongestionControl.BLOCK) for i in range(bodies)]
    time.sleep(1.0)  # the service's subscription reaches this session
    start, sent = time.monotonic(), 0
    for tick in range(int(hz * seconds)):
        for i, publisher in enumerate(publishers):
            x, y, yaw = pose_of(i, tick)
            publisher.put(json.dumps(pose_dict(f"b{i}", "cam", Time.of(1 + tick), (x, y, 0.0),
                                               yaw_rotation(yaw))).encode())
            sent += 1
        time.sleep(max(0.0, start + (tick + 1) / hz - time.monotonic()))
    print(sent, round(time.monotonic() - start, 3), flush=True)
    time.sleep(3.0)  # what is in flight is delivered before the session closes
    for publisher in publishers:
        publisher.undeclare()
"""
