"""Reader for laser-tracker records ``tracker/<dir>_f<feed>.csv`` (``docs/data-contract.md``).

Columns ``t_s, x_mm, y_mm, z_mm``: sample time [s] at the tracker rate (815 Hz in the thesis)
— or, for a stream without a time base (``time_base: none``), the export's own coarse stamps —
and the target position [mm] in the robot base frame, while the robot moves along one
straight cut path at one feed. Checks: the columns are present and numeric (no NaN/inf),
at least ``MIN_ROWS`` rows, time strictly increasing and uniform at ``1/fs_hz`` (the
manifest's rate), and the target actually moves along a path at least ``min_path_mm`` long
with no jump (lost beam) larger than ``max_step_factor`` times the median step.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.io.tables import check_uniform, read_numeric_csv

COLUMNS = ("t_s", "x_mm", "y_mm", "z_mm")
MIN_ROWS = 64


def read_tracker(path: str | Path, *, fs_hz: float | None = None, min_path_mm: float = 1.0,
                 max_step_mm: float = 1.0, spatial_only: bool = False
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Read and validate one tracker record.

    Parameters
    ----------
    path
        The CSV file.
    fs_hz
        Sampling rate from the manifest; the time step must be ``1/fs_hz`` (0.1 %).
    min_path_mm
        Shortest accepted distance between the first and the last position.
    max_step_mm
        Largest accepted distance between consecutive samples (a longer one is a lost beam
        or a re-acquired target; at 815 Hz even 100 mm/s moves 0.12 mm per sample).
    spatial_only
        A stream without a time base (manifest ``time_base: none``, imported with
        ``--spatial-only``): ``t_s`` holds the export's own stamps (non-decreasing, coarse)
        and is not checked against a rate; the samples keep their acquisition order.

    Returns
    -------
    t_s, points_mm
        Times ``(n,)`` [s] and positions ``(n, 3)`` [mm].

    Raises
    ------
    RawDataError
        Naming the file, the row/column and what was expected.
    """
    df = read_numeric_csv(path, COLUMNS, min_rows=MIN_ROWS)
    t = df["t_s"].to_numpy(float)
    if spatial_only:
        back = np.flatnonzero(np.diff(t) < 0)
        if back.size:
            raise RawDataError(path, f"t_s goes backwards ({t[back[0]]:g} then "
                               f"{t[back[0] + 1]:g})", where=f"row {int(back[0]) + 3}, column t_s",
                               expected="non-decreasing stamps (the acquisition order)")
    else:
        check_uniform(path, t, "t_s", step=None if fs_hz is None else 1.0 / float(fs_hz))
    p = df[["x_mm", "y_mm", "z_mm"]].to_numpy(float)
    span = float(np.linalg.norm(p[-1] - p[0]))
    if span < min_path_mm:
        raise RawDataError(path, f"the target moves only {span:.3g} mm from the first to the "
                           "last sample", where="columns x_mm, y_mm, z_mm",
                           expected=f"a straight path at least {min_path_mm:g} mm long")
    step = np.linalg.norm(np.diff(p, axis=0), axis=1)
    bad = np.flatnonzero(step > max_step_mm)
    if bad.size:
        i = int(bad[0]) + 1
        raise RawDataError(path, f"the position jumps by {step[i - 1]:.3g} mm between two "
                           "samples (lost beam?)", where=f"row {i + 2}, columns x_mm, y_mm, z_mm",
                           expected=f"consecutive positions within {max_step_mm:g} mm")
    return t, p
