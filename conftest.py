"""Repository-level pytest configuration: docstring examples under src/ run as doctests."""

import importlib.util

import matplotlib

matplotlib.use("Agg")  # tests never open windows; the package itself never chooses a backend

# the optional MuJoCo model cannot even be imported without its extra
collect_ignore = [] if importlib.util.find_spec("mujoco") else ["src/seapass/rig/mujoco_model.py"]
