"""Measurement scripts for facing-service: they print numbers, they assert nothing."""
