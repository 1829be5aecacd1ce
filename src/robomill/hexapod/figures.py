"""Chapter 6's figures and tables: the acceleration programme and its open-loop replay, the
actuator forces, the vertical move with a force error, the drift map; the seed's Table 1 and
the vertical move beside the seed's, from the findings (:mod:`robomill.hexapod.findings`).
Each figure function draws one figure from the stage's artefacts and returns it; the chapter
saves and shows it."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr

VERTICAL_ROWS = ("force, all actuators [N]", "force, actuator 1 [N]", "exact end x [mm]",
                 "exact end y [mm]", "exact end z [mm]", "perturbed end x [mm]",
                 "perturbed end y [mm]", "perturbed end z [mm]", "ψ [deg]", "θ [deg]", "φ [deg]")


def trajectory_figure(traj: xr.Dataset):
    """The programme's position (command and open-loop replay, dashed) and the round-trip
    error on a log scale, with the growth e^(λt) of the largest instability rate."""
    t = traj["time"].values
    pos, rep = traj["position_mm"], traj["replay_position_mm"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax_name, c in zip("xyz", ["C0", "C1", "C2"], strict=True):
        p0 = float(pos.sel(axis=ax_name)[0])
        axes[0].plot(t, pos.sel(axis=ax_name) - p0, c, label=f"{ax_name} − {p0:.1f} (command)")
        axes[0].plot(t, rep.sel(axis=ax_name) - p0, c + "--", lw=2.5, alpha=0.6)
    axes[0].axvline(float(traj["replay_hold_s"]), color="k", lw=0.8)
    axes[0].set(xlabel="t [s]", ylabel="displacement [mm]",
                title="platform position (dashed: open-loop replay)")
    axes[0].legend()
    err = traj["replay_error_mm"].values
    axes[1].semilogy(t, err, "k")
    axes[1].axhline(float(traj["replay_tolerance_mm"]), color="r", lw=0.8)
    lam = float(np.max(traj["instability_rate_per_s"].values))
    t0 = t[np.isfinite(err) & (err > 0)]
    if t0.size:
        e_end = float(traj["replay_error_mm"].sel(time=t0[-1]))
        axes[1].semilogy(t0, e_end * np.exp(lam * (t0 - t0[-1])), "C3:",
                         label=f"e^(λt), λ = {lam:.1f} 1/s")
        axes[1].legend()
    axes[1].set(xlabel="t [s]", ylabel="|replay − command| [mm]", title="round-trip error")
    return fig


def forces_figure(frc: xr.Dataset):
    """The actuator forces of the programme (inverse dynamics) and the closed-form static
    force (dotted)."""
    fig, ax = plt.subplots()
    for a in frc["actuator"].values:
        ax.plot(frc["time"], frc["force_N"].sel(actuator=a), label=f"actuator {a}")
    ax.axhline(float(frc["static_force_N"]), color="k", lw=0.8, ls=":",
               label="static, closed form")
    ax.set(xlabel="t [s]", ylabel="Γ [N]",
           title="Inverse dynamics: actuator forces along the programme")
    ax.legend(ncol=2, fontsize=8)
    return fig


def vertical_figure(traj: xr.Dataset):
    """The vertical move with exact forces and with the perturbed actuator: height, drift
    and the Euler angles."""
    tv = traj["time_vertical"].values
    ex, pe = traj["vertical_exact_mm"], traj["vertical_perturbed_mm"]
    eul = traj["vertical_perturbed_euler_deg"]
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    axes[0].plot(tv, ex.sel(axis="z"), "k", label="exact forces")
    axes[0].plot(tv, pe.sel(axis="z"), "C3", label="perturbed actuator")
    axes[0].set_ylabel("z [mm]")
    for a in "xyz":
        axes[1].plot(tv, pe.sel(axis=a) - ex.sel(axis=a), label=a)
    axes[1].set_ylabel("drift [mm]")
    for a in eul["angle"].values:
        axes[2].plot(tv, eul.sel(angle=a), label=str(a))
    axes[2].set_ylabel("Euler angle [deg]")
    for ax in axes:
        ax.set_xlabel("t [s]")
        ax.legend()
    fig.suptitle("Vertical move: exact forces vs a force error in one actuator")
    return fig


def drift_map_figure(sens: xr.Dataset):
    """Final drift and tilt over force error × actuator (``sensitivity.nc``)."""
    e = sens["force_error_pct"].values
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, name, unit in ((axes[0], "drift_mm", "mm"), (axes[1], "tilt_deg", "deg")):
        im = ax.pcolormesh(e, sens["actuator"].values, sens[name].values, shading="nearest",
                           cmap="viridis")
        fig.colorbar(im, ax=ax, label=f"{name.split('_')[0]} [{unit}]")
        ax.set(xlabel="force error [%]", ylabel="actuator",
               title=f"final {name.split('_')[0]} after {sens.attrs['duration_s']:g} s")
    return fig


def _cell(value: Any) -> str:
    return f"{value[0]:g}–{value[1]:g}" if isinstance(value, list) else f"{value:g}"


def seed_table1(found: Mapping[str, Any]) -> pd.DataFrame:
    """[Rybak n.d., Table 1] (ball-end milling, conventional against high-speed) as printed,
    its numbers from the findings' ``seed_table1_*`` (references.yaml)."""
    rows = {"spindle speed [rpm]": "spindle_rpm", "feed [m/min]": "feed_m_min",
            "depth of cut [mm]": "depth_mm"}
    out = {kind: [_cell(found[f"seed_table1_{q}_{key}"]) for q in rows.values()]
           + [f"< {found[f'seed_table1_hardness_hrc_max_{key}']:g}"] + words
           for kind, key, words in (("conventional", "conventional", ["high", "high"]),
                                    ("high-speed", "high_speed", ["low", "low"]))}
    return pd.DataFrame(out, index=[*rows, "hardness [HRC]", "cutting force", "heat"])


def vertical_table(found: Mapping[str, Any]) -> pd.DataFrame:
    """The vertical move: the seed's printed numbers, ours and the difference (the
    findings' ``vertical_table_*``)."""
    return pd.DataFrame({"seed": found["vertical_table_seed"],
                         "ours": found["vertical_table_ours"],
                         "difference": found["vertical_table_difference"]},
                        index=list(VERTICAL_ROWS))
