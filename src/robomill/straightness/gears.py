"""Gear kinematics along a path (thesis §3.2, step 3): the spatial frequency [mm⁻¹] of every
gear element (once-per-revolution runout and tooth mesh) from the joint rates along the path
(Slamani & Bonev 2013), ``f = r · |dq/ds| / 2π`` (× ``z`` for the mesh).
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from robomill.kinematics import SerialRobot

ORDERS = ("runout", "mesh")
"""Gear error orders: once per revolution (eccentricity) and tooth mesh (teeth per rev)."""

# ---------------------------------------------------------------------------------------------
# 3. gear spatial frequencies
# ---------------------------------------------------------------------------------------------
def _gear_field(g: Any, name: str) -> Any:
    return g[name] if isinstance(g, Mapping) else getattr(g, name)


def gear_orders(gears: Sequence[Any]) -> Iterator[tuple[int, str, str, float]]:
    """``(joint, stage, order, multiplier)`` for every gear and order: ``runout`` turns
    ``r`` times per joint revolution, ``mesh`` ``r z`` times [Pulatbek 2024, §3.2]."""
    for g in gears:
        r = float(_gear_field(g, "rev_per_joint_rev"))
        z = int(_gear_field(g, "teeth"))
        joint, stage = int(_gear_field(g, "joint")), str(_gear_field(g, "stage"))
        yield joint, stage, "runout", r
        yield joint, stage, "mesh", r * z


def joint_path_for_line(robot: SerialRobot, start_mm: np.ndarray, end_mm: np.ndarray,
                        rotation: np.ndarray, q0_rad: np.ndarray,
                        n_points: int = 41) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles ``(n_points, n)`` along a straight TCP line at a fixed tool orientation
    (inverse kinematics, each solution seeding the next); also returns the abscissa [mm]."""
    a, b = np.asarray(start_mm, float), np.asarray(end_mm, float)
    s = np.linspace(0.0, float(np.linalg.norm(b - a)), n_points)
    u = (b - a) / np.linalg.norm(b - a)
    T = np.broadcast_to(np.eye(4), (n_points, 4, 4)).copy()
    T[:, :3, :3] = rotation
    T[:, :3, 3] = a + np.outer(s, u)
    return robot.ik_path(T, q0_rad), s


def gear_spatial_frequencies(q_rad: np.ndarray, s_mm: np.ndarray,
                             gears: Sequence[Any]) -> pd.DataFrame:
    """Spatial frequency of every gear element (both orders) along a path.

    Parameters
    ----------
    q_rad
        ``(m, n_joints)`` joint angles at path abscissae ``s_mm`` ``(m,)``.
    gears
        Gear stages (mappings or objects) with ``joint`` (1-based), ``stage``,
        ``rev_per_joint_rev`` and ``teeth``: any robot, any transmission.

    Returns
    -------
    DataFrame
        One row per gear and order: ``joint, stage, order, f_spatial_per_mm`` (mean over the
        path), ``f_min_per_mm, f_max_per_mm`` (its range along the path) and
        ``rev_per_mm_joint`` (joint revolutions per mm).

    Notes
    -----
    A gear turning ``r`` times per joint revolution makes ``r |dq/ds| / 2π`` revolutions per
    mm of path; its tooth mesh ``z`` times that. The joint angle is a function of the TCP
    position only, so on a given path this is independent of the feed (the temporal
    frequency is this times the feed).
    """
    q = np.asarray(q_rad, float)
    s = np.asarray(s_mm, float)
    dq = np.abs(np.gradient(q, s, axis=0)) / (2 * np.pi)  # joint rev per mm
    mean_rate = np.abs(q[-1] - q[0]) / (s[-1] - s[0]) / (2 * np.pi)
    rows = [{"joint": j, "stage": stage, "order": order,
             "f_spatial_per_mm": mult * mean_rate[j - 1],
             "f_min_per_mm": mult * dq[:, j - 1].min(),
             "f_max_per_mm": mult * dq[:, j - 1].max(),
             "rev_per_mm_joint": mean_rate[j - 1]}
            for j, stage, order, mult in gear_orders(gears)]
    return pd.DataFrame(rows)


def gear_frequencies_from_motion(t_s: np.ndarray, q_rad: np.ndarray, p_mm: np.ndarray,
                                 gears: Sequence[Any], *,
                                 min_speed_fraction: float = 0.99) -> pd.DataFrame:
    """Temporal [Hz] and spatial [mm⁻¹] frequency of every gear from a timed motion.

    ``f_t = r |q̇| / 2π`` (``× z`` for the mesh), ``f_s = f_t / |ṗ|``, averaged over the
    samples where the TCP speed is at least ``min_speed_fraction`` of its maximum (the
    constant-feed part). Used to check numerically that ``f_s`` does not depend on the feed.
    """
    t = np.asarray(t_s, float)
    qd = np.abs(np.gradient(np.asarray(q_rad, float), t, axis=0)) / (2 * np.pi)
    v = np.linalg.norm(np.gradient(np.asarray(p_mm, float), t, axis=0), axis=1)
    sel = v >= min_speed_fraction * v.max()
    rows = []
    for j, stage, order, mult in gear_orders(gears):
        ft = mult * qd[sel, j - 1]
        rows.append({"joint": j, "stage": stage, "order": order,
                     "f_temporal_hz": float(ft.mean()),
                     "f_spatial_per_mm": float(np.mean(ft / v[sel]))})
    return pd.DataFrame(rows)
