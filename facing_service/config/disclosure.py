"""What of the configuration may leave the process: an allow-list, never a deny-list.

The status queryable is readable by every consumer, and logs end up in places with wide
read access, yet zenoh settings carry secrets: passwords (``transport/auth/usrpwd``),
inline TLS keys (``..._base64`` keys, or an endpoint's ``#`` config part), key file paths.
A deny-list would leak the next secret zenoh adds, so only what is listed here is shown;
everything else is replaced by ``REDACTED`` (its name stays, so an operator still sees that
it is set).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import Any

REDACTED = "<redacted>"

#: Settings fields shown as they are: none of them can hold a credential.
PUBLIC_FIELDS = frozenset(
    {
        "namespace",
        "base_frame",
        "threshold_deg",
        "hysteresis_deg",
        "stale_after_s",
        "silent_after_s",
        "hold_silent_s",
        "max_payload_bytes",
        "max_bodies",
        "engagement",
        "rule_field_of_view_deg",
        "rule_max_distance_m",
        "rule_threshold",
        "rule_window_s",
        "rule_rate_hz",
        "engage_above",
        "disengage_below",
        "engagement_tau_s",
        "engage_dwell_s",
        "disengage_dwell_s",
        "engagement_period_s",
        "zones_m",
        "head_model",
        "head_memory_s",
        "head_cone",
        "head_threshold_deg",
        "head_facing_window_s",
        "head_falloff_deg",
        "head_engagement_tau_s",
        "head_dwell_s",
        "head_vote_deg",
        "head_vote_tau_s",
        "head_vote_share",
        "group_hold_s",
        "group_heading_s",
        "group_memory_s",
        "group_rate_hz",
        "group_max_people",
        "input",
        "ros_format",
        "ros_distro",
        "ros_max_message_bytes",
        "ros_max_frames",
        "ros_join_wait_s",
        "ros_domain_id",
        "ros_namespace",
        "output",
        "ros_node_name",
        "ros_engagement_rate_hz",
        "ros_intents",
        "instance",
        "log_level",
        "mode",
        "no_multicast_scouting",
        "reconnect_s",
        "exit_without_router",
    }
)
#: Fields that may hold secrets in part: shown through the functions below.
FILTERED_FIELDS = frozenset({"connect", "listen", "config", "cfg"})

#: Zenoh config keys (and everything below them) whose values are shown in ``--cfg``
#: entries: timing, scouting and routing knobs, never auth, TLS or endpoints.
PUBLIC_ZENOH_KEYS = (
    "mode",
    "scouting",
    "timestamping",
    "queries_default_timeout",
    "routing",
    "connect/timeout_ms",
    "connect/exit_on_failure",
    "connect/retry",
    "listen/timeout_ms",
    "listen/exit_on_failure",
    "listen/retry",
    "transport/link/tx",
    "transport/link/rx",
    "transport/unicast/lowlatency",
    "transport/unicast/max_links",
    "transport/unicast/max_sessions",
    "transport/unicast/open_timeout",
    "transport/unicast/accept_timeout",
    "transport/unicast/qos",
    "transport/multicast",
    "transport/shared_memory/enabled",
    "adminspace/enabled",
)


def is_public_zenoh_key(key: str) -> bool:
    """True when ``key`` is one of PUBLIC_ZENOH_KEYS or lies below one (whole chunks)."""
    key = key.strip().strip("/")
    return any(key == p or key.startswith(p + "/") for p in PUBLIC_ZENOH_KEYS)


def public_endpoint(endpoint: str) -> str:
    """An endpoint without its ``#`` config part, where zenoh takes inline TLS keys."""
    locator, sep, _config = endpoint.partition("#")
    return f"{locator}#{REDACTED}" if sep else locator


def public_endpoints(endpoints: Iterable[str]) -> str:
    """Endpoints as a message lists them: comma-separated, each without its config part
    ("" for none)."""
    return ", ".join(public_endpoint(e) for e in endpoints)


def public_cfg_entry(entry: str) -> str:
    """A ``--cfg KEY:VALUE`` entry with its value shown only for a public key."""
    key, sep, value = entry.partition(":")
    if not sep:  # not KEY:VALUE at all: nothing in it is known to be a key
        return REDACTED
    return f"{key}:{value if is_public_zenoh_key(key) else REDACTED}"


def public_settings(values: dict[str, Any]) -> dict[str, Any]:
    """The settings (as ``Settings.model_dump(mode="json")``) as they may be shown.

    The zenoh config file's path is shown (it says where to look, and reading it needs
    access to the host); its contents never are: only zenoh reads it.
    """
    shown = {name: values[name] for name in sorted(PUBLIC_FIELDS) if name in values}
    shown["connect"] = [public_endpoint(e) for e in values.get("connect", [])]
    shown["listen"] = [public_endpoint(e) for e in values.get("listen", [])]
    shown["config"] = values.get("config")
    shown["cfg"] = [public_cfg_entry(e) for e in values.get("cfg", [])]
    return shown


def public_value(field: str, value: Any) -> str:
    """A user-given value as an error message may quote it."""
    if field in PUBLIC_FIELDS or field == "config":
        return repr(value)
    if field in ("connect", "listen"):
        items = value if isinstance(value, list) else [value]
        return repr([public_endpoint(str(v)) for v in items])
    if field == "cfg":
        items = value if isinstance(value, list) else [value]
        return repr([public_cfg_entry(str(v)) for v in items])
    return REDACTED


def public_zenoh_error(error: Exception) -> str:
    """A zenoh error (e.g. "Unable to connect to any of [...]") as it may be shown:
    without the paths of the Rust sources that raised it (wherever they stand: a port in
    use carries one inside its brackets), endpoints without their ``#`` config part."""
    text = re.sub(r"\s+at /\S+?\.rs:\d+\.?", "", str(error).strip()).strip()
    return re.sub(r"#[^\s\])(,]*", "#" + REDACTED, text)


def zenoh_failure(command: str, error: Exception) -> str:
    """The one line a command prints when zenoh refuses it: what zenoh said, without
    secrets, and the flag to look at when it could not connect."""
    text = public_zenoh_error(error)
    if text.startswith("Unable to connect"):
        text += " (--connect: is a router listening there, and reachable from here?)"
    elif "Address already in use" in text:
        text += " (--listen: another process listens there: pick another port, or stop it)"
    return f"facing-service {command}: cannot open the zenoh session: {text}"
