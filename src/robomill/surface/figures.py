"""Chapter 2's figures, drawn from the surface artefacts (``profiles.nc``, ``spectra.nc``,
``metrics.csv``, ``peaks.csv``): each function returns a matplotlib figure and computes
nothing the chapter states (the cuts shown come from :mod:`robomill.surface.tables` and the
findings). Importing this module loads matplotlib (:mod:`robomill.plotting`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import pandas as pd
import xarray as xr

from robomill.plotting import plt
from robomill.surface.tables import path_label, with_directions

PROFILE_OFFSET_UM = 15.0
"""Vertical offset between the stacked profiles of one figure [µm]."""


def _xlabels(axs, label: str = "x [mm]") -> None:
    for ax in axs:
        ax.set_xlabel(label)


def detrend_figure(profiles: xr.Dataset, cut: str):
    """A measured profile and the same profile detrended (stylus tilt removed)."""
    p = profiles.sel(cut=cut)
    fig, ax = plt.subplots()
    ax.plot(p.x, p.z_measured, lw=0.6, label="measured")
    ax.plot(p.x, p.z, lw=0.6, label="detrended")
    _xlabels([ax])
    ax.set_ylabel("z [µm]")
    ax.set_title(f"Profile of {cut}")
    ax.legend()
    return fig


def waviness_figure(profiles: xr.Dataset, cut: str, lambda_c_mm: float):
    """The detrended profile and its waviness (ISO 16610-21 Gaussian filter)."""
    p = profiles.sel(cut=cut)
    fig, ax = plt.subplots()
    ax.plot(p.x, p.z, lw=0.5, color="0.6", label="detrended")
    ax.plot(p.x, p.waviness, lw=1.2, label=f"waviness (λc = {lambda_c_mm:g} mm)")
    _xlabels([ax])
    ax.set_ylabel("z [µm]")
    ax.legend()
    return fig


def roughness_feed_figure(profiles: xr.Dataset, cuts: Sequence[str], length_mm: float = 1.0):
    """The roughness over the first ``length_mm`` of each of ``cuts``, one panel each."""
    fig, axs = plt.subplots(len(cuts), 1, sharex=True, sharey=True, squeeze=False)
    for ax, c in zip(axs[:, 0], cuts, strict=True):
        p = profiles.sel(cut=c)
        m = p.x <= p.x[0] + length_mm
        ax.plot(p.x[m], p.roughness[m], lw=0.7)
        ax.set_title(f"{c}: feed {float(p.feed_mm_s):g} mm/s", fontsize=9)
        ax.set_ylabel("roughness [µm]")
    _xlabels([axs[-1, 0]])
    return fig


def profiles_figure(profiles: xr.Dataset, rows: pd.DataFrame, title: str, per_feed: bool):
    """The profiles of ``rows`` stacked ``PROFILE_OFFSET_UM`` apart (one per feed of a set in
    the thesis layout, every cut of a direction otherwise)."""
    fig, ax = plt.subplots()
    for k, r in enumerate(rows.itertuples()):
        ax.plot(profiles.x, profiles.sel(cut=r.cut).z + PROFILE_OFFSET_UM * k, lw=0.5,
                label=f"{r.feed_mm_s:g} mm/s" if per_feed else f"{r.cut}: {r.feed_mm_s:g} mm/s")
    _xlabels([ax])
    ax.set_ylabel(f"z [µm] (offset {PROFILE_OFFSET_UM:g} µm per "
                  + ("feed)" if per_feed else "cut)"))
    ax.set_title(title)
    ax.legend(fontsize=7, ncol=5)
    return fig


def spectrum_figure(spectra: xr.Dataset, cut: str, settings: Mapping[str, Any]):
    """The normalized amplitude spectrum A(k) of one cut (eq. 2.1), waviness and roughness
    ranges (``surface.waviness_plot_max_per_mm``, ``roughness_plot_max_per_mm``)."""
    s = spectra.sel(cut=cut)
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.6))
    axs[0].plot(s.f, s.amplitude, lw=0.8)
    axs[0].set_xlim(0, settings["waviness_plot_max_per_mm"])
    axs[1].plot(s.f, s.amplitude, lw=0.6)
    axs[1].set_xlim(0, settings["roughness_plot_max_per_mm"])
    axs[1].set_ylim(0, float(s.amplitude.where(s.f > 2).max()) * 1.2)
    _xlabels(axs, "spatial frequency [mm⁻¹]")
    axs[0].set_ylabel("A(k) [µm]")
    fig.suptitle(f"Normalized amplitude spectrum of {cut}")
    return fig


def spectra_figure(spectra: xr.Dataset, rows: Mapping[str, pd.DataFrame], title: str,
                   settings: Mapping[str, Any], per_feed: bool):
    """P(k) of the cuts in ``rows`` (direction → cuts), waviness left, roughness right
    (eq. 2.2)."""
    fig, axs = plt.subplots(len(rows), 2, figsize=(10, 2.5 * len(rows) + 0.5), sharex="col",
                            squeeze=False)
    for i, (d, cs) in enumerate(rows.items()):
        for r in cs.itertuples():
            sp = spectra.sel(cut=r.cut)
            axs[i, 0].plot(sp.f, sp.power, lw=0.7,
                           label=f"{r.feed_mm_s:g} mm/s" if per_feed else f"{r.cut}")
            axs[i, 1].plot(sp.f, sp.power, lw=0.5)
        axs[i, 0].set_xlim(0, settings["waviness_plot_max_per_mm"])
        axs[i, 1].set_xlim(2, settings["roughness_plot_max_per_mm"])
        axs[i, 1].set_yscale("log")
        axs[i, 0].set_ylabel(f"{path_label(d)}: P(k) [µm²]")
        axs[i, 0].legend(fontsize=6)
    _xlabels(axs[-1], "spatial frequency [mm⁻¹]")
    fig.suptitle(title)
    return fig


def rms_vs_feed_figure(metrics: pd.DataFrame):
    """Waviness and roughness RMS (segment method) against feed, by direction."""
    m = with_directions(metrics)
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.6))
    for _, g in m.groupby("direction"):
        axs[0].plot(g.feed_mm_s, g.waviness_rms_um, "o", label=g["label"].iloc[0])
        axs[1].plot(g.feed_mm_s, g.roughness_rms_um, "o", label=g["label"].iloc[0])
    axs[0].set_ylabel("waviness RMS [µm]")
    axs[1].set_ylabel("roughness RMS [µm]")
    _xlabels(axs, "feed [mm/s]")
    for ax in axs:
        ax.legend()
    return fig


def peak_mechanisms_figure(peaks: pd.DataFrame):
    """Spatial and temporal frequency of every peak against feed, by mechanism."""
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.6))
    for mech, g in peaks.groupby("mechanism"):
        axs[0].plot(g.feed_mm_s, g.f_spatial_per_mm, "o", ms=4, label=mech)
        axs[1].plot(g.feed_mm_s, g.f_temporal_hz, "o", ms=4, label=mech)
    for ax, label in zip(axs, ("spatial frequency [mm⁻¹]", "temporal frequency [Hz]"),
                         strict=True):
        ax.set_yscale("log")
        ax.set_ylabel(label)
        ax.set_xlabel("feed [mm/s]")
        ax.legend(fontsize=7)
    return fig


def areal_psd_figure(spectra: xr.Dataset):
    """Areal scans (``areal_spectra.nc``): the radially averaged areal PSD of every scan
    (left) and its PSDs along and across the feed (right), log-log."""
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.6))
    for cut in spectra.cut.values:
        s = spectra.sel(cut=cut)
        r = s.psd_radial.dropna("k_radial")
        axs[0].loglog(r.k_radial[1:], r[1:], lw=0.8, label=str(cut))
        for name, style in (("along", "-"), ("across", "--")):
            v = s[f"psd_{name}"].dropna(f"k_{name}")
            line, = axs[1].loglog(v[f"k_{name}"][1:], v[1:], style, lw=0.8,
                                  label=f"{cut}, {name} the feed")
    axs[0].set_ylabel("C(|k|) [µm² mm²]")
    axs[1].set_ylabel("P(k) [µm² mm]")
    _xlabels(axs, "spatial frequency [mm⁻¹]")
    for ax in axs:
        ax.legend(fontsize=7)
    axs[0].set_title("radially averaged", fontsize=9)
    axs[1].set_title("along (—) and across (--) the feed", fontsize=9)
    return fig
