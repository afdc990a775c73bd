"""What a ``FacingClient`` takes: how its zenoh session reaches the service, and nothing
of the service's own settings (a facing cone given to a client would do nothing, so it is
refused by name). Every refusal is one ``SettingsError`` line naming the option."""

from __future__ import annotations

import difflib
import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal, TypedDict

import zenoh
from pydantic import ConfigDict, Field, ValidationError, field_validator

from ..config.fields import SessionChecks
from ..config.session import insert, readable_file, zenoh_config
from ..config.settings import Settings
from ..contract import keys
from ..contract.errors import SettingsError

#: Where each TLS file goes in zenoh's config (mutual TLS when the client has its own
#: certificate, as examples/secure's consumer does).
_TLS_KEYS = {
    "tls_root_ca": "transport/link/tls/root_ca_certificate",
    "tls_certificate": "transport/link/tls/connect_certificate",
    "tls_private_key": "transport/link/tls/connect_private_key",
}


class ClientOptionFields(TypedDict, total=False):
    """The keyword options of ``FacingClient`` (for type checkers; ``ClientOptions``
    validates them and holds their defaults)."""

    mode: Literal["peer", "client"] | None
    connect: list[str] | str
    listen: list[str] | str
    config: Path | str | None
    cfg: list[str] | str
    no_multicast_scouting: bool
    reconnect_s: list[float]
    timeout_s: float
    tls_root_ca: Path | str | None
    tls_certificate: Path | str | None
    tls_private_key: Path | str | None


class ClientOptions(SessionChecks):
    """A client's options, checked. ``mode``: zenoh's (None: the config file's, else
    peer); ``connect`` / ``listen``: endpoints; ``config``: a zenoh JSON5 file the other
    options override; ``cfg``: ``KEY:VALUE`` entries applied last; ``timeout_s``: how long
    a query or the first sight of a service is waited for; the ``tls_*`` files: the CA
    that signed the router's certificate, and the client's own certificate and key for
    mutual TLS (both or neither)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    namespace: str = "hri"
    frame: str = keys.ALL_FRAMES
    mode: Literal["peer", "client"] | None = None
    connect: list[str] = Field(default_factory=list)
    listen: list[str] = Field(default_factory=list)
    config: Path | None = None
    cfg: list[str] = Field(default_factory=list)
    no_multicast_scouting: bool = False
    reconnect_s: list[float] = Field(default_factory=lambda: [0.25, 1.0])
    timeout_s: float = Field(2.0, gt=0, le=3600)
    tls_root_ca: Path | None = None
    tls_certificate: Path | None = None
    tls_private_key: Path | None = None

    @field_validator("connect", "listen", "cfg", mode="before")
    @classmethod
    def _one_is_a_list_of_one(cls, value: Any) -> Any:
        """``connect="tcp/host:7447"`` as ``connect=["tcp/host:7447"]`` ("Input
        should be a valid list"; a string is never a list of its characters here)."""
        return [value] if isinstance(value, str) else value

    def zenoh_config(self) -> zenoh.Config:
        """The session's config: as the service's is made (``config/session.py``), then
        the TLS files. SettingsError naming the option when zenoh refuses one."""
        conf = zenoh_config(self, named=lambda field: f"FacingClient {field}=")
        given = {k: getattr(self, k) for k in _TLS_KEYS if getattr(self, k) is not None}
        if ("tls_certificate" in given) != ("tls_private_key" in given):
            raise SettingsError(
                "FacingClient: tls_certificate= and tls_private_key= go together (mutual TLS)"
            )
        for field, path in given.items():
            if problem := readable_file(path, f"FacingClient {field}="):
                raise SettingsError(problem)
            insert(conf, _TLS_KEYS[field], json.dumps(str(path)), f"FacingClient {field}=")
        if "tls_certificate" in given:
            insert(conf, "transport/link/tls/enable_mtls", "true", "FacingClient tls_certificate=")
        return conf


def client_options(given: Mapping[str, Any]) -> ClientOptions:
    """``given`` checked: an option the client does not take is named, with the nearest
    one, or said to be the service's; a bad value is named with why."""
    known = list(ClientOptions.model_fields)
    for name in given:
        if name in known:
            continue
        if name in Settings.model_fields:
            raise SettingsError(
                f"FacingClient: {name}= is a setting of the service (facing-service run "
                f"--{name.replace('_', '-')}), not of a client; a client takes "
                f"{', '.join(known)}"
            )
        near = difflib.get_close_matches(name, known, n=1)
        hint = f" (did you mean {near[0]}=?)" if near else f"; it takes {', '.join(known)}"
        raise SettingsError(f"FacingClient: no option {name}={hint}")
    try:
        return ClientOptions(**given)
    except ValidationError as error:
        problems = []
        for detail in error.errors(include_url=False, include_input=False):
            field = ".".join(str(part) for part in detail["loc"])
            problems.append(f"{field}=: {detail['msg'].removeprefix('Value error, ')}")
        raise SettingsError(f"FacingClient: {'; '.join(problems)}") from None
