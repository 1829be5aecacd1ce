"""Static deflection under the cutting force, measured as a lab measures it with a tracker: the
loaded pass along a cut's path (while the tool cuts) minus the air pass along the same path
(the same motion without material).

Both runs are expressed in the air pass' frame: its best line (centroid c, direction of motion
u, :func:`robomill.straightness.profile.fit_line`), the abscissa s = (p − c)·u of every sample,
and the positions resampled on one uniform grid of s over the span both runs cover (less
``trim_mm`` at each end: the speed ramps, at most
:data:`robomill.straightness.profile.TRIM_MAX_FRACTION` of the span). The deflection is the
mean over the grid of the difference,

    δ = (1/K) Σ_k [p_loaded(s_k) − p_air(s_k)],

read along the wall normal n = ẑ × u / |ẑ × u| and the tool axis ẑ (the planner's cut frame,
:func:`robomill.plan.poses.cut_frames`). What is common to both passes — the gear errors of the
joints along the path, the calibration of the tracker to the robot — cancels; the servo
ripple and the tracker noise average out over the path (their part of the mean is the
``stderr`` columns' order). Signed along n and ẑ; the planner predicts |δ·n| and |δ·ẑ|.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from robomill.straightness.profile import TRIM_MAX_FRACTION, fit_line, resample_uniform

DEFLECTION_COLUMNS = ["cut", "loaded_run", "air_run", "deflection_normal_um", "deflection_axial_um",
           "stderr_normal_um", "stderr_axial_um", "length_mm"]
"""Columns of ``results/straightness/deflection.csv``."""


def _along(points_mm: np.ndarray, c: np.ndarray, u: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """Abscissa along the line (c, u) of ``points_mm`` sorted in space, and the points."""
    s = (points_mm - c) @ u
    k = np.argsort(s, kind="stable")
    return s[k], points_mm[k]


def pass_deflection_um(loaded_mm: np.ndarray, air_mm: np.ndarray, *, ds_mm: float,
                       trim_mm: float = 0.0, t_air_s: np.ndarray | None = None) -> dict[str, float]:
    """Static deflection of the loaded pass against the air pass [µm] (module docstring).

    Parameters
    ----------
    loaded_mm, air_mm
        ``(n, 3)`` tracker positions [mm] of the two passes (base frame).
    ds_mm
        Step of the common grid along the path [mm].
    trim_mm
        Span dropped at each end of the common span [mm] (speed ramps).
    t_air_s
        Sample times of the air pass; None: the acquisition order (orients its line along
        the motion).

    Returns
    -------
    dict
        ``deflection_normal_um``, ``deflection_axial_um`` (signed along n = ẑ × u and ẑ),
        ``stderr_normal_um``, ``stderr_axial_um`` (standard error of the mean difference,
        from the spread of the resampled difference; correlated noise makes it optimistic) and
        ``length_mm`` (the common span averaged over).

    Raises
    ------
    ValueError
        The passes share less than four grid steps of path, or the path is vertical (no wall
        normal ẑ × u).
    """
    loaded = np.asarray(loaded_mm, float)
    air = np.asarray(air_mm, float)
    c, u = fit_line(air)
    t = np.arange(len(air), dtype=float) if t_air_s is None else np.asarray(t_air_s, float)
    if np.polyfit(t, (air - c) @ u, 1)[0] < 0:  # the direction of motion
        u = -u
    normal = np.cross([0.0, 0.0, 1.0], u)
    if np.linalg.norm(normal) < 1e-6:
        raise ValueError("the air pass runs along the tool axis: no wall normal z x u")
    normal /= np.linalg.norm(normal)
    s_a, p_a = _along(air, c, u)
    s_l, p_l = _along(loaded, c, u)
    s0, s1 = max(s_a[0], s_l[0]), min(s_a[-1], s_l[-1])
    trim = min(float(trim_mm), TRIM_MAX_FRACTION * max(s1 - s0, 0.0))
    s0, s1 = s0 + trim, s1 - trim
    if s1 - s0 < 4 * ds_mm:
        raise ValueError(f"the loaded and the air pass share {max(s1 - s0, 0.0):.3g} mm of "
                         f"path, under four grid steps of {ds_mm} mm")
    _, g_a = resample_uniform(s_a, p_a.T, ds_mm, s0, s1)
    _, g_l = resample_uniform(s_l, p_l.T, ds_mm, s0, s1)
    diff_um = (g_l - g_a) * 1e3                                          # (3, K)
    out: dict[str, float] = {}
    for name, axis in (("normal", normal), ("axial", np.array([0.0, 0.0, 1.0]))):
        d = axis @ diff_um
        out[f"deflection_{name}_um"] = float(d.mean())
        out[f"stderr_{name}_um"] = float(d.std(ddof=1) / np.sqrt(d.size))
    out["length_mm"] = float(s1 - s0)
    return out


def deflection_table(rows: Sequence[Mapping[str, Any]]) -> pd.DataFrame:
    """``results/straightness/deflection.csv`` from one mapping per air pass
    (:data:`DEFLECTION_COLUMNS`; NaN deflection where the air pass has no loaded pass)."""
    return pd.DataFrame(list(rows), columns=DEFLECTION_COLUMNS)
