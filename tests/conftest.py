"""Test-suite settings: a non-interactive matplotlib backend (no display is needed anywhere)."""
import os

os.environ.setdefault("MPLBACKEND", "Agg")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
