"""Performance: the service against a bare relay in the same run (``python -m
benchmarks``), the worker's hot path, an hour of churn, floods."""
