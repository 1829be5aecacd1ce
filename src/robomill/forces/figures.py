"""Chapter 3.1's figures, drawn from the forces stage's artefacts (each function returns the
figure; the chapter saves, shows and captions it): the model's force shape (eq. 3.1, thesis
Fig 3.2), a record (Fig 3.3) and its full-band spectrum (Fig 3.4), the low-band spectra per
feed direction in spatial and in time frequency (Figs 3.5–3.10), and the mean forces against
the feed per tooth (Fig 3.11)."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr

from robomill.forces.tables import direction_text

AXES = ("Fx", "Fy", "Fz")


def model_shape_figure(spectra: xr.Dataset) -> plt.Figure:
    """The model's forces on the tool over two revolutions (``model_force`` against
    ``model_angle``; eq. 3.1 at the dataset's ``model_feed_per_tooth_mm`` and
    ``model_depth_mm``)."""
    fig, ax = plt.subplots()
    ang = spectra["model_angle"].values
    for i, lab in enumerate(["F_x (feed)", "F_y (cross-feed)", "F_z (axial)"]):
        ax.plot(ang, spectra["model_force"].values[:, i], label=lab, lw=2 if i == 2 else 1)
    ax.set_xlabel("rotation angle of tooth 1 [deg]")
    ax.set_ylabel("force on the tool [N]")
    ax.set_title(f"Eq. 3.1, c = {spectra.attrs['model_feed_per_tooth_mm'] * 1e3:.2f} µm, "
                 f"a = {spectra.attrs['model_depth_mm']:.2f} mm")
    ax.legend()
    return fig


def record_figure(spectra: xr.Dataset, cut: str) -> plt.Figure:
    """(a) The whole record of ``cut`` as a min–max envelope per axis, (b) the raw excerpt
    from its middle."""
    d = spectra.sel(cut=cut)
    fig, axs = plt.subplots(1, 2, figsize=(11, 4))
    for a in AXES:
        axs[0].fill_between(d["envelope_t"], d["envelope_min"].sel(axis=a),
                            d["envelope_max"].sel(axis=a), alpha=0.5, label=a)
        axs[1].plot(d["excerpt_t"] * 1e3, d["excerpt"].sel(axis=a), lw=0.8, label=a)
    axs[0].set_xlabel("t [s]")
    axs[0].set_ylabel("force [N] (min–max envelope)")
    axs[0].set_title(f"(a) {cut}: whole record")
    axs[1].set_xlabel("t [ms]")
    axs[1].set_title("(b) zoom, middle of the record")
    axs[0].legend()
    return fig


def full_band_figure(spectra: xr.Dataset, cut: str) -> plt.Figure:
    """The Welch PSD of ``cut`` summed over the axes, over the full band."""
    f = spectra["frequency"].values
    fig, ax = plt.subplots()
    ax.semilogy(f / 1e3, spectra["psd"].sel(cut=cut).sum("axis").values, lw=0.7)
    ax.set_xlabel("frequency [kHz]")
    ax.set_ylabel("PSD, sum of axes [N²/Hz]")
    ax.set_title(f"{cut}, Welch PSD over the full band")
    return fig


def direction_figure(spectra: xr.Dataset, cuts: Sequence[str], direction: str, *,
                     spatial: bool, x_max: float, vlines: Sequence[float] = (),
                     which: str = "") -> plt.Figure | None:
    """The low-band power (summed over the axes) of the ``cuts`` fed along ``direction``, one
    panel per cut: against the spatial frequency f/v up to ``x_max`` [1/mm] (``spatial``) or
    the time frequency up to ``x_max`` [Hz]; dotted verticals at ``vlines``. ``None`` when no
    cut runs along ``direction``."""
    xkey = "f_spatial_low" if spatial else "f_low"
    cs = [c for c in cuts if str(spectra["direction"].sel(cut=c).item()) == direction]
    if not cs:
        return None
    fig, axs = plt.subplots(len(cs), 1, figsize=(7.5, 1.8 * len(cs) + 0.8), sharex=True,
                            squeeze=False)
    for ax, c in zip(axs[:, 0], cs, strict=True):
        d = spectra.sel(cut=c)
        x = d[xkey].values
        p = d["power_low"].sum("axis").values
        sel = np.isfinite(x) & (x > 0) & (x <= x_max)
        ax.plot(x[sel], p[sel], lw=0.8)
        for v in vlines:
            ax.axvline(v, color="0.6", ls=":", lw=0.8)
        ax.set_ylabel("P [N²]")
        ax.set_title(f"{c}: {float(d['feed_mm_s']):g} mm/s, tooth passing "
                     f"{float(d['tooth_passing_hz']):.0f} Hz", fontsize=9)
    axs[-1, 0].set_xlabel("spatial frequency f/v [1/mm]" if spatial else "frequency [Hz]")
    fig.suptitle(f"{'Spatial' if spatial else 'Time'}-frequency power, "
                 f"{direction_text(direction)}" + (f", {which}" if which else ""))
    return fig


def mean_forces_figure(process: pd.DataFrame) -> plt.Figure:
    """The mean forces of each cut in the cut frame divided by N·a (flutes × depth) against
    the feed per tooth, one marker series per depth (``process``: the mean-force table with
    each cut's ``flutes``, :func:`robomill.forces.tables.process_table`)."""
    fig, axs = plt.subplots(1, 3, figsize=(12, 3.6))
    for ax, comp, lab in zip(axs, ["F_cross_feed_N", "F_feed_N", "F_axial_N"],
                             ["F̄_y/(Na) (tangential)", "F̄_x/(Na) (radial)",
                              "F̄_z/(Na) (axial)"], strict=True):
        for depth, g in process.groupby("depth_mm"):
            ax.plot(g["feed_per_tooth_mm"] * 1e3, g[comp] / (g["flutes"] * depth), "o", ms=4,
                    label=f"a = {depth:g} mm")
        ax.set_xlabel("feed per tooth c [µm]")
        ax.set_title(lab, fontsize=10)
    axs[0].set_ylabel("N/mm")
    axs[0].legend()
    return fig
