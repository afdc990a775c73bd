"""The zenoh session a service's settings make, configured exactly like zenoh's own example
programs (``-m -e -l -c --no-multicast-scouting --cfg``): the ``--config`` file first, then
the flags over it, then each ``--cfg KEY:VALUE``; every endpoint checked before zenoh sees
it, and zenoh's own errors said in one line.
"""

from __future__ import annotations

import json
import os
import re
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

import zenoh

from ..contract.errors import SettingsError
from .disclosure import public_cfg_entry, zenoh_failure

if TYPE_CHECKING:
    from .settings import Settings


class SessionFlags(Protocol):
    """What a zenoh session is made from: the service's ``Settings`` and a client's
    ``ClientOptions`` both carry these (each names them its own way in errors)."""

    @property
    def mode(self) -> str | None: ...
    @property
    def connect(self) -> Sequence[str]: ...
    @property
    def listen(self) -> Sequence[str]: ...
    @property
    def config(self) -> Path | None: ...
    @property
    def no_multicast_scouting(self) -> bool: ...
    @property
    def reconnect_s(self) -> Sequence[float]: ...
    @property
    def cfg(self) -> Sequence[str]: ...


def as_flag(field: str) -> str:
    """How the command line names a session field (``--no-multicast-scouting``)."""
    return "--" + field.replace("_", "-")


def _loopback(endpoint: str) -> str:
    """The address a process on the same host reaches a wildcard listener at."""
    return endpoint.replace("/0.0.0.0:", "/127.0.0.1:").replace("/[::]:", "/[::1]:")


def probe_endpoints(settings: Settings) -> list[str]:
    """Where a helper session beside a service connects: the service's connect endpoints,
    else its listen endpoints on loopback (none: it finds services by scouting)."""
    return list(settings.connect) or [_loopback(e) for e in settings.listen]


def probe_config(settings: Settings, timeout_s: float) -> zenoh.Config:
    """Zenoh config of a short-lived helper session (``health``) beside a running service,
    configured from the same flags and ``FACING_*`` variables as the service.

    It must not take the service's ports, so it listens nowhere (even if the config file
    says otherwise); when the service is only configured to listen, the helper connects to
    those endpoints on loopback. It is one shot: it waits for its endpoints no longer than
    ``timeout_s``, whatever the service's own settings say (a service beside a robot waits
    for its router for ever, ``connect/timeout_ms: -1``: the check then hung with it).
    """
    connect = probe_endpoints(settings)
    # A router's mode would make the helper listen; otherwise the configured mode holds
    # (the config file's, when no flag gives one: a client stays a client).
    mode = "client" if connect else (None if settings.mode == "router" else settings.mode)
    helper = settings.model_copy(update={"listen": [], "connect": connect, "mode": mode})
    conf = zenoh_config(helper)
    conf.insert_json5("listen/endpoints", "[]")
    conf.insert_json5("connect/timeout_ms", json.dumps(max(1, round(timeout_s * 1000))))
    conf.insert_json5("connect/exit_on_failure", "true")
    return conf


def effective_session(settings: Settings, conf: zenoh.Config) -> dict[str, Any]:
    """The session settings in force, whether a flag or the config file said them (the
    status shows these, not the flags' None and False defaults)."""
    scouting = json.loads(conf.get_json("scouting/multicast/enabled"))
    return {
        "mode": mode_and_endpoints(conf, "connect")[0],
        "no_multicast_scouting": settings.no_multicast_scouting or scouting is False,
    }


def mode_and_endpoints(conf: zenoh.Config, kind: str) -> tuple[str, list[str]]:
    """The session's mode (zenoh's default: peer) and its ``kind`` ("connect" or "listen")
    endpoints in force for that mode: zenoh keeps either a list or a map of lists per mode."""
    mode = json.loads(conf.get_json("mode")) or "peer"
    value = json.loads(conf.get_json(f"{kind}/endpoints"))
    if isinstance(value, dict):
        value = value.get(mode, [])
    return mode, [str(e) for e in value] if isinstance(value, list) else []


def zenoh_config(flags: SessionFlags, named: Callable[[str], str] = as_flag) -> zenoh.Config:
    """The zenoh session config; SettingsError on an unreadable file, unknown key or bad
    value, naming the flag (as ``named`` spells a field) and never echoing a secret value
    (zenoh's own messages quote the offending text, and the source file of zenoh's that
    raised them)."""
    conf = _config_file(flags.config, named("config")) if flags.config else zenoh.Config()
    if flags.mode is not None:
        insert(conf, "mode", json.dumps(flags.mode), named("mode"))
    if flags.connect:
        insert(conf, "connect/endpoints", json.dumps(list(flags.connect)), named("connect"))
    if flags.listen:
        insert(conf, "listen/endpoints", json.dumps(list(flags.listen)), named("listen"))
    if flags.no_multicast_scouting:
        insert(conf, "scouting/multicast/enabled", "false", named("no_multicast_scouting"))
    if json.loads(conf.get_json("connect/retry")) is None:  # the config file's wins
        first, most = flags.reconnect_s
        retry = {
            "period_init_ms": round(first * 1000),
            "period_max_ms": round(most * 1000),
            "period_increase_factor": 2,
        }
        insert(conf, "connect/retry", json.dumps(retry), named("reconnect_s"))
    for entry in flags.cfg:
        key, _, value = entry.partition(":")
        insert(conf, key, value, f"{named('cfg')} {public_cfg_entry(entry)}")
    return conf


def readable_file(path: Path, what: str) -> str | None:
    """Why ``path`` cannot be read as a file (``what`` names the option), or None."""
    if not path.exists():
        return f"{what} {str(path)!r}: no such file"
    if not path.is_file():
        return f"{what} {str(path)!r}: not a file"
    if not os.access(path, os.R_OK):
        return f"{what} {str(path)!r}: not readable (permission denied)"
    return None


def _config_file(path: Path, what: str) -> zenoh.Config:
    if problem := readable_file(path, what):
        raise SettingsError(problem)
    try:
        return zenoh.Config.from_file(str(path))
    except zenoh.ZError as error:
        raise SettingsError(f"{what} {str(path)!r}: {zenoh_error_reason(error)}") from None


def insert(conf: zenoh.Config, key: str, value: str, what: str) -> None:
    """One config entry; a refusal is a SettingsError naming ``what`` gave it."""
    try:
        conf.insert_json5(key, value)
    except zenoh.ZError as error:
        raise SettingsError(f"{what}: {zenoh_error_reason(error)}") from None


def zenoh_error_reason(error: zenoh.ZError) -> str:
    """Why zenoh refused a config, without the text it quotes (which may be a password)."""
    text = str(error)
    loc = re.search(r"(?:-->\s*|line: )(\d+)(?::|, column: )(\d+)", text)
    where = f" at line {loc[1]}, column {loc[2]}" if loc else ""
    if field := re.search(r"unknown field `([^`]*)`", text):
        return f"unknown key {field[1]!r}{where}"
    if "unknown key" in text:
        return "unknown zenoh config key"
    if choices := re.search(r"unknown variant `[^`]*`, (expected one of [^\"]*)", text):
        return f"invalid value{where}; {choices[1]}"
    if "-->" in text or "Json5Err" in text:
        return f"not valid JSON5{where}"
    if os_error := re.match(r"(.+?) \(os error \d+\)", text):
        return os_error[1]
    return f"invalid value{where}"


def waiting_for_router(settings: Settings) -> Settings:
    """``run``'s settings: in client mode, unless ``--exit-without-router`` or the config
    says otherwise (``connect/timeout_ms``), the session waits for its router to come up
    rather than failing at once: a robot's processes start in any order."""
    conf = zenoh_config(settings)
    mode, _ = mode_and_endpoints(conf, "connect")
    if (
        mode != "client"
        or settings.exit_without_router
        or json.loads(conf.get_json("connect/timeout_ms")) is not None
    ):
        return settings
    wait = ["connect/timeout_ms:-1", "connect/exit_on_failure:false"]
    return settings.model_copy(update={"cfg": [*wait, *settings.cfg]})


def opened(conf: zenoh.Config, command: str) -> zenoh.Session | None:
    """A session of ``conf``, or None after the one line saying why zenoh refused it."""
    try:
        return zenoh.open(conf)
    except zenoh.ZError as error:
        print(zenoh_failure(command, error), file=sys.stderr)
        return None
