"""Set for every test and doctest the suite collects: figures use the Agg backend (no display in CI)."""

import os

os.environ.setdefault("MPLBACKEND", "Agg")

collect_ignore = ["workspace_sym/__main__.py"]
