"""Chapter 5's tables: the stage's artefacts beside the seed's numbers of its findings
(:mod:`robomill.stiffness.findings`), in the units the chapter prints (kN·m/rad, N/µm).
Display only: every number a sentence states is a finding."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

_N_UM = 1e6  # N/m per N/µm
_RANGES = (("X (3-D)", "x"), ("Y (3-D)", "y"), ("Z (3-D)", "z"),
           ("X (X–Z plane)", "xz_plane_x"), ("Z (X–Z plane)", "xz_plane_z"))


def workspace_table(found: Mapping[str, Any]) -> pd.DataFrame:
    """The workspace ranges, the seed's beside ours [mm], from the findings' values
    (``workspace_<range>_mm`` and ``seed_workspace_<range>_mm``)."""
    rows = [(label, *found[f"seed_workspace_{key}_mm"], *found[f"workspace_{key}_mm"])
            for label, key in _RANGES]
    return pd.DataFrame(rows, columns=["range", "seed min mm", "seed max mm", "ours min mm",
                                       "ours max mm"])


def joints_table(joints: pd.DataFrame, models: pd.DataFrame,
                 found: Mapping[str, Any]) -> pd.DataFrame:
    """Identified joint stiffness [kN·m/rad] with its 95 % interval, per model (``cube``,
    ``plane`` of ``identification.csv``), beside the seed's 3-D and plane values and the
    planted values where the findings have them."""
    tab = joints[["joint", "observable"]].copy()
    tab["k kN·m/rad"] = joints["k_Nm_rad"] / 1e3
    tab["95 % CI kN·m/rad"] = [f"{lo / 1e3:.4g} … {hi / 1e3:.4g}" for lo, hi in
                               zip(joints["ci95_low_Nm_rad"], joints["ci95_high_Nm_rad"],
                                   strict=True)]
    by_model = models.set_index("model")
    for name in ("cube", "plane"):
        if name in by_model.index:
            tab[f"{name} kN·m/rad"] = [by_model.loc[name, f"k{j}_Nm_rad"] / 1e3
                                       for j in tab["joint"]]
    n = len(tab)
    for col, key in (("seed 3-D kN·m/rad", "seed_k3d_kNm_rad"),
                     ("seed plane kN·m/rad", "seed_k_plane_kNm_rad"),
                     ("planted kN·m/rad", "planted_k_kNm_rad")):
        values = list(found.get(key) or [])
        if values:
            tab[col] = (values + [np.nan] * n)[:n]
    return tab


def validation_table(validation: pd.DataFrame, found: Mapping[str, Any]) -> pd.DataFrame:
    """Mean absolute error [%] of the predicted deflection per model, beside the seed's
    (``cube``: 3-D identification, ``plane``)."""
    v = validation.groupby("model")[["error_pct", "vector_error_pct"]].agg(
        lambda s: np.abs(s).mean())
    seed = {"cube": found.get("seed_validation_cube_pct"),
            "plane": found.get("seed_validation_plane_pct")}
    v["seed error %"] = [seed.get(m, np.nan) for m in v.index]
    return v.astype(float)


def maxima_table(maps: xr.Dataset, found: Mapping[str, Any]) -> pd.DataFrame:
    """Largest directional stiffness [N/µm] per height and redundancy angle, beside the
    seed's printed Y maxima (N/m as printed) where it gives one for that angle."""
    mx = maps["k_N_m"].max(dim=("x", "y")).to_dataframe().reset_index().pivot_table(
        index=["height_mm", "redundancy_deg"], columns="axis", values="k_N_m") / _N_UM
    mx.columns = [f"max k_{c} N/µm" for c in mx.columns]
    seed = dict(zip(found.get("seed_y_redundancy_deg") or [],
                    found.get("seed_y_max_N_m") or [], strict=True))
    mx["seed max k_Y (printed N/m)"] = [seed.get(float(r), np.nan) for _, r in mx.index]
    return mx


def cut_stiffness_um(cut_stiffness: pd.DataFrame) -> tuple[pd.DataFrame, list[str]]:
    """``cut_stiffness.csv`` with its stiffness columns also in N/µm (``k feed N/µm``, …), and
    the names of those columns."""
    cols = {f"k_{a}_N_m": f"k {a} N/µm" for a in ("feed", "normal", "axial")}
    out = cut_stiffness.assign(**{n: cut_stiffness[c] / _N_UM for c, n in cols.items()})
    return out, list(cols.values())


def slot_means_um(slots: pd.DataFrame) -> pd.DataFrame:
    """Mean stiffness [N/µm] of both models in series (``model = combined``) per slot
    direction, along the feed, the normal and the tool axis (the chapter's bar chart)."""
    c = slots[slots["model"] == "combined"].groupby("direction")[
        ["k_feed_N_m", "k_normal_N_m", "k_axial_N_m"]].mean() / _N_UM
    c.columns = ["feed", "normal", "axial"]
    return c
