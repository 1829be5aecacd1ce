"""Chapter 5's figures: the workspace, the directional-stiffness maps of one height, the
optimal against the random poses, the beam frame and the slot stiffness beside Table 2.1.
Each function draws one figure from the stage's artefacts and returns it; the chapter saves
and shows it."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr

from robomill.stiffness.tables import slot_means_um


def workspace_figure(maps: xr.Dataset):
    """X–Z projection of the Monte-Carlo workspace and the X–Z plane (``maps.nc``)."""
    ws, wxz = maps["workspace_mm"].values, maps["workspace_xz_mm"].values
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    axes[0].scatter(ws[:, 0], ws[:, 2], s=1, alpha=0.3)
    axes[0].set(xlabel="X [mm]", ylabel="Z [mm]", title="3-D workspace (X–Z projection)")
    axes[1].scatter(wxz[:, 0], wxz[:, 2], s=1, alpha=0.3, color="C1")
    axes[1].set(xlabel="X [mm]", ylabel="Z [mm]", title="X–Z plane (joints 1, 5, 6 at 0)")
    for ax in axes:
        ax.set_aspect("equal")
    return fig


def maps_figure(maps: xr.Dataset, height_mm: float):
    """Directional stiffness [N/µm] along the tool axes over the working plane at one
    height, one row per redundancy angle [Yi 2025, Fig. 11]."""
    red = maps["redundancy_deg"].values
    fig, axs = plt.subplots(len(red), 3, figsize=(11, 3.2 * len(red)), squeeze=False)
    for i, r in enumerate(red):
        for j, a in enumerate(["X", "Y", "Z"]):
            k = maps["k_N_m"].sel(height_mm=height_mm, redundancy_deg=r, axis=a).values / 1e6
            im = axs[i, j].pcolormesh(maps["x"], maps["y"], k, shading="nearest",
                                      cmap="viridis")
            axs[i, j].set_aspect("equal")
            axs[i, j].set_title(f"k_{a}, θr = {r:.0f}°", fontsize=9)
            fig.colorbar(im, ax=axs[i, j], label="N/µm")
    fig.suptitle(f"Directional stiffness along the tool axes, H = {height_mm:.0f} mm")
    fig.tight_layout()
    return fig


def optimal_figure(optimal: pd.DataFrame, found: Mapping[str, Any]):
    """Deformation under the end load per pose and height; dashed: the seed's optimum at
    the heights it gives one (the findings' ``seed_optimal_height_mm`` and
    ``seed_optimal_deformation_um``)."""
    seed_deformation_um = dict(zip(found.get("seed_optimal_height_mm") or [],
                                   found.get("seed_optimal_deformation_um") or [], strict=True))
    fig, ax = plt.subplots()
    for h, g in optimal.groupby("height_mm"):
        ax.plot(np.arange(len(g)), g["deformation_um"], "o-", label=f"H = {h:.0f} mm")
        if h in seed_deformation_um:
            ax.axhline(seed_deformation_um[h], ls="--", color=ax.lines[-1].get_color(), lw=0.8)
        ax.set_xticks(np.arange(len(g)), g["pose"], rotation=30)
    ax.set_ylabel("deformation under the end load [µm]")
    ax.set_title("Optimal vs random poses (dashed: seed's optimum)")
    ax.legend()
    return fig


def beamframe_figure(bf: xr.Dataset):
    """The beam nodes at t = 0, and the tool displacement with the predicted σ(t) (Cai 2015
    eq. 17)."""
    fig, axs = plt.subplots(1, 2, figsize=(11, 4))
    n = bf["node_m"].values
    axs[0].plot(n[:, 0], n[:, 2], "o-")
    for i, p in enumerate(n):
        axs[0].annotate(str(i + 1), (p[0], p[2]), fontsize=8)
    axs[0].set(xlabel="X [m]", ylabel="Z [m]", title="beam nodes at t = 0")
    axs[0].set_aspect("equal")
    axs[1].plot(bf["time"], bf["delta_sum_um"], label="δ_sum [µm]")
    ax2 = axs[1].twinx()
    ax2.plot(bf["time"], bf["sigma_pred"], color="C1", label="σ(t) predicted")
    axs[1].set(xlabel="t [s]", ylabel="δ_sum [µm]", title="tool displacement and σ(t), eq. 17")
    ax2.set_ylabel("σ(t)")
    fig.tight_layout()
    return fig


def slots_figure(slots: pd.DataFrame, found: Mapping[str, Any]):
    """The thesis robot's mean stiffness per slot direction (both models in series) beside
    the mean waviness RMS of Table 2.1 (the findings' ``waviness_<direction>_um``)."""
    c = slot_means_um(slots)
    fig, ax = plt.subplots()
    x = np.arange(len(c))
    for i, col in enumerate(c.columns):
        ax.bar(x + (i - 1) * 0.25, c[col], 0.25, label=col)
    ax.set_xticks(x, c.index)
    ax.set_ylabel("stiffness [N/µm]")
    ax2 = ax.twinx()
    ax2.plot(x, [found.get(f"waviness_{d}_um", np.nan) for d in c.index], "kD--",
             label="waviness RMS")
    ax2.set_ylabel("waviness RMS [µm]")
    ax.set_title("Thesis robot: stiffness per slot direction vs Table 2.1")
    ax.legend(loc="upper left")
    return fig
