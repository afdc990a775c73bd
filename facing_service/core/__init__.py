"""The functional core: pure functions and plain data, no zenoh, no threads, no clock of
its own (docs/architecture.md).

- facing: ``detector`` (the cone test), ``tracker`` (the latest state per body, order,
  staleness, hysteresis) with ``records`` (what a change says) and ``journal`` (its
  containers, undone when a turn meets a bug), ``snapshot`` (a turn's, read-only),
  ``silence`` (an input silent, its people held);
- engagement: ``engagement`` (levels, the score), ``evidence`` (a head's soft evidence),
  ``mutual_gaze`` and ``rule`` (hri_engagement's rule, as its mode);
- ``social/``: the social scene (groups, where to stand, the scene over time);
- ``tf/``: tf2's rules (the buffer, a link's cache, rigid transforms, tf2's errors)."""

from ..contract.levels import Level
from .detector import classify
from .records import Changes, PoseSample
from .tf.buffer import TfBuffer
from .tf.errors import TfError
from .tracker import Tracker

__all__ = ["Changes", "Level", "PoseSample", "TfBuffer", "TfError", "Tracker", "classify"]
