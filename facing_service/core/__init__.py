"""The functional core: the facing test (``detector``), engagement levels
(``engagement``), the latest state per body (``tracker``) and tf2's buffer rules
(``tf_buffer``). Pure functions and plain data: no zenoh, no threads, no clock of its own."""

from ..contract.levels import Level
from .detector import classify
from .records import Changes, PoseSample
from .tf_buffer import TfBuffer
from .tf_errors import TfError
from .tracker import Tracker

__all__ = ["Changes", "Level", "PoseSample", "TfBuffer", "TfError", "Tracker", "classify"]
