"""Repository-level pytest configuration: docstring examples under src/ run as doctests."""

import matplotlib

matplotlib.use("Agg")  # tests never open windows; the package itself never chooses a backend
