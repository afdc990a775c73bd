"""The command line's argument types: each refuses a bad value in one line that says what
it must be, which argparse prints after the flag's name."""

from __future__ import annotations

import argparse
import ipaddress
import math
from collections.abc import Callable

from .camera.intrinsics import FIELD_OF_VIEW_DEG
from .contract import keys


def number(
    minimum: float, *, strict: bool, integer: bool = False, most: float | None = None
) -> Callable[[str], float]:
    """An argparse type: a finite number above (or from) ``minimum``, and at ``most``."""

    def parse(text: str) -> float:
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
        if not math.isfinite(value) or value < minimum or (strict and value == minimum):
            bound = f"> {minimum:g}" if strict else f">= {minimum:g}"
            raise argparse.ArgumentTypeError(f"must be a number {bound}, got {text}")
        if most is not None and value > most:
            raise argparse.ArgumentTypeError(f"must be a number <= {most:g}, got {text}")
        return value

    return parse


POSITIVE = number(0, strict=True)
NON_NEGATIVE = number(0, strict=False)


def port_number(text: str) -> int:
    """An argparse type: a TCP port, 0 for any free one."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a port number: {text!r}") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"must be a port in 0..65535 (0: any free), got {text}")
    return value


def listen_address(text: str) -> str:
    """An argparse type: an IP address to listen on (a name could resolve anywhere)."""
    try:
        return str(ipaddress.ip_address(text))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"not an IP address: {text!r} (127.0.0.1 for this machine only, 0.0.0.0 for all)"
        ) from None


def finite(text: str) -> float:
    """An argparse type: any finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
    return value


def field_of_view(text: str) -> float:
    """An argparse type: a field of view a camera can have (179° would read every face
    as 9 cm away)."""
    value, (low, high) = number(0, strict=True)(text), FIELD_OF_VIEW_DEG
    if not low <= value <= high:
        raise argparse.ArgumentTypeError(
            f"must be from {low:g} to {high:g} degrees (a "
            f"camera's horizontal field of view), got {text}"
        )
    return value


def id_prefix(text: str) -> str:
    """An argparse type: the start of a body id (a key chunk of letters, digits, _ or -)."""
    if not keys.is_name(text + "1"):
        raise argparse.ArgumentTypeError(f"not the start of an id: {text!r} ({keys.NAME_PATTERN})")
    return text
