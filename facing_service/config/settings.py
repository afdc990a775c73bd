"""Settings of the service: command-line flags, ``FACING_*`` environment variables, defaults.

Precedence: a flag beats its environment variable, which beats the default. The zenoh
session is configured exactly like zenoh's own example programs (``-m -e -l -c
--no-multicast-scouting --cfg``): the ``--config`` file first, then the flags over it,
then each ``--cfg KEY:VALUE``.
"""

from __future__ import annotations

import json
import os
import re
import socket
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any, Literal

import zenoh
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from ..contract import keys
from ..contract.schemas import DEFAULT_MAX_PAYLOAD_BYTES
from ..core.engagement import EngagementParams
from ..core.tf_buffer import DEFAULT_MAX_FRAMES
from ..core.tracker import Profile
from ..ros2.input import DEFAULT_MAX_MESSAGE_BYTES
from ..ros2.wire import Distro, RosFormat, Wire
from .disclosure import public_cfg_entry, public_endpoint, public_value

ENV_PREFIX = "FACING_"
#: In environment variables, list settings are comma-separated, except ``FACING_CFG``
#: whose JSON5 values may hold commas: its entries are separated by ``;``.
_LIST_SEPARATORS = {"connect": ",", "listen": ",", "cfg": ";", "zones_m": ","}

LogLevel = Literal["DEBUG", "INFO", "WARNING", "ERROR", "CRITICAL"]


def default_instance() -> str:
    """``<host name>-<pid>``, made a valid key chunk: unique per process on a network."""
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{socket.gethostname()}-{os.getpid()}")
    return name[-64:]


SERVICE, ENGAGEMENT, HEADS = "service", "engagement levels", "heads: face frames, from ROS 2 input"
ROS_IN = "ROS 2 input: a robot's own /tf and /humans/* topics"
ROS_OUT = "ROS 2 output: our results on the robot's own topics, beside the JSON keys"
ZENOH = "zenoh session"


def _flag(
    description: str,
    group: str = SERVICE,
    *,
    short: str | None = None,
    metavar: str | None = None,
    shown: str | None = None,
) -> dict[str, Any]:
    """A setting's flag: its help (the description), group, short form, metavar, and the
    default as the docs say it when the value itself would not (``shown``)."""
    extra = {"group": group, "short": short, "metavar": metavar, "shown": shown}
    return {"description": description, "json_schema_extra": extra}


class Settings(BaseModel):
    """Every setting of ``facing-service run``: the single source of the CLI's flags and
    help, the ``FACING_*`` variables and docs/configuration.md's table."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    namespace: str = Field("hri", **_flag("key prefix, one or more chunks"))
    base_frame: str = Field(
        keys.ALL_FRAMES,
        **_flag(
            "the base frame to serve, or `*` for every frame (with `--input ros2`, `*` means "
            "REP 105's `base_link`, libhri's reference frame)"
        ),
    )
    threshold_deg: float = Field(
        20.0, gt=0.0, lt=180.0, **_flag("half-angle of the facing cone, in (0, 180)")
    )
    hysteresis_deg: float = Field(
        5.0,
        ge=0.0,
        lt=180.0,
        **_flag(
            "extra angle a facing body may turn before it stops facing; `0` decides "
            "sample by sample"
        ),
    )
    stale_after_s: float = Field(
        2.0,
        gt=0.0,
        allow_inf_nan=False,
        **_flag("a body with no accepted pose for this long is lost"),
    )
    max_payload_bytes: int = Field(
        DEFAULT_MAX_PAYLOAD_BYTES, gt=0, **_flag("larger pose payloads are rejected")
    )
    max_bodies: int = Field(
        10_000,
        gt=0,
        **_flag("most bodies tracked over all frames; new ones beyond are rejected (`capacity`)"),
    )
    engage_above: float = Field(
        0.6, gt=0.0, le=1.0, **_flag("smoothed score at which a body starts ENGAGING", ENGAGEMENT)
    )
    disengage_below: float = Field(
        0.35,
        ge=0.0,
        lt=1.0,
        **_flag("smoothed score below which ENGAGED turns DISENGAGING", ENGAGEMENT),
    )
    engagement_tau_s: float = Field(
        0.25,
        gt=0.0,
        allow_inf_nan=False,
        **_flag("time constant of the smoothed score", ENGAGEMENT),
    )
    engage_dwell_s: float = Field(
        0.5,
        ge=0.0,
        allow_inf_nan=False,
        **_flag("ENGAGING must hold this long to become ENGAGED", ENGAGEMENT),
    )
    disengage_dwell_s: float = Field(
        0.6,
        ge=0.0,
        allow_inf_nan=False,
        **_flag("DISENGAGING must hold this long to become DISENGAGED", ENGAGEMENT),
    )
    engagement_period_s: float = Field(
        1.0,
        gt=0.0,
        allow_inf_nan=False,
        **_flag("an unchanged level is republished this often", ENGAGEMENT),
    )
    zones_m: list[float] = Field(
        [0.45, 1.2, 3.6],
        **_flag(
            "intimate, personal, social zone limits (public beyond)",
            ENGAGEMENT,
            metavar="INTIMATE,PERSONAL,SOCIAL",
        ),
    )
    # Heads (face frames, from ROS 2 input): chosen by cross-validation on the shared
    # recordings (benchmarks/crossval.py, docs/engagement.md).
    head_cone: Literal["3d", "planar"] = Field(
        "3d", **_flag("how a face's angle to the robot is measured: `3d` or `planar`", HEADS)
    )
    head_threshold_deg: float = Field(
        28.0,
        gt=0.0,
        lt=180.0,
        **_flag(
            "half-angle of a face's facing cone; a face starts ENGAGING at its edge",
            HEADS,
        ),
    )
    head_falloff_deg: float = Field(
        20.0,
        gt=0.0,
        lt=180.0,
        **_flag("a face's engagement score reaches 0 this far beyond its cone", HEADS),
    )
    head_engagement_tau_s: float = Field(
        2.0, gt=0.0, allow_inf_nan=False, **_flag("time constant of a face's smoothed score", HEADS)
    )
    head_dwell_s: float = Field(
        1.0,
        ge=0.0,
        allow_inf_nan=False,
        **_flag("a face's ENGAGING and DISENGAGING must hold this long", HEADS),
    )
    input: Literal["json", "ros2"] = Field(
        "json",
        **_flag(
            "`json` (our pose keys) or `ros2` (a robot's `/tf` and `/humans/*` topics)", ROS_IN
        ),
    )
    ros_format: Literal["rmw_zenoh", "bridge"] = Field(
        "rmw_zenoh", **_flag("`rmw_zenoh`, or `bridge` (zenoh-bridge-ros2dds)", ROS_IN)
    )
    ros_distro: Literal["auto", "humble", "jazzy"] = Field(
        "auto",
        **_flag(
            "rmw_zenoh's form to answer in: `auto` (learned from the robot's keys), `humble` "
            "(TypeHashNotSupported), `jazzy` (RIHS01 hashes: Jazzy, Kilted, Rolling)",
            ROS_IN,
        ),
    )
    ros_max_message_bytes: int = Field(
        DEFAULT_MAX_MESSAGE_BYTES,
        gt=0,
        **_flag(
            "a robot's message larger than this is refused undecoded (`payload_too_large`)",
            ROS_IN,
        ),
    )
    ros_max_frames: int = Field(
        DEFAULT_MAX_FRAMES,
        gt=0,
        **_flag(
            "most TF frames kept; frames silent for 10 s are forgotten to make room, and a "
            "transform naming one more is refused (`tf_too_many_frames`)",
            ROS_IN,
        ),
    )
    ros_domain_id: int = Field(
        0,
        ge=0,
        le=232,
        **_flag("`ROS_DOMAIN_ID`, 0-232 (rmw_zenoh keys start with it)", ROS_IN),
    )
    ros_namespace: str = Field(
        "", **_flag("ROS namespace (or the bridge's) prefixing every topic", ROS_IN)
    )
    output: Literal["json", "ros2"] = Field(
        "json",
        **_flag(
            "`ros2` also publishes on the robot's topics (engagement_status, facing lists)",
            ROS_OUT,
        ),
    )
    ros_node_name: str = Field(
        "facing_service",
        pattern=r"^[A-Za-z_][A-Za-z0-9_]*$",
        **_flag("our ROS node's name in the liveliness graph", ROS_OUT),
    )
    ros_engagement_rate_hz: float = Field(
        10.0, gt=0.0, le=1000.0, **_flag("engagement_status is republished this often", ROS_OUT)
    )
    ros_intents: bool = Field(
        False,
        **_flag("publish `ENGAGE_WITH` on `/intents` when a person becomes ENGAGED", ROS_OUT),
    )
    instance: str = Field(
        default_factory=default_instance,
        **_flag(
            "this service's name in `NS/services/facing/<instance>`", shown="<host name>-<pid>"
        ),
    )
    log_level: LogLevel = Field(
        "INFO", **_flag("`DEBUG`, `INFO`, `WARNING`, `ERROR` or `CRITICAL`")
    )
    # zenoh session; None means "as the config file says, else zenoh's default (peer)".
    mode: Literal["peer", "client", "router"] | None = Field(
        None,
        **_flag(
            "zenoh mode: `peer`, `client` or `router`",
            ZENOH,
            short="-m",
            shown="the config file's, else `peer`",
        ),
    )
    connect: list[str] = Field(
        [],
        **_flag(
            "endpoint to connect to, repeatable, e.g. `tcp/192.168.1.10:7447`",
            ZENOH,
            short="-e",
            metavar="ENDPOINT",
        ),
    )
    listen: list[str] = Field(
        [], **_flag("endpoint to listen on, repeatable", ZENOH, short="-l", metavar="ENDPOINT")
    )
    config: Path | None = Field(
        None,
        **_flag(
            "a zenoh JSON5 config file; the flags override it", ZENOH, short="-c", metavar="FILE"
        ),
    )
    no_multicast_scouting: bool = Field(False, **_flag("disable multicast discovery", ZENOH))
    cfg: list[str] = Field(
        [],
        **_flag(
            "any zenoh config key with a JSON5 value, repeatable, e.g. `--cfg "
            "'scouting/delay:0'`; applied last",
            ZENOH,
            metavar="KEY:VALUE",
        ),
    )

    @field_validator("namespace")
    @classmethod
    def _namespace(cls, value: str) -> str:
        return keys.validate_namespace(value)

    @field_validator("instance")
    @classmethod
    def _instance(cls, value: str) -> str:
        return keys.validate_name(value, "instance")

    @field_validator("base_frame")
    @classmethod
    def _base_frame(cls, value: str) -> str:
        return keys.validate_frame_filter(value)

    @field_validator("connect", "listen")
    @classmethod
    def _endpoints(cls, value: list[str], info: Any) -> list[str]:
        for endpoint in value:
            if reason := endpoint_problem(endpoint, listen=info.field_name == "listen"):
                raise ValueError(f"{public_endpoint(endpoint)}: {reason}")
        return value

    @field_validator("ros_namespace")
    @classmethod
    def _ros_namespace(cls, value: str) -> str:
        value = value.strip("/")
        if value and not all(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", c) for c in value.split("/")):
            raise ValueError("a ROS namespace is names of [A-Za-z0-9_] joined by '/'")
        return value

    @field_validator("log_level", mode="before")
    @classmethod
    def _log_level(cls, value: Any) -> Any:
        return value.upper() if isinstance(value, str) else value

    @field_validator("zones_m")
    @classmethod
    def _zones(cls, value: list[float]) -> list[float]:
        if len(value) != 3 or not 0 < value[0] < value[1] < value[2]:
            raise ValueError("zones_m is INTIMATE,PERSONAL,SOCIAL limits, increasing, > 0")
        return value

    @model_validator(mode="after")
    def _hysteresis(self) -> Settings:
        if self.disengage_below >= self.engage_above:
            raise ValueError("disengage_below must be below engage_above")
        return self

    @property
    def forced_distro(self) -> Distro | None:
        """``--ros-distro``, None when it is to be learned from the robot (``auto``)."""
        return None if self.ros_distro == "auto" else Distro(self.ros_distro)

    def ros_wire(self) -> Wire:
        """Where the robot's topics are on zenoh, and the form we write in before (or
        instead of) learning the robot's."""
        return Wire(
            RosFormat(self.ros_format),
            self.ros_domain_id,
            self.ros_namespace,
            self.forced_distro or Distro.JAZZY,
        )

    @property
    def ros_base_frame(self) -> str:
        """The frame ROS 2 input looks people up in: ``--base-frame``, or REP 105's
        ``base_link`` (libhri's default reference frame) when it is ``*``."""
        return "base_link" if self.base_frame == keys.ALL_FRAMES else self.base_frame

    def engagement_params(self) -> EngagementParams:
        intimate, personal, social = self.zones_m
        return EngagementParams(
            threshold_deg=self.threshold_deg,
            tau_s=self.engagement_tau_s,
            engage_above=self.engage_above,
            disengage_below=self.disengage_below,
            engage_dwell_s=self.engage_dwell_s,
            disengage_dwell_s=self.disengage_dwell_s,
            intimate_m=intimate,
            personal_m=personal,
            social_m=social,
        )

    def head_profile(self) -> Profile:
        """How face frames are decided (ROS 2 input): see docs/ros2.md's evaluation.

        One story for heads: a face is facing inside its cone (``head_threshold_deg``),
        and its engagement score crosses ``engage_above`` exactly at the cone's edge (the
        score's full plateau is ``(1 - engage_above) * head_falloff_deg`` inside it), so
        a face that can engage is a face that faces, and one facing within the hysteresis
        band is one that has not dropped below ``disengage_below``: a person ENGAGED is
        never "not facing" for long, nor facing without a score that engages."""
        plateau = self.head_threshold_deg - (1.0 - self.engage_above) * self.head_falloff_deg
        engagement = replace(
            self.engagement_params(),
            threshold_deg=max(0.0, plateau),
            falloff_deg=self.head_falloff_deg,
            tau_s=self.head_engagement_tau_s,
            engage_dwell_s=self.head_dwell_s,
            disengage_dwell_s=self.head_dwell_s,
        )
        return Profile(
            self.head_threshold_deg, self.hysteresis_deg, self.head_cone == "3d", engagement
        )

    @field_validator("cfg")
    @classmethod
    def _cfg(cls, value: list[str]) -> list[str]:
        for position, entry in enumerate(value, 1):
            key, sep, _ = entry.partition(":")
            if not (sep and key):  # the entry itself is not quoted: it may be a secret
                raise ValueError(f"entry {position} is not KEY:VALUE")
        return value


#: zenoh's link protocols; those of them that take ``host:port``.
_PROTOCOLS = {"tcp", "udp", "tls", "quic", "ws", "unixsock-stream", "unixpipe", "serial", "vsock"}
_HOST_PORT = {"tcp", "udp", "tls", "quic", "ws"}


def endpoint_problem(endpoint: str, *, listen: bool = False) -> str | None:
    """Why zenoh could never use ``endpoint`` (zenoh itself only finds out when it tries,
    and a peer then retries forever in silence), or None."""
    locator = endpoint.split("#", 1)[0].split("?", 1)[0]
    protocol, sep, address = locator.partition("/")
    if not sep or protocol not in _PROTOCOLS:
        return f"not <protocol>/<address>, protocol one of {', '.join(sorted(_PROTOCOLS))}"
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


class SettingsError(ValueError):
    """A bad setting, as one line that names the flag or variable it came from and never
    quotes a secret (see ``disclosure``)."""


def env_name(field: str) -> str:
    return ENV_PREFIX + field.upper()


def flag_name(field: str) -> str:
    return "--" + field.replace("_", "-")


def flag_info(field: str) -> dict[str, Any]:
    """What ``Settings`` says about a field's flag: group, short, metavar, shown."""
    extra = Settings.model_fields[field].json_schema_extra
    assert isinstance(extra, dict), f"{field} has no flag metadata"
    return extra


def shown_default(field: str) -> str:
    """A field's default as the docs and ``--help`` say it."""
    info = Settings.model_fields[field]
    if (shown := flag_info(field)["shown"]) is not None:
        return str(shown)
    value = info.default
    if value is None or value == [] or value == "":
        return "none"
    if value is False:
        return "off"
    if isinstance(value, list):
        return ",".join(f"{v:g}" if isinstance(v, float) else str(v) for v in value)
    return f"{value:g}" if isinstance(value, float) else str(value)


def env_help(field: str, code: str = "") -> str:
    """A field's environment variable (in ``code`` quotes), with its list separator when
    it has one."""
    separator = _LIST_SEPARATORS.get(field)
    name = f"{code}{env_name(field)}{code}"
    if separator is None:
        return name
    return f"{name} ({'comma' if separator == ',' else repr(separator)}-separated)"


def settings_table() -> str:
    """docs/configuration.md's table of every setting (a test keeps the page equal)."""
    rows = [
        "| flag | environment | default | meaning |",
        "| --- | --- | --- | --- |",
    ]
    for field, info in Settings.model_fields.items():
        flags = ", ".join(f"`{f}`" for f in (flag_info(field)["short"], flag_name(field)) if f)
        shown = shown_default(field)
        if flag_info(field)["shown"] is None and shown not in ("none", "off"):
            shown = f"`{shown}`"
        rows.append(
            f"| {flags} | {env_help(field, '`')} | {'—' if shown == 'none' else shown} "
            f"| {info.description} |"
        )
    return "\n".join(rows)


def load_settings(flags: Mapping[str, Any], environ: Mapping[str, str]) -> Settings:
    """Merge flags (None or absent = not given) over ``FACING_*`` variables over defaults.

    Raises SettingsError naming the flag or variable each bad value came from.
    """
    values: dict[str, Any] = {}
    sources: dict[str, str] = {}
    for name in Settings.model_fields:
        flag = flags.get(name)
        if flag is not None and flag != [] and flag is not False:
            values[name], sources[name] = flag, flag_name(name)
        elif (raw := environ.get(env_name(name))) is not None and raw != "":
            separator = _LIST_SEPARATORS.get(name)
            values[name] = (
                [part.strip() for part in raw.split(separator) if part.strip()]
                if separator
                else raw
            )
            sources[name] = env_name(name)
    try:
        return Settings(**values)
    except ValidationError as error:
        raise SettingsError(_describe(error, values, sources)) from None


def _describe(error: ValidationError, values: Mapping[str, Any], sources: Mapping[str, str]) -> str:
    """One line per problem: where the value came from, the value if it may be shown, why."""
    problems = []
    for detail in error.errors(include_url=False, include_input=False):
        field = str(detail["loc"][0]) if detail["loc"] else ""
        reason = detail["msg"].removeprefix("Value error, ")
        if field in values:
            shown = public_value(field, values[field])
            problems.append(f"{sources[field]}={shown}: {reason}")
        elif field:
            problems.append(f"{flag_name(field)}: {reason}")
        else:
            problems.append(reason)
    return "; ".join(problems)


def _loopback(endpoint: str) -> str:
    """The address a process on the same host reaches a wildcard listener at."""
    return endpoint.replace("/0.0.0.0:", "/127.0.0.1:").replace("/[::]:", "/[::1]:")


def probe_config(settings: Settings) -> zenoh.Config:
    """Zenoh config of a short-lived helper session (``health``) beside a running service,
    configured from the same flags and ``FACING_*`` variables as the service.

    It must not take the service's ports, so it listens nowhere (even if the config file
    says otherwise); when the service is only configured to listen, the helper connects to
    those endpoints on loopback.
    """
    connect = settings.connect or [_loopback(e) for e in settings.listen]
    # A router's mode would make the helper listen; otherwise the configured mode holds
    # (the config file's, when no flag gives one: a client stays a client).
    mode = "client" if connect else (None if settings.mode == "router" else settings.mode)
    helper = settings.model_copy(update={"listen": [], "connect": connect, "mode": mode})
    conf = zenoh_config(helper)
    conf.insert_json5("listen/endpoints", "[]")
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


def zenoh_config(settings: Settings) -> zenoh.Config:
    """The zenoh session config; SettingsError on an unreadable file, unknown key or bad
    value, naming the flag and never echoing a secret value (zenoh's own messages quote
    the offending text, and the source file of zenoh's that raised them)."""
    conf = _config_file(settings.config) if settings.config else zenoh.Config()
    if settings.mode is not None:
        _insert(conf, "mode", json.dumps(settings.mode), "--mode")
    if settings.connect:
        _insert(conf, "connect/endpoints", json.dumps(settings.connect), "--connect")
    if settings.listen:
        _insert(conf, "listen/endpoints", json.dumps(settings.listen), "--listen")
    if settings.no_multicast_scouting:
        _insert(conf, "scouting/multicast/enabled", "false", "--no-multicast-scouting")
    for entry in settings.cfg:
        key, _, value = entry.partition(":")
        _insert(conf, key, value, f"--cfg {public_cfg_entry(entry)}")
    return conf


def _config_file(path: Path) -> zenoh.Config:
    if not path.exists():
        raise SettingsError(f"--config {str(path)!r}: no such file")
    if not path.is_file():
        raise SettingsError(f"--config {str(path)!r}: not a file")
    if not os.access(path, os.R_OK):
        raise SettingsError(f"--config {str(path)!r}: not readable (permission denied)")
    try:
        return zenoh.Config.from_file(str(path))
    except zenoh.ZError as error:
        raise SettingsError(f"--config {str(path)!r}: {zenoh_error_reason(error)}") from None


def _insert(conf: zenoh.Config, key: str, value: str, what: str) -> None:
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
