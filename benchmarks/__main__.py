"""``python -m benchmarks``: one performance run (``benchmarks.perf.run``)."""

from .perf.run import main

main()
