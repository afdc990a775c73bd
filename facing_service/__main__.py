"""``python -m facing_service``: the same CLI as the ``facing-service`` command."""

import sys

from .cli import main

sys.exit(main())
