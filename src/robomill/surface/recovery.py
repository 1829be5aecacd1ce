"""Recovery of the planted surface (synthetic runs only): planted vs recovered segment RMS."""

from __future__ import annotations

import pandas as pd
import xarray as xr


def recovery_table(metrics: pd.DataFrame, truth: xr.Dataset) -> pd.DataFrame:
    """Planted (``truth.nc``: ``surface_planted_*``) vs recovered segment RMS per cut."""
    t = truth[["surface_planted_waviness_rms_um", "surface_planted_roughness_rms_um"]]
    t = t.to_dataframe().reset_index().rename(columns={"surface_cut": "cut"})
    df = metrics[["cut", "waviness_rms_um", "roughness_rms_um"]].merge(t, on="cut")
    df["waviness_ratio"] = df["waviness_rms_um"] / df["surface_planted_waviness_rms_um"]
    df["roughness_ratio"] = df["roughness_rms_um"] / df["surface_planted_roughness_rms_um"]
    return df.rename(columns={"surface_planted_waviness_rms_um": "planted_waviness_rms_um",
                              "surface_planted_roughness_rms_um": "planted_roughness_rms_um"})
