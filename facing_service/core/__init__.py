"""The functional core: the facing test (``detector``), engagement levels
(``engagement``), the latest state per body (``tracker``) and tf2's buffer rules
(``tf_buffer``). Pure functions and plain data: no zenoh, no threads, no clock of its own."""

from .detector import classify
from .engagement import Level
from .tf_buffer import TfBuffer, TfError
from .tracker import Changes, PoseSample, Tracker

__all__ = ["Changes", "Level", "PoseSample", "TfBuffer", "TfError", "Tracker", "classify"]
