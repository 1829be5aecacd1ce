"""Readers of the Creaform C-Track tables (``ctrack/*.csv``, ``docs/data-contract.md``).

Every reader goes through :func:`robomill.io.tables.read_numeric_csv` (missing columns, text
or NaN in a coordinate, truncated rows) and then checks what the calibration needs: enough
points for each joint circle, and every step position measured from both directions.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from robomill.errors import RawDataError
from robomill.io.tables import read_numeric_csv

XYZ = ["x_mm", "y_mm", "z_mm"]
N_JOINTS = 6
QCOLS = [f"q{i}_deg" for i in range(1, N_JOINTS + 1)]
MIN_CIRCLE_POINTS = 3

COLUMNS = {
    "circles": ["joint", "q_deg", *XYZ],
    "home": XYZ,
    "steps": ["joint", "step", "q_deg", "direction", *XYZ],
    "base": ["pose", *QCOLS, "group", *XYZ],
    "loads": ["test", *QCOLS, "load_kg", *XYZ],
    "accuracy": ["point", *QCOLS, "x_cmd_mm", "y_cmd_mm", "z_cmd_mm", *XYZ],
}
"""Required numeric columns of each table (``table`` key of the manifest)."""


def _joints(path, df, column="joint"):
    j = df[column].to_numpy()
    bad = np.flatnonzero((j != np.round(j)) | (j < 1) | (j > N_JOINTS))
    if bad.size:
        i = int(bad[0])
        raise RawDataError(path, f"joint {float(j[i])!r} is not a joint number",
                           where=f"row {i + 2}, column {column}",
                           expected=f"an integer 1..{N_JOINTS}")
    return df.astype({column: int})


def read_circles(path: str | Path, *, min_points: int = MIN_CIRCLE_POINTS) -> pd.DataFrame:
    """Joint circles: ``joint, q_deg, x_mm, y_mm, z_mm`` (a target on link i, joint i alone).

    Raises :class:`RawDataError` when a joint has fewer than ``min_points`` distinct angles
    (a circle needs at least 3), or when a joint of 1..6 is missing.
    """
    df = _joints(path, read_numeric_csv(path, COLUMNS["circles"], min_rows=1), "joint")
    for j in range(1, N_JOINTS + 1):
        g = df[df["joint"] == j]
        n = g["q_deg"].nunique()
        if n < min_points:
            raise RawDataError(path, f"joint {j} has {n} circle point(s)",
                               where=f"column q_deg, rows with joint = {j}",
                               expected=f"at least {min_points} distinct angles per joint "
                                        "(a circle needs 3)")
    return df


def read_home(path: str | Path) -> pd.DataFrame:
    """Tool tip at home: ``x_mm, y_mm, z_mm`` (repeated readings)."""
    return read_numeric_csv(path, COLUMNS["home"], min_rows=1)


def read_steps(path: str | Path) -> pd.DataFrame:
    """Joint steps: ``joint, step, q_deg, direction, x_mm, y_mm, z_mm``.

    Every (joint, q_deg) must be measured approached from both directions (``direction`` +1
    and −1: their mean cancels backlash), and q = 0 must be among the steps (the reference
    P_0 of eq. 1.5).
    """
    df = _joints(path, read_numeric_csv(path, COLUMNS["steps"], min_rows=2), "joint")
    d = df["direction"].to_numpy()
    bad = np.flatnonzero(~np.isin(d, (-1.0, 1.0)))
    if bad.size:
        i = int(bad[0])
        raise RawDataError(path, f"direction {float(d[i])!r}",
                           where=f"row {i + 2}, column direction",
                           expected="+1 or -1 (the approach direction)")
    for (j, q), g in df.groupby(["joint", "q_deg"]):
        dirs = set(g["direction"].astype(int))
        if dirs != {1, -1}:
            only = "+1" if dirs == {1} else "-1"
            row = int(g.index[0]) + 2
            raise RawDataError(path, f"joint {j} step at q = {q:g} deg is measured from one "
                               f"direction only (direction {only})",
                               where=f"row {row}, column direction",
                               expected="each step position approached from both directions "
                                        "(+1 and -1)")
    for j, g in df.groupby("joint"):
        if not np.isclose(g["q_deg"].abs().min(), 0.0):
            raise RawDataError(path, f"joint {j} has no step at q = 0",
                               where=f"column q_deg, rows with joint = {j}",
                               expected="the home position q = 0 among the steps (P_0)")
    return df


def read_base(path: str | Path) -> pd.DataFrame:
    """Base target groups: ``pose, q1_deg..q6_deg, group (1|2), x_mm, y_mm, z_mm``; every pose
    must have both groups."""
    df = read_numeric_csv(path, COLUMNS["base"], min_rows=4).astype({"group": int})
    for p, g in df.groupby("pose"):
        if set(g["group"]) != {1, 2}:
            raise RawDataError(path, f"pose {p:g} has groups {sorted(set(g['group']))}",
                               where=f"row {int(g.index[0]) + 2}, column group",
                               expected="both target groups 1 and 2 at every pose")
    return df


def read_loads(path: str | Path) -> pd.DataFrame:
    """Load-disc tests: ``test, q1_deg..q6_deg, load_kg, x_mm, y_mm, z_mm``; each test needs an
    unloaded reference (load 0) and at least one load."""
    df = read_numeric_csv(path, COLUMNS["loads"], min_rows=2)
    for t, g in df.groupby("test"):
        loads = set(g["load_kg"])
        if 0.0 not in loads or len(loads) < 2:
            raise RawDataError(path, f"test {t:g} has loads {sorted(loads)} kg",
                               where=f"row {int(g.index[0]) + 2}, column load_kg",
                               expected="an unloaded reading (0 kg) and at least one load")
    return df


def read_accuracy(path: str | Path) -> pd.DataFrame:
    """Accuracy points: ``point, q1_deg..q6_deg, x/y/z_cmd_mm, x/y/z_mm`` (one row per visit)."""
    return read_numeric_csv(path, COLUMNS["accuracy"], min_rows=1)


READERS = {"circles": read_circles, "home": read_home, "steps": read_steps, "base": read_base,
           "loads": read_loads, "accuracy": read_accuracy}
"""Reader per ``table`` value of the manifest."""
