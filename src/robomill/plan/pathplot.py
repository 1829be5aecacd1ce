"""What a programmer looks at before running the program (chapter 7): each planned cut's path
on the part, and its six joint angles along every move target against the cell's joint
limits, the request's limit margin, and the wrist angle against the smallest one allowed
(``results/plan/next/program/stations.csv``; :mod:`robomill.plan.motion` names the moves)."""

from __future__ import annotations

import numpy as np
import pandas as pd

MOVE_STYLE = {"safe_in": "^", "approach": "v", "entry": "s", "cut": "o", "retract": "v",
              "safe_out": "^"}


def path_figure(stations: pd.DataFrame, block_min_mm=None, block_max_mm=None):
    """The cuts' TCP paths in the part's x–y plane (every move target, the block's outline
    when the work object states one) and their height above the part's origin along the
    targets."""
    import matplotlib.pyplot as plt

    fig, (ax, az) = plt.subplots(1, 2, figsize=(10, 4))
    if block_min_mm is not None and block_max_mm is not None:
        lo, hi = np.asarray(block_min_mm, float), np.asarray(block_max_mm, float)
        ax.plot([lo[0], hi[0], hi[0], lo[0], lo[0]], [lo[1], lo[1], hi[1], hi[1], lo[1]], "k-",
                lw=0.8, label="block")
    for cut, st in stations.groupby("cut", sort=False):
        line, = ax.plot(st["x_part_mm"], st["y_part_mm"], "-", lw=1, label=str(cut))
        az.plot(np.arange(len(st)), st["z_part_mm"], "-", color=line.get_color(), lw=1,
                label=str(cut))
        for move, marker in MOVE_STYLE.items():
            sel = st[st["move"] == move]
            ax.plot(sel["x_part_mm"], sel["y_part_mm"], marker, color=line.get_color(), ms=3)
            az.plot(np.flatnonzero(st["move"].to_numpy() == move), sel["z_part_mm"], marker,
                    color=line.get_color(), ms=3)
    ax.set_xlabel("x in the part frame [mm]")
    ax.set_ylabel("y in the part frame [mm]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7)
    az.axhline(0.0, color="k", lw=0.6)
    az.set_xlabel("move target (safe ▲, approach/retract ▼, ramp ■, cut ●)")
    az.set_ylabel("z in the part frame [mm]")
    fig.tight_layout()
    return fig


def joints_figure(stations: pd.DataFrame, limits_deg=None, margin_deg: float = 0.0,
                  min_wrist_angle_deg: float | None = None):
    """Each joint's angle [deg] along every cut's move targets, the joint limits (solid) and
    the limits less ``margin_deg`` (dashed); a seventh panel the wrist angle at the cut's
    stations against ``min_wrist_angle_deg``."""
    import matplotlib.pyplot as plt

    n = sum(c.startswith("q") and c.endswith("_deg") for c in stations.columns)
    fig, axes = plt.subplots(2, 4, figsize=(12, 5.5), sharex=True)
    axes = axes.ravel()
    for cut, st in stations.groupby("cut", sort=False):
        x = np.arange(len(st))
        for j in range(n):
            axes[j].plot(x, st[f"q{j + 1}_deg"], ".-", lw=0.8, ms=3, label=str(cut))
        if "wrist_angle_deg" in st:
            axes[n].plot(x, st["wrist_angle_deg"], ".-", lw=0.8, ms=3, label=str(cut))
    for j in range(n):
        axes[j].set_title(f"joint {j + 1} [deg]", fontsize=9)
        if limits_deg is not None:
            lo, hi = np.asarray(limits_deg, float)[j]
            for v in (lo, hi):
                axes[j].axhline(v, color="r", lw=0.8)
            for v in (lo + margin_deg, hi - margin_deg):
                axes[j].axhline(v, color="r", lw=0.8, ls="--")
    axes[n].set_title("wrist angle [deg]", fontsize=9)
    if min_wrist_angle_deg is not None:
        axes[n].axhline(min_wrist_angle_deg, color="r", lw=0.8, ls="--")
    axes[n].legend(fontsize=7)
    for ax in axes[n + 1:]:
        ax.axis("off")
    for ax in axes[: n + 1]:
        ax.tick_params(labelsize=7)
        ax.set_xlabel("move target", fontsize=8)
    fig.tight_layout()
    return fig
