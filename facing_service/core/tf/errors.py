"""The lookups tf2 refuses, as tf2's four exception kinds (with tf2's messages, built by
the buffer and its caches)."""

from __future__ import annotations


class TfError(Exception):
    """A lookup tf2 would refuse; ``kind`` is tf2's exception name."""

    kind = "TransformException"


class LookupError_(TfError):
    kind = "LookupException"


class ConnectivityError(TfError):
    kind = "ConnectivityException"


class ExtrapolationError(TfError):
    kind = "ExtrapolationException"


class InvalidArgumentError(TfError):
    kind = "InvalidArgumentException"
