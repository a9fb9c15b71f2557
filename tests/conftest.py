import os

import matplotlib

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")

from hypothesis import settings

# derandomized: CI runs the same examples every time, so a failure reproduces
settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True)
settings.register_profile("dev", max_examples=30, deadline=None)
# one-off deep runs before a release: HYPOTHESIS_PROFILE=deep (random, 20x the CI examples)
settings.register_profile("deep", max_examples=1200, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


import numpy as np  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(scope="session")
def small_sweep():
    """A 3 × 5 grid of the load-side P design with metrics, in 4 chunks (sweep and Dask tests)."""
    from seapass.model.sea import SEA
    from seapass.sweep import GridAxis, SweepSpec

    sea = SEA(D1="k1 + b1*s", CL="kd", values=dict(m=1.0, b=10.0, k1=1000.0, b1=None, kd=None))
    return SweepSpec(
        sea=sea,
        grid=(GridAxis("b1", 0.0, 40.0, 20.0), GridAxis("kd", 500.0, 1500.0, 250.0)),
        chunk_size=4,
        horizon=1.0,
    )


def _assert_same_rows(a, b) -> None:
    assert a.column_names == b.column_names and a.num_rows == b.num_rows
    for name in a.column_names:  # NaN-aware, bit-for-bit
        np.testing.assert_array_equal(
            a.column(name).to_numpy(zero_copy_only=False),
            b.column(name).to_numpy(zero_copy_only=False),
        )


@pytest.fixture(scope="session")
def assert_same_rows():
    """``assert_same_rows(a, b)``: two Arrow tables have the same columns and values (NaN = NaN)."""
    return _assert_same_rows


@pytest.fixture(scope="session")
def paper_tables():
    """Tables I and II from `seapass.paper.tables.build_tables`, derived once per test process
    (~8 s of CPU); tests of their formatting and wording share them."""
    from seapass.paper.tables import build_tables

    return build_tables()
