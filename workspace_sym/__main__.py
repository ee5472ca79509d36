"""``python -m workspace_sym`` is the same as the ``workspace-sym`` command."""

import sys

from .cli import main

sys.exit(main())
