"""Chapter 3.2's figures, drawn from the straightness stage's artefacts (each function returns
the figure; the chapter saves, shows and captions it): the deviation from the best line along
each path direction at every feed (thesis Figs 3.12, 3.14), its power spectrum with the peaks
found (Figs 3.13, 3.15, 3.16) and the peaks by mechanism against the feed (Fig 3.17); and the
numbers and file names of the figures for the study's directions (:func:`figure_numbers`)."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr

from robomill.straightness.tables import direction_text

MECHANISM_MARKERS = {"gear": "v", "temporal": "o", "spatial": "s", "unclassified": "x"}
"""The marker of each peak mechanism in :func:`mechanism_figure`."""

THESIS_FIGURES = {"py": (12, 13), "my": (14, 15), "px": (18, 19)}
"""The thesis' figure numbers of the deviation and the spectrum of each direction (±Y:
Figs 3.12–3.15; the +X runs, not in the thesis, numbered after its figures)."""


def figure_numbers(directions: Sequence[str], thesis_layout: bool
                   ) -> dict[str, tuple[int, str, str]]:
    """``number, part, file stem`` of the figures ``deviation_<d>`` and ``psd_<d>`` of every
    direction ``d``: the thesis' numbers (:data:`THESIS_FIGURES`) in its layout, else Figs
    3.12 and 3.13 with one part per direction (a, b, …; none for a single direction)."""
    out = {}
    for k, d in enumerate(directions):
        name = d.replace(" ", "")
        if thesis_layout:
            n_dev, n_psd = THESIS_FIGURES[d]
            x = "x" if d == "px" else ""
            out[f"deviation_{d}"] = (n_dev, "", f"fig3_{n_dev - 6 if x else n_dev}{x}"
                                                f"_deviation_{d}")
            out[f"psd_{d}"] = (n_psd, "", f"fig3_{n_psd - 6 if x else n_psd}{x}_psd_{d}")
        else:
            part = "abcdefghijklmnopqrstuvwxyz"[k] if len(directions) > 1 else ""
            out[f"deviation_{d}"] = (12, part, f"fig3_12{part}_deviation_{name}")
            out[f"psd_{d}"] = (13, part, f"fig3_13{part}_psd_{name}")
    return out


def runs_of(profiles: xr.Dataset, direction: str) -> list[str]:
    """The runs (ids, the join key) of ``direction``, slowest feed first."""
    runs = pd.DataFrame({"direction": profiles["direction"].values.astype(str),
                         "feed_mm_s": profiles["feed_mm_s"].values.astype(float)},
                        index=profiles["run"].values)
    return list(runs[runs["direction"] == direction]
                .sort_values("feed_mm_s", kind="stable").index)


def deviation_figure(profiles: xr.Dataset, direction: str, *,
                     mean_mm: float = 0.1) -> plt.Figure:
    """The deviation from the best line of every run along ``direction``, one panel per feed:
    each component thin, and its running mean over ``mean_mm`` bold."""
    ids = runs_of(profiles, direction)
    fig, axes = plt.subplots(len(ids), 1, figsize=(7.5, 1.6 * len(ids) + 0.6), sharex=True,
                             squeeze=False)
    for ax, r in zip(axes[:, 0], ids, strict=True):
        ds = profiles.sel(run=r)
        step = float(ds.attrs.get("ds_mm", profiles.s[1] - profiles.s[0]))
        n_avg = max(1, int(round(mean_mm / step)))
        for k, comp in enumerate(ds.component.values):
            y = ds.deviation_um.sel(component=comp).values
            ax.plot(ds.s, y, lw=0.3, alpha=0.35, color=f"C{k}")
            smooth = np.convolve(np.nan_to_num(y), np.ones(n_avg) / n_avg, mode="same")
            ax.plot(ds.s, np.where(np.isfinite(y), smooth, np.nan), lw=0.9, color=f"C{k}",
                    label=f"{comp} ({mean_mm:g} mm mean)")
        ax.set_ylabel("µm")
        ax.set_title(f"feed {float(ds.feed_mm_s):g} mm/s", fontsize=9, loc="left")
    axes[0, 0].legend(ncol=2, fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel("distance along the path s [mm]")
    fig.suptitle(f"Deviation from the best line, path {direction_text(direction)}")
    return fig


def psd_figure(profiles: xr.Dataset, peaks: pd.DataFrame, direction: str, *,
               fmax_per_mm: float = 1.0,
               title: str = "power spectrum of the motion") -> plt.Figure:
    """The power spectrum of every run along ``direction`` up to ``fmax_per_mm`` (default
    1 mm⁻¹: the gear lines' band, thesis Figs 3.13, 3.15), one line per feed, with its peaks
    (``peaks.csv`` joined by ``run``; power A²/2): ▼ a gear peak, ● any other."""
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for k, r in enumerate(runs_of(profiles, direction)):
        ds = profiles.sel(run=r)
        keep = ds.f <= fmax_per_mm
        ax.semilogy(ds.f[keep], ds.power_um2.where(keep, drop=True), lw=0.7,
                    label=f"{float(ds.feed_mm_s):g} mm/s", color=f"C{k}")
        mine = peaks[(peaks["run"].astype(str) == str(r))
                     & (peaks["f_spatial_per_mm"] <= fmax_per_mm)]
        for p in mine.itertuples():
            ax.plot(p.f_spatial_per_mm, p.amplitude_um**2 / 2,
                    "v" if p.mechanism == "gear" else "o", color=f"C{k}", ms=5)
    ax.set_xlabel("spatial frequency [mm⁻¹]")
    ax.set_ylabel("power [µm²]")
    ax.set_xlim(0, fmax_per_mm)
    ax.set_ylim(bottom=max(1e-6, float(profiles.floor_um2.min()) / 10))
    ax.legend(fontsize=8, ncol=2)
    ax.set_title(f"{title}, path {direction_text(direction)} (▼ gear, ● other peak)")
    return fig


def mechanism_figure(peaks: pd.DataFrame, feeds_mm_s: Sequence[float]) -> plt.Figure:
    """Every peak's spatial (left) and temporal (right) frequency against the feed, by
    mechanism (:data:`MECHANISM_MARKERS`); with temporal peaks, their median temporal
    frequency f_t dotted (f_t / v on the left)."""
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    for mech, mk in MECHANISM_MARKERS.items():
        sel = peaks[peaks["mechanism"] == mech]
        axes[0].plot(sel.feed_mm_s, sel.f_spatial_per_mm, mk, label=mech, ms=5)
        axes[1].plot(sel.feed_mm_s, sel.f_temporal_hz, mk, label=mech, ms=5)
    temporal = peaks[peaks["mechanism"] == "temporal"]
    if len(temporal):
        v = np.linspace(min(feeds_mm_s), max(feeds_mm_s), 50)
        f_t = float(temporal["f_temporal_hz"].median())
        axes[0].plot(v, f_t / v, "k:", lw=0.8, label=f"{f_t:.2f} Hz / v")
        axes[1].axhline(f_t, color="k", ls=":", lw=0.8)
    for ax, what in zip(axes, ("spatial frequency [mm⁻¹]", "temporal frequency [Hz]"),
                        strict=True):
        ax.set_yscale("log")
        ax.set_xlabel("feed [mm/s]")
        ax.set_ylabel(what)
    axes[0].legend(fontsize=8)
    fig.suptitle("Peaks by mechanism: spatial and temporal frequency vs feed")
    fig.tight_layout()
    return fig
