"""The functional core: pure functions and plain data, no zenoh, no threads, no clock of
its own (docs/architecture.md).

- facing: ``detector`` (the cone test), ``tracker`` (the latest state per body, order,
  staleness, hysteresis) with ``records`` (what a change says) and ``journal`` (its
  containers, undone when a turn meets a bug), ``view`` (a turn's read-only view);
- engagement: ``engagement`` (levels, the score), ``evidence`` (a head's soft evidence),
  ``mutual_gaze`` and ``rule`` (hri_engagement's rule, as its mode);
- the social scene: ``groups`` (F-formations, who faces whom), ``join`` (where to stand),
  ``scene`` (both per frame, over time);
- TF: ``tf_buffer`` (tf2's BufferCore rules), ``tf_cache``, ``tf_math``, ``tf_errors``."""

from ..contract.levels import Level
from .detector import classify
from .records import Changes, PoseSample
from .tf_buffer import TfBuffer
from .tf_errors import TfError
from .tracker import Tracker

__all__ = ["Changes", "Level", "PoseSample", "TfBuffer", "TfError", "Tracker", "classify"]
