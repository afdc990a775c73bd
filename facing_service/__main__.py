"""``python -m facing_service``: the same CLI as the ``facing-service`` command."""

from .launch import entry

entry()
