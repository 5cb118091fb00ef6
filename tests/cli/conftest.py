"""The CLI reliability tests reuse the engine tests' toy study and helpers."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[1] / "engine"))
