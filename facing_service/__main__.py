"""``python -m facing_service``: the same CLI as the ``facing-service`` command."""

from .cli import entry

entry()
