"""The zenoh shell: ``FacingService`` and the collaborators it hands each job to (the
``intake`` and its ``side_queue``, the ``outbox`` and its ``publisher``, the ``publications``
it builds and the ``ledger`` of what was counted). It moves bytes; the core decides."""

from .run import run_until
from .service import FacingService

__all__ = ["FacingService", "run_until"]
