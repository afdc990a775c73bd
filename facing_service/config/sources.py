"""Where settings come from, and how each is named: a flag beats its ``FACING_*`` variable,
which beats the default; a bad value is refused in one line that names the flag or the
variable it came from. Also the table of every setting that docs/configuration.md shows.
"""

from __future__ import annotations

import difflib
import logging
from collections.abc import Mapping
from typing import Any

from pydantic import ValidationError

from ..contract.errors import SettingsError
from .disclosure import public_value
from .settings import Settings

log = logging.getLogger("facing_service")

ENV_PREFIX = "FACING_"
#: ``FACING_*`` variables that are not settings: the health check's own identity
#: (``client.health``); ``FACING_TEST_*`` is kept for the project's own test tooling.
OTHER_VARIABLES = ("FACING_HEALTH_CONFIG",)
TEST_PREFIX = "FACING_TEST_"
#: In environment variables, list settings are comma-separated, except ``FACING_CFG``
#: whose JSON5 values may hold commas: its entries are separated by ``;``.
_LIST_SEPARATORS = {
    "connect": ",", "listen": ",", "cfg": ";", "zones_m": ",", "reconnect_s": ",",
}  # fmt: skip


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
        if _given(flag):
            values[name], sources[name] = flag, flag_name(name)
        elif (raw := environ.get(env_name(name))) is not None and raw != "":
            separator = _LIST_SEPARATORS.get(name)
            values[name] = (
                [part.strip() for part in raw.split(separator) if part.strip()]
                if separator
                else raw
            )
            sources[name] = env_name(name)
    for warning in unknown_variables(environ):
        log.warning(warning)
    try:
        return Settings(**values)
    except ValidationError as error:
        raise SettingsError(_describe(error, values, sources)) from None


def _given(flag: Any) -> bool:
    return flag is not None and flag != [] and flag is not False


def source_of(field: str, flags: Mapping[str, Any], environ: Mapping[str, str]) -> str:
    """What set ``field``, as ``load_settings`` chose: its flag, else its variable when
    set (an error about the value names it: FACING_CFG's were once said as --cfg)."""
    if not _given(flags.get(field)) and environ.get(env_name(field)):
        return env_name(field)
    return flag_name(field)


def unknown_variables(environ: Mapping[str, str]) -> list[str]:
    """One line for each ``FACING_*`` variable that names no setting (a misspelt one
    would otherwise be ignored without a word), with the nearest name when one is close."""
    known = [env_name(name) for name in Settings.model_fields] + list(OTHER_VARIABLES)
    lines = []
    for name in sorted(environ):
        if not name.startswith(ENV_PREFIX) or name in known or name.startswith(TEST_PREFIX):
            continue
        near = difflib.get_close_matches(name, known, n=1, cutoff=0.85)
        hint = f" (did you mean {near[0]}?)" if near else " (docs/configuration.md lists them)"
        lines.append(f"{name} names no setting and is ignored{hint}")
    return lines


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
