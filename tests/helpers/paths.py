"""Where the suite finds the checkout and its data, wherever a test file sits under tests/."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]     # the checkout: pyproject.toml, docs/, notebooks/
DATA = ROOT / "tests" / "data"                 # robot files and caches written here (dh/, exercise_keys.json.gz)
