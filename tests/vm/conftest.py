"""Lets the tests of vm/ import their fakes (``vm_fakes``) with pytest's importlib mode."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
