"""Reader for stylus profiles, ``profiles/<cut>.csv`` (docs/data-contract.md).

Columns ``x_mm`` (position along the feed direction, uniformly spaced, increasing) and
``z_um`` (height). NaN/inf, text, a missing column, a non-increasing or non-uniform ``x_mm``
all raise :class:`robomill.io.RawDataError` naming the file, row/column and expectation.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.io.tables import check_uniform, read_numeric_csv

MIN_SAMPLES = 64
"""Fewest samples accepted (a profile shorter than this cannot be filtered meaningfully)."""


def read_profile(path: str | Path, *, rtol: float = 1e-3) -> tuple[np.ndarray, np.ndarray, float]:
    """Read one profile: ``(x_mm, z_um, fs_per_mm)``.

    Raises
    ------
    RawDataError
        Missing ``x_mm``/``z_um`` (with a unit hint, e.g. ``z_mm``), non-numeric or non-finite
        values, fewer than :data:`MIN_SAMPLES` rows, ``x_mm`` not strictly increasing or not
        uniformly spaced within ``rtol`` of its median step.
    """
    df = read_numeric_csv(path, ["x_mm", "z_um"], min_rows=MIN_SAMPLES)
    x = df["x_mm"].to_numpy(float)
    z = df["z_um"].to_numpy(float)
    step = check_uniform(path, x, "x_mm", rtol=rtol)
    if step <= 0:
        raise RawDataError(path, f"x_mm step is {step}", where="column x_mm",
                           expected="a positive sampling step")
    return x, z, 1.0 / step
