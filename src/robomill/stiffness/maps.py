"""Stiffness over the workspace [Yi 2025, §2 and §4.2]: directional stiffness maps over the
working plane for one redundancy angle, their labelled datasets, and the Monte-Carlo
workspace with the reachable annulus per milling height.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from robomill.kinematics import SerialRobot
from robomill.stiffness.model import (
    comprehensive_index_N_m,
    directional_stiffness_N_m,
    jacobian_m,
    translational_compliance_m_N,
)
from robomill.stiffness.poses import solve_poses, tool_rotation_redundancy
from robomill.xrvars import attrs


def plane_map(robot: SerialRobot, compliance: np.ndarray, x_mm: np.ndarray, y_mm: np.ndarray,
              height_mm: float, redundancy_rad: float, R0: np.ndarray,
              q_seed_rad: np.ndarray, *, limits_rad: np.ndarray | None = None) -> dict:
    """Directional stiffness over the working plane z = H for one redundancy angle
    [Yi 2025, §4.2, Fig. 11].

    Returns a mapping of arrays on the ``(len(y), len(x))`` grid: ``k_N_m`` ``(ny, nx, 3)``
    along tool X, Y, Z (NaN where unreachable), ``S_N_m`` (comprehensive index), ``q_rad``
    ``(ny, nx, n)`` and ``reachable``.
    """
    X, Y = np.meshgrid(np.asarray(x_mm, float), np.asarray(y_mm, float))
    P = np.stack([X.ravel(), Y.ravel(), np.full(X.size, float(height_mm))], -1)
    R = tool_rotation_redundancy(R0, redundancy_rad)
    q, ok = solve_poses(robot, P, R, q_seed_rad, limits_rad=limits_rad)
    C = translational_compliance_m_N(jacobian_m(robot, q), compliance)
    k = directional_stiffness_N_m(C, np.broadcast_to(R, C.shape))
    k[~ok] = np.nan
    S = comprehensive_index_N_m(k)
    shape = X.shape
    return {"k_N_m": k.reshape(shape + (3,)), "S_N_m": S.reshape(shape),
            "q_rad": q.reshape(shape + (robot.n_joints,)), "reachable": ok.reshape(shape)}


def monte_carlo_workspace(robot: SerialRobot, limits_rad: np.ndarray, n: int,
                          rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Monte-Carlo workspace [Yi 2025, §2.1]: ``n`` uniform joint samples within
    ``limits_rad`` ``(n_joints, 2)``; returns the samples and TCP positions ``(n, 3)`` [mm]."""
    lim = np.asarray(limits_rad, float)
    q = rng.uniform(lim[:, 0], lim[:, 1], size=(n, robot.n_joints))
    return q, robot.fk(q)[:, :3, 3]


def map_dataset(robot: SerialRobot, compliance: np.ndarray, *, height_mm: float,
                redundancy_deg: float, half_width_mm: float, step_mm: float,
                q_seed_deg: Sequence[float], limits_deg=None):
    """One working-plane map (:func:`plane_map`) as a labelled dataset (dims y, x, axis,
    joint; scalar coordinates ``height_mm`` and ``redundancy_deg``)."""
    import xarray as xr

    g = np.arange(-half_width_mm, half_width_mm + 0.5 * step_mm, step_mm)
    lim = None if limits_deg is None else np.deg2rad(np.asarray(limits_deg, float))
    m = plane_map(robot, compliance, g, g, height_mm, np.deg2rad(redundancy_deg),
                  np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]]),
                  np.deg2rad(q_seed_deg), limits_rad=lim)
    q = np.rad2deg(m["q_rad"])
    q[~m["reachable"]] = np.nan
    return xr.Dataset(
        {"k_N_m": (("y", "x", "axis"), m["k_N_m"],
                   attrs("N/m", "directional stiffness along the tool axis (X feed, Z axial)")),
         "S_N_m": (("y", "x"), m["S_N_m"],
                   attrs("N/m", "comprehensive stiffness index (harmonic mean of X, Y, Z)")),
         "q_deg": (("y", "x", "joint"), q, attrs("deg", "joint angles of the pose")),
         "reachable": (("y", "x"), m["reachable"],
                       attrs("1", "pose reachable within the joint limits"))},
        coords={"x": ("x", g, attrs("mm", "TCP x in the base frame")),
                "y": ("y", g, attrs("mm", "TCP y in the base frame")),
                "axis": ("axis", ["X", "Y", "Z"], attrs("1", "tool axis")),
                "joint": ("joint", np.arange(1, robot.n_joints + 1), attrs("1", "joint")),
                "height_mm": ((), float(height_mm), attrs("mm", "milling height H")),
                "redundancy_deg": ((), float(redundancy_deg),
                                   attrs("deg", "redundancy angle about the tool axis"))})


def workspace_dataset(robot: SerialRobot, limits_deg, n: int, rng: np.random.Generator,
                      maps=None):
    """Monte-Carlo workspace ([Yi 2025, §2.1], N samples) as a dataset: TCP points over all
    joints within ``limits_deg``; the X–Z section (joints 1, 5, 6 at 0, joints 2–4 within
    their limits, flange point as the seed's Fig. 2b); and, from ``maps``, the inner and
    outer diameter of the reachable working-plane annulus per height [Yi 2025, §2.2]."""
    import dataclasses

    import xarray as xr

    lim = np.deg2rad(np.asarray(limits_deg, float))
    _, P = monte_carlo_workspace(robot, lim, n, rng)
    lim_xz = lim.copy()
    lim_xz[[0, 4, 5]] = 0.0
    flange = dataclasses.replace(robot, tool_mm=np.zeros(3), tool_R=np.eye(3))
    _, Pxz = monte_carlo_workspace(flange, lim_xz, n, rng)
    ds = xr.Dataset(
        {"workspace_mm": (("sample", "axis3"), P, attrs("mm", "Monte-Carlo TCP positions")),
         "workspace_xz_mm": (("sample", "axis3"), Pxz,
                             attrs("mm", "Monte-Carlo flange positions, joints 1, 5, 6 at 0"))},
        coords={"sample": ("sample", np.arange(n), attrs("1", "sample")),
                "axis3": ("axis3", ["X", "Y", "Z"], attrs("1", "base axis"))})
    if maps is not None:
        X, Y = np.meshgrid(maps["x"].values, maps["y"].values)
        r = np.hypot(X, Y)
        inner, outer = [], []
        for h in maps["height_mm"].values:
            ok = maps["reachable"].sel(height_mm=h).values.any(axis=0)
            inner.append(2 * r[ok].min() if ok.any() else np.nan)
            outer.append(2 * r[ok].max() if ok.any() else np.nan)
        ds["annulus_inner_diameter_mm"] = ("height_mm", inner, attrs(
            "mm", "inner diameter of the reachable working plane (grid resolution)"))
        ds["annulus_outer_diameter_mm"] = ("height_mm", outer, attrs(
            "mm", "outer diameter of the reachable working plane (grid resolution)"))
        ds = ds.assign_coords(height_mm=("height_mm", maps["height_mm"].values,
                                         attrs("mm", "milling height H")))
    return ds
