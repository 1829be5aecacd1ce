"""Chapter 3.3's figures, drawn from the modal stage's artefacts (each function returns the
figure; the chapter saves, shows and captions it): the test and its hits (thesis Fig 3.18),
the grid of every measured FRF, the real part, imaginary part and coherence of one FRF
(Figs 3.20–3.28), the LSCF stabilization chart and the MAC matrix with the shapes."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr

STABILITY_STYLE = {"new": ("x", "0.7", "new"), "f": ("v", "tab:orange", "stable in f"),
                   "fd": ("s", "tab:blue", "stable in f, ζ"),
                   "stable": ("o", "tab:green", "stable in f, ζ, MAC")}
"""Marker, colour and legend of each pole status of ``stabilization.csv``."""


def measured_pairs(ds: xr.Dataset) -> list[tuple[str, str]]:
    """The (output, input) pairs whose FRF holds a finite value (the layout measured them)."""
    return [(o, i) for o in ds["output"].values.tolist() for i in ds["input"].values.tolist()
            if np.isfinite(ds["H"].sel(output=o, input=i).values[1:]).any()]


def _in_band(ds: xr.Dataset, band_hz: Sequence[float]) -> np.ndarray:
    f = ds["frequency"].values
    return (f >= band_hz[0]) & (f <= band_hz[1])


def _tool_drawing(ax: plt.Axes, tooltip_layout: bool) -> None:
    """The tool tip, the spindle, the accelerometer and the three hammer directions."""
    ax.add_patch(plt.Rectangle((-0.15, 0.0), 0.3, 1.6, color="0.6"))
    ax.add_patch(plt.Rectangle((-0.06, -0.9), 0.12, 0.9, color="0.3"))
    ax.add_patch(plt.Rectangle((0.08, -0.5), 0.25, 0.25, color="tab:orange"))
    ax.text(0.36, -0.38, "accelerometer", fontsize=8)
    for (dx, dy, lab) in [(-1.0, 0.0, "X"), (0.0, -1.0, "Z")]:
        ax.annotate("", xy=(-0.07 if dx else 0, -0.6 if dx else -0.95),
                    xytext=(dx - 0.07, -0.6 + dy if dx else -1.9),
                    arrowprops=dict(arrowstyle="->", lw=2, color="tab:red"))
        ax.text(dx - 0.3 if dx else 0.05, -0.5 if dx else -1.8, f"hammer {lab}",
                color="tab:red", fontsize=8)
    ax.plot(-0.55, -0.6, "o", ms=9, mfc="none", mec="tab:red")
    ax.text(-0.85, -0.95, "hammer Y (⊙)", color="tab:red", fontsize=8)
    ax.set_xlim(-1.4, 1.2)
    ax.set_ylim(-2.0, 1.8)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title("tool tip, spindle and hits" if tooltip_layout else
                 "the thesis' tool-tip test (for reference)")


def impact_test_figure(traces: xr.Dataset, hits: pd.DataFrame, *,
                       tooltip_layout: bool) -> plt.Figure:
    """The test drawing, and the force and accelerations of the first accepted hit and of
    every rejected one (``hits.nc``; trigger time and reason from ``hits.csv``)."""
    t = traces["time"].values
    accepted = [bool(a) for a in traces["accepted"].values]
    show = [i for i, a in enumerate(accepted) if a][:1] + [
        i for i, a in enumerate(accepted) if not a]
    by_path = hits.set_index("path")
    fig = plt.figure(figsize=(11, 2.6 + 2.2 * len(show)))
    _tool_drawing(fig.add_subplot(1, 3, 1), tooltip_layout)
    axf = axa = None
    for r, i in enumerate(show):
        axf = fig.add_subplot(len(show), 3, 3 * r + 2)
        axa = fig.add_subplot(len(show), 3, 3 * r + 3)
        name = str(traces["hit_file"].values[i])
        axf.plot(1e3 * t, traces["force_N"].values[i], "k", lw=0.8)
        t_trig_ms = 1e3 * float(by_path.loc[name, "trigger_s"])
        axf.set_xlim(t_trig_ms - 10, t_trig_ms + 60)
        axf.set_ylabel("force [N]")
        axf.set_title(f"{name}: {str(by_path.loc[name, 'reason'])[:48]}", fontsize=8)
        for c, col in zip(["ax_ms2", "ay_ms2", "az_ms2"],
                          ["tab:blue", "tab:green", "tab:purple"], strict=True):
            axa.plot(t, traces[c].values[i], color=col, lw=0.6, label=c[:2])
        axa.set_ylabel("acceleration [m/s²]")
        axa.legend(fontsize=7, loc="upper right")
    if axf is not None:
        axf.set_xlabel("time [ms]")
        axa.set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def frf_grid_figure(ds: xr.Dataset, synth: xr.Dataset, band_hz: Sequence[float]
                    ) -> plt.Figure:
    """One panel per (output, input): |H| measured (black), synthesized from the modes (red,
    dashed) and the coherence (blue, right axis) over the band; unmeasured pairs empty."""
    f, band, measured = ds["frequency"].values, _in_band(ds, band_hz), measured_pairs(ds)
    outs, ins = ds["output"].values.tolist(), ds["input"].values.tolist()
    fig, axs = plt.subplots(len(outs), len(ins), squeeze=False, sharex=True,
                            figsize=(min(3.2 * len(ins), 14), min(2.2 * len(outs), 24)))
    for a, o in enumerate(outs):
        for b, i in enumerate(ins):
            ax = axs[a, b]
            if (o, i) not in measured:
                ax.axis("off")
                continue
            ax.semilogy(f[band], np.abs(ds["H"].sel(output=o, input=i).values[band]), "k",
                        lw=0.8)
            ax.semilogy(f[band], np.abs(synth["H_synth"].sel(output=o, input=i).values[band]),
                        "r--", lw=0.8)
            ax.set_title(f"{o} / {i}", fontsize=8)
            if "coherence" in ds:
                ax2 = ax.twinx()
                ax2.plot(f[band], ds["coherence"].sel(output=o, input=i).values[band], "b",
                         lw=0.5, alpha=0.6)
                ax2.set_ylim(0, 1.05)
                ax2.grid(False)
                ax2.tick_params(labelsize=6)
            ax.tick_params(labelsize=6)
    for ax in axs[-1]:
        ax.set_xlabel("frequency [Hz]", fontsize=8)
    fig.suptitle("|H| [m/N] measured (black), synthesized (red), coherence (blue)", fontsize=9)
    fig.tight_layout()
    return fig


def frf_pair_figure(ds: xr.Dataset, synth: xr.Dataset, output: str, input_: str,
                    band_hz: Sequence[float], coherence_min: float) -> plt.Figure:
    """Real part, imaginary part [µm/N] and coherence of one FRF over the band, measured (H1)
    and synthesized, with the peak-picking coherence threshold ``modal.coherence_min``."""
    f, band = ds["frequency"].values, _in_band(ds, band_hz)
    h = ds["H"].sel(output=output, input=input_).values
    hs = synth["H_synth"].sel(output=output, input=input_).values
    fig, axs = plt.subplots(3, 1, figsize=(7.5, 6.0), sharex=True)
    axs[0].plot(f[band], 1e6 * h.real[band], "k", lw=1, label="measured (H1)")
    axs[0].plot(f[band], 1e6 * hs.real[band], "r--", lw=1, label="synthesized (modes)")
    axs[1].plot(f[band], 1e6 * h.imag[band], "k", lw=1)
    axs[1].plot(f[band], 1e6 * hs.imag[band], "r--", lw=1)
    axs[2].plot(f[band], ds["coherence"].sel(output=output, input=input_).values[band], "b",
                lw=1)
    axs[2].axhline(coherence_min, color="tab:orange", ls=":",
                   label=f"modal.coherence_min = {coherence_min:g}")
    axs[0].set_ylabel("Re H [µm/N]")
    axs[1].set_ylabel("Im H [µm/N]")
    axs[2].set_ylabel("coherence")
    axs[2].set_ylim(0, 1.05)
    axs[2].set_xlabel("frequency [Hz]")
    axs[0].legend(fontsize=8)
    axs[2].legend(fontsize=8, loc="lower right")
    axs[0].set_title(f"response {output} / hammer {input_}")
    return fig


def stabilization_figure(stab: pd.DataFrame, modes: pd.DataFrame, ds: xr.Dataset,
                         band_hz: Sequence[float]) -> plt.Figure:
    """The poles of every model order by status (:data:`STABILITY_STYLE`), the selected modes
    as verticals, over the sum of |H| of all measured FRFs."""
    f, band = ds["frequency"].values, _in_band(ds, band_hz)
    fig, ax = plt.subplots(figsize=(9, 5))
    for status, (mk, col, lab) in STABILITY_STYLE.items():
        s = stab[stab["status"] == status]
        ax.plot(s["f_hz"], s["order"], mk, color=col, ms=4, mfc="none" if mk != "x" else col,
                label=f"{lab} ({len(s)})")
    for fn in modes["f_n_hz"]:
        ax.axvline(fn, color="tab:green", lw=0.6, alpha=0.5)
    ax2 = ax.twinx()
    ax2.semilogy(f[band], np.nansum(np.abs(ds["H"].values), axis=(0, 1))[band], "k", lw=0.8)
    ax2.set_ylabel("Σ|H| [m/N]")
    ax2.grid(False)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("model order")
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title("Stabilization chart")
    return fig


def mac_shapes_figure(mac: pd.DataFrame, shapes: pd.DataFrame, modes: pd.DataFrame
                      ) -> plt.Figure:
    """The MAC matrix (``mac.csv`` indexed by ``mode``) and the real part of the unit shapes
    along the node numbers, one line per direction (bars per direction for one node)."""
    fig, (axm, axs) = plt.subplots(1, 2, figsize=(11, 4.2))
    m = mac.to_numpy(float)
    im = axm.imshow(m, vmin=0, vmax=1, cmap="viridis")
    axm.set_xticks(range(len(mac)), [c.replace("mode_", "") for c in mac.columns])
    axm.set_yticks(range(len(mac)), mac.index)
    axm.set_xlabel("mode")
    axm.set_ylabel("mode")
    axm.set_title("MAC")
    for a in range(len(mac)):
        for b in range(len(mac)):
            axm.text(b, a, f"{m[a, b]:.2f}", ha="center", va="center", fontsize=6,
                     color="w" if m[a, b] < 0.5 else "k")
    fig.colorbar(im, ax=axm, shrink=0.8)
    nodes = sorted(shapes["node"].unique())
    for mode in modes["mode"]:
        st = shapes[shapes["mode"] == mode]
        for d, ls in ((1, "-"), (2, "--"), (3, ":")):
            sd = st[st["direction"].abs() == d].sort_values("node")
            if sd.empty:
                continue
            y = np.sign(sd["direction"]) * sd["shape_real"]
            if len(nodes) > 1:
                axs.plot(sd["node"], y, ls, marker="o", ms=3, label=f"mode {mode} {'XYZ'[d - 1]}")
            else:
                axs.bar(mode + 0.25 * (d - 2), y.iloc[0], width=0.25,
                        color=["tab:blue", "tab:green", "tab:purple"][d - 1],
                        label="XYZ"[d - 1] if mode == modes["mode"].iloc[0] else None)
    axs.axhline(0, color="0.5", lw=0.6)
    axs.set_xlabel("node" if len(nodes) > 1 else "mode")
    axs.set_ylabel("Re φ (unit shape, positive axes)")
    axs.legend(fontsize=6, ncol=2)
    axs.set_title("mode shapes over the measured points")
    fig.tight_layout()
    return fig
