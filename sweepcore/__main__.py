"""``python -m sweepcore``: the ``sweepcore`` command (see :mod:`sweepcore.cli`)."""
import sys

from .cli import main

sys.exit(main())
