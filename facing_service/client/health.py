"""``facing-service health``: is a service answering, as a container's health check asks.

A session just opened has not discovered anybody yet, a peer especially: a query sent at
once reaches nobody, and a running service would be reported absent (seen in 5 of 20
tries). So the check first waits, up to its time-out, for a matching service's liveliness
token, then asks for the status until an answer or the time-out.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import zenoh

from ..config.disclosure import public_endpoints, zenoh_failure
from ..config.patience import open_interruptibly
from ..config.session import probe_config, probe_endpoints
from ..config.settings import Settings
from ..config.sources import env_name, load_settings
from ..contract import keys
from ..contract.errors import SettingsError
from ..contract.schemas import INPUT_BROKEN, ServiceStatus
from ..contract.words import counted


def statuses(
    session: zenoh.Session, namespace: str, instance: str, timeout: float
) -> tuple[list[ServiceStatus], bool]:
    """The status of every service matching ``instance`` (``*``: any) that answers within
    ``timeout`` seconds (empty when none does), and whether any such service was seen
    alive (its liveliness token) at all."""
    deadline = time.monotonic() + timeout
    token = keys.service_token(namespace, instance)
    alive = False
    while (left := deadline - time.monotonic()) > 0:
        replies = session.liveliness().get(token, timeout=min(0.25, left))
        if any(reply.ok is not None for reply in replies):
            alive = True
            answers = ask(session, namespace, instance, max(deadline - time.monotonic(), 0.1))
            if answers:
                return answers, alive
        time.sleep(min(0.05, max(deadline - time.monotonic(), 0)))
    return [], alive


def wait_for_service(
    session: zenoh.Session, namespace: str, timeout: float, seen: Callable[[str], None]
) -> bool:
    """Wait (up to ``timeout``) until a service's liveliness token is visible in
    ``namespace``, telling ``seen`` each instance found. A session just opened may not be
    connected yet, and a service declares its token after its queryables: once the token
    is seen, a query reaches them."""
    token = keys.service_token(namespace, "*")
    deadline = time.monotonic() + timeout
    while True:
        found = False
        for reply in session.liveliness().get(token, timeout=0.2):
            if reply.ok is not None:
                seen(keys.instance_of(str(reply.ok.key_expr)))
                found = True
        if found:
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.05)


def namespaces_with_service(session: zenoh.Session, timeout: float = 0.5) -> list[str]:
    """The namespaces in which some facing service's liveliness token is seen now: what a
    check that found none in its own namespace can suggest."""
    found = set()
    for reply in session.liveliness().get(keys.service_token("**", "*"), timeout=timeout):
        if reply.ok is not None:
            found.add(str(reply.ok.key_expr).rsplit("/services/facing/", 1)[0])
    return sorted(found)


def no_service_seen(session: zenoh.Session, namespace: str, where: Sequence[str]) -> str:
    """Why a session saw no facing service in ``namespace``, in one line: nothing reached
    at all (no router or peer), or no service in that namespace (and those that have one):
    a wrong namespace was once blamed on the router."""
    at = f" at {public_endpoints(where)}" if where else ""
    info = session.info
    if not list(info.routers_zid()) and not list(info.peers_zid()):
        return f"nothing answers{at}: no router or peer reached (is one listening there?)"
    others = [n for n in namespaces_with_service(session) if n != namespace]
    return f"no facing service in namespace {namespace!r}{at}" + (
        f" (namespaces with one: {', '.join(others)})" if others else ""
    )


def ask(
    session: zenoh.Session, namespace: str, instance: str, timeout: float
) -> list[ServiceStatus]:
    """One status query: the answers that came within ``timeout``."""
    return [
        ServiceStatus.model_validate_json(reply.ok.payload.to_bytes())
        for reply in session.get(keys.status_key(namespace, instance), timeout=timeout)
        if reply.ok is not None
    ]


def instances_seen(session: zenoh.Session, namespace: str, timeout: float = 0.5) -> list[str]:
    """The instances whose liveliness token is seen in ``namespace`` now."""
    replies = session.liveliness().get(keys.service_token(namespace, "*"), timeout=timeout)
    return sorted({keys.instance_of(str(r.ok.key_expr)) for r in replies if r.ok is not None})


def _why_no_answer(
    settings: Settings,
    instance: str,
    timeout: float,
    alive: bool,
    identity: str | None,
    others: Sequence[str] = (),
) -> str:
    """The usual cause first (no service at all, or none of that --instance: those there
    are named), then the others: one alive that did not answer, or access control hiding
    it from this identity."""
    if not alive and instance != "*" and others:
        return (
            f"no facing service of instance {instance!r} {reached(settings)} in namespace "
            f"'{settings.namespace}'; instances there: {', '.join(others)} (--instance, or "
            "FACING_INSTANCE, names one of them; none: any)"
        )
    acl = (
        ""
        if identity
        else f"; under access control, give the check an identity allowed to "
        f"{'query' if alive else 'see and query'} it: {HEALTH_CONFIG_ENV} or --health-config"
    )
    if not alive:
        return (
            f"no facing service found: no liveliness token on "
            f"{keys.service_token(settings.namespace, instance)} {reached(settings)} in "
            f"{timeout:g} s (is one running, in namespace '{settings.namespace}'?{acl}); "
            + _flags_to_try(settings)
        )
    selector = keys.status_key(settings.namespace, instance)
    return f"a facing service is alive, but no answer on {selector}{acl}"


def reached(settings: Settings) -> str:
    """How the check looks for services: at the endpoints it connects to, or by scouting
    (then it finds whichever service is around, not necessarily the one meant)."""
    endpoints = probe_endpoints(settings)
    if endpoints:
        return "at " + public_endpoints(endpoints)
    return "found by multicast scouting"


def _flags_to_try(settings: Settings) -> str:
    """The flags that reach a service, for a check that found none."""
    if probe_endpoints(settings):
        return (
            "a service behind a router: -m client -e tcp/<router>:7447; another namespace: "
            "--namespace"
        )
    return (
        "give its endpoint: -e tcp/<host>:<port> --no-multicast-scouting (a service run "
        "with -l), or -m client -e tcp/<router>:7447 --no-multicast-scouting (one behind "
        "a router)"
    )


def summary(status: ServiceStatus, reach: str) -> str:
    """One line of a service's status: what an operator reads (``--json`` for all), with
    which instance answered and how it was reached (a plain check found some
    other service on the host by scouting, and said only "ok")."""
    frames = ", ".join(f"{n} in {f}" for f, n in sorted(status.bodies_tracked.items()))
    listens = ", ".join(map(str, status.config.get("listen") or []))
    line = (
        f"{status.status}: instance {status.instance} (facing-service {status.version}) "
        f"{reach}" + (f", listening on {listens}" if listens else "") + ", up "
        f"{status.uptime_s:.0f} s, {counted(status.bodies_tracked_total, 'body', 'bodies')} "
        "tracked"
        + (f" ({frames})" if frames else "")
        + f", {counted(sum(status.rejected.values()), 'sample', 'samples')} refused"
    )
    if other := status.rejected.get("other_frame"):
        line += (f" ({other} in another frame than the service's --base-frame: misspelt? "
                 "its log names the frames)")  # fmt: skip
    if status.outage_s is not None:
        line += f", no router or peer for {status.outage_s:.1f} s"
    if (heard := status.input) is not None and heard.silent:
        line += (f", its input silent for {heard.last_heard_s or 0:.1f} s "
                 f"({counted(heard.held, 'person', 'people')} held)")  # fmt: skip
    if status.ros2 is not None and status.ros2.findings:
        line += f"; findings: {', '.join(sorted(status.ros2.findings))}"
    return line


def input_broken(status: ServiceStatus) -> str | None:
    """Why a service's input gives no results now (its input silent, or a ROS 2 finding
    that nothing can be read or looked up), or None: what ``--require-input`` fails on."""
    if (heard := status.input) is not None and heard.silent:
        return "its input is silent"
    broken = broken_findings(status)
    return f"its ROS 2 input: {', '.join(broken)}" if broken else None


def broken_findings(status: ServiceStatus) -> list[str]:
    """The ROS 2 findings that leave nobody's results (``INPUT_BROKEN``), sorted."""
    return sorted(set(status.ros2.findings) & INPUT_BROKEN) if status.ros2 else []


#: A zenoh config file for the health check's own identity (``--health-config``).
HEALTH_CONFIG_ENV = "FACING_HEALTH_CONFIG"


def check(
    flags: Mapping[str, Any],
    environ: Mapping[str, str],
    instance: str | None,
    health_config: str | None,
    timeout: float,
    as_json: bool = False,
    require_input: bool = False,
) -> int:
    """``facing-service health``: print every answering service's status; the exit code
    (0: one is ok, and with ``require_input`` hears its input; 1: none does; 2: a bad
    setting). With its own identity
    (``health_config``), the service's config file and ``--cfg`` (its credentials) stay
    out of the check's session."""
    instance = instance or environ.get(env_name("instance")) or "*"
    flags, environ = {**flags, "instance": None}, dict(environ)
    identity = health_config or environ.get(HEALTH_CONFIG_ENV) or None
    if identity:  # its own identity: the service's file and --cfg (credentials) stay out
        flags |= {"config": Path(identity), "cfg": None}
        environ.pop(env_name("config"), None)
        environ.pop(env_name("cfg"), None)
    try:
        settings = load_settings(flags, environ)
        if instance != "*":
            keys.validate_name(instance, "instance")
        config = probe_config(settings, timeout)
    except (SettingsError, ValueError) as error:
        print(f"facing-service health: invalid setting: {error}", file=sys.stderr)
        return 2
    deadline = time.monotonic() + timeout  # the whole check, the session's opening too
    try:
        with open_interruptibly(lambda: zenoh.open(config)) as session:
            left = max(deadline - time.monotonic(), 0.1)
            answers, alive = statuses(session, settings.namespace, instance, left)
            others = [] if answers or alive else instances_seen(session, settings.namespace)
    except zenoh.ZError as error:
        print(zenoh_failure("health", error), file=sys.stderr)
        return 1
    for status in answers:
        print(status.model_dump_json() if as_json else summary(status, reached(settings)))
    if not answers:
        why = _why_no_answer(settings, instance, timeout, alive, identity, others)
        print(f"facing-service health: {why}", file=sys.stderr)
    healthy = [s for s in answers if s.status == "ok"]
    if require_input and healthy:
        working = [s for s in healthy if input_broken(s) is None]
        if not working:
            why = "; ".join(f"{s.instance}: {input_broken(s)}" for s in healthy)
            print(f"facing-service health: --require-input: {why}", file=sys.stderr)
        healthy = working
    return 0 if healthy else 1
