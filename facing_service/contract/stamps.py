"""Time, in one shape: ``Time``, integer nanoseconds (the stamp of a pose, a result, a
transform, a scene), with the ``sec``/``nanosec`` views ROS messages and our JSON carry.
``Stamp`` is its JSON form on the wire (``builtin_interfaces/Time``), converted at the
edges only (``Time.from_model``, ``Time.model``).

An int, so stamps compare, hash, sort and subtract as numbers, and tf2's rules (integer
nanoseconds) need no conversion; arithmetic gives plain ints (a duration is not a stamp).
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

NS_PER_S = 1_000_000_000
#: builtin_interfaces/Time: ROS 2 keeps ``sec`` in an int32 and never negative.
MAX_SEC, MAX_NANOSEC = 2**31 - 1, 999_999_999


class Stamp(BaseModel):
    """``builtin_interfaces/Time``: ROS 2 keeps ``sec`` in an int32 and never negative."""

    model_config = ConfigDict(strict=True, allow_inf_nan=False)
    sec: int = Field(ge=0, le=MAX_SEC)
    nanosec: int = Field(ge=0, le=MAX_NANOSEC)


class Time(int):
    """A stamp: integer nanoseconds on the sender's clock."""

    __slots__ = ()

    @classmethod
    def of(cls, sec: int, nanosec: int = 0) -> Time:
        return cls(sec * NS_PER_S + nanosec)

    @classmethod
    def checked(cls, sec: int, nanosec: int) -> Time | None:
        """The stamp, or None when it is outside what a ``builtin_interfaces/Time`` may
        say, and so what any output of ours can carry (negative seconds; nanoseconds past
        999 999 999, as an uninitialised stamp has)."""
        if 0 <= sec <= MAX_SEC and 0 <= nanosec <= MAX_NANOSEC:
            return cls(sec * NS_PER_S + nanosec)
        return None

    @classmethod
    def from_seconds(cls, seconds: float) -> Time:
        return cls(round(seconds * 1e9))

    @classmethod
    def from_model(cls, stamp: Stamp) -> Time:
        return cls(stamp.sec * NS_PER_S + stamp.nanosec)

    @property
    def sec(self) -> int:
        return self // NS_PER_S

    @property
    def nanosec(self) -> int:
        return self % NS_PER_S

    @property
    def seconds(self) -> float:
        """As float seconds (the engagement machine's clock), on the hot path: sec +
        nanosec * 1e-9 as the tuples said it, from one divmod."""
        sec, nanosec = divmod(self, NS_PER_S)
        return sec + nanosec * 1e-9

    def model(self) -> Stamp:
        sec, nanosec = divmod(self, NS_PER_S)
        return Stamp.model_construct(sec=sec, nanosec=nanosec)

    def __repr__(self) -> str:
        return f"Time.of({self.sec}, {self.nanosec})"

    def __str__(self) -> str:
        """As a person reads a stamp, in a log line or an error: seconds, to the
        nanosecond (``Time.of(1700000000, 33333248)``, the repr, was said)."""
        return f"{self.sec}.{self.nanosec:09d} s"

    def __format__(self, spec: str) -> str:
        return str(self) if not spec else int.__format__(self, spec)


#: No stamp yet (an empty frame, a scene before anyone was seen).
ZERO = Time(0)
