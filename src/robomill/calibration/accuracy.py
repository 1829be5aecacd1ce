"""Positioning accuracy of the nominal, geometric and full models (thesis §1.5) on points not
used for identification: per point, per model, per workspace region, and the chapter's
improvement ratios. Lengths in mm.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from robomill.calibration.identification import CalibratedModel


def accuracy_points(acc: pd.DataFrame, cal: CalibratedModel) -> pd.DataFrame:
    """Per accuracy point: the mean reached (measured) point over its visits, and the error
    of each model's prediction at the commanded joints [mm].

    ``nominal``: the commanded point (the controller's nominal model); ``geometric``: eq. 1.4
    with the identified geometry; ``full``: + joint-error regression + compliance.
    """
    n = cal.geometry.n_joints
    qcols = [f"q{i}_deg" for i in range(1, n + 1)]
    g = acc.groupby("point")
    meas = g[["x_mm", "y_mm", "z_mm"]].mean().to_numpy()
    cmd = g[["x_cmd_mm", "y_cmd_mm", "z_cmd_mm"]].first().to_numpy()
    q = np.deg2rad(g[qcols].first().to_numpy())
    geo = cal.geometry.tcp(q)
    full = cal.tcp(q)
    return pd.DataFrame({
        "point": g.size().index.to_numpy(), "visits": g.size().to_numpy(),
        "x_cmd_mm": cmd[:, 0], "y_cmd_mm": cmd[:, 1], "z_cmd_mm": cmd[:, 2],
        "err_nominal_mm": np.linalg.norm(meas - cmd, axis=1),
        "err_geometric_mm": np.linalg.norm(meas - geo, axis=1),
        "err_full_mm": np.linalg.norm(meas - full, axis=1),
    })


MODELS = ("nominal", "geometric", "full")


def error_stats(err: np.ndarray) -> dict[str, float]:
    err = np.asarray(err, float)
    return {"mean_mm": float(err.mean()), "rms_mm": float(np.sqrt(np.mean(err**2))),
            "p95_mm": float(np.percentile(err, 95)), "max_mm": float(err.max()),
            "n_points": int(err.size)}


def accuracy_table(points: pd.DataFrame) -> pd.DataFrame:
    """``model, mean_mm, rms_mm, p95_mm, max_mm, n_points`` for nominal, geometric, full."""
    return pd.DataFrame([{"model": m, **error_stats(points[f"err_{m}_mm"])} for m in MODELS])


def workspace_regions(points: pd.DataFrame, reach_edges_mm: Sequence[float],
                      height_edges_mm: Sequence[float]) -> pd.Series:
    """Region label per point from the commanded reach (distance from the base z axis) and
    height: ``reach<800/z<400`` style labels."""
    reach = np.hypot(points["x_cmd_mm"], points["y_cmd_mm"])

    def label(v, edges, name):
        edges = list(edges)
        k = np.searchsorted(edges, v, side="right")
        names = ([f"{name}<{edges[0]:g}"] if edges else []) + \
            [f"{name}{a:g}-{b:g}" for a, b in zip(edges[:-1], edges[1:], strict=True)] + \
            ([f"{name}>={edges[-1]:g}"] if edges else [f"{name}:all"])
        return np.array(names)[k]

    return pd.Series(np.char.add(np.char.add(label(reach, reach_edges_mm, "reach"), "/"),
                                 label(points["z_cmd_mm"].to_numpy(), height_edges_mm, "z")),
                     index=points.index, name="region")


def accuracy_by_region(points: pd.DataFrame, regions: pd.Series) -> pd.DataFrame:
    """Accuracy statistics per workspace region and model."""
    rows = []
    for reg, g in points.groupby(regions):
        for m in MODELS:
            rows.append({"region": reg, "model": m, **error_stats(g[f"err_{m}_mm"])})
    return pd.DataFrame(rows)


def improvement_ratios(accuracy: pd.DataFrame, *, baseline: str = "nominal") -> pd.Series:
    """How many times smaller each model's RMS positioning error is than ``baseline``'s.

    Parameters
    ----------
    accuracy
        ``results/calibration/accuracy.csv`` indexed by ``model`` (column ``rms_mm``).

    Returns
    -------
    pandas.Series
        Per model ``rms_baseline / rms_model`` (1 for the baseline itself).
    """
    rms = accuracy["rms_mm"].astype(float)
    return float(rms.loc[baseline]) / rms


def region_table(regions: pd.DataFrame,
                 models: Sequence[str] = ("nominal", "geometric", "full")) -> pd.DataFrame:
    """RMS positioning error [mm] per workspace region (rows) and model (columns), with the
    number of validation points per region.

    Parameters
    ----------
    regions
        ``results/calibration/accuracy_by_region.csv`` (``region, model, rms_mm,
        n_points``, long form).
    models
        The model columns, in order (models absent from ``regions`` are left out).
    """
    tab = regions.pivot_table(index="region", columns="model", values="rms_mm")
    tab = tab[[m for m in models if m in tab.columns]]
    tab["n_points"] = regions.groupby("region")["n_points"].first()
    return tab
