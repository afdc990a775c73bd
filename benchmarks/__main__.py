"""``python -m benchmarks``: one performance run (``benchmarks.perf.run``)."""

import sys

from .perf.run import main

sys.exit(main())
