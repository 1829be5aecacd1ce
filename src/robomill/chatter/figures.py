"""Chapter 4's figures, drawn from the chatter stage's artefacts (each function returns the
figure; the chapter saves, shows and captions it): the lobes of a configured case with their
flip lobes and their discretization error, the slotting agreement of the two methods, the
Shagniev 2019 lobes, time histories, spectra and chatter indicator, and the identified robot's
lobes per slot direction."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

SPECTRUM_MAX_HZ = 600.0
"""Upper end of the Shagniev 2019 force spectra shown (Hz): the tooth-passing harmonics and the
chatter line of the seed's 2-tooth tool at its spindle speed lie below it."""


def case_lobes_figure(ds: xr.Dataset) -> plt.Figure:
    """The critical depth of a configured case (``results/chatter/cases/<name>.nc``) against
    the spindle speed: zero-order (Altintas & Budak 1995) and spectral element (Khasawneh &
    Mann 2011), the speeds of a flip (period-doubling) boundary marked."""
    rpm = ds["spindle_rpm"].values
    a_s = ds["a_crit_mm"].sel(solver="sem").values
    flip = ds["bifurcation"].values.astype(str) == "flip"
    fig, ax = plt.subplots()
    ax.plot(rpm, ds["a_crit_mm"].sel(solver="zoa").values, "-", color="0.5",
            label="zero-order (ZOA)")
    ax.plot(rpm, a_s, "k-", lw=1.2,
            label=f"spectral element (error ≤ {100 * ds.attrs['accuracy']:.1f} %)")
    ax.plot(rpm[flip], a_s[flip], "r.", ms=4, label="flip (period doubling)")
    ax.set_xlabel("spindle speed [rpm]")
    ax.set_ylabel("critical axial depth [mm]")
    ax.set_ylim(0, ds.attrs["depth_max_mm"])
    ax.set_title(f"Case {ds.attrs['case_name']}")
    ax.legend()
    return fig


def case_error_figure(ds: xr.Dataset) -> plt.Figure:
    """The estimated relative discretization error of the spectral element per speed,
    ``a_crit_error_mm / a_crit_mm[solver=sem]``, against ``chatter.accuracy``."""
    rel = 100 * ds["a_crit_error_mm"].values / ds["a_crit_mm"].sel(solver="sem").values
    fig, ax = plt.subplots()
    ax.semilogy(ds["spindle_rpm"].values, rel, "k.", ms=3,
                label="estimated error of the spectral element")
    ax.axhline(100 * ds.attrs["accuracy"], color="r", ls="--", label="chatter.accuracy")
    ax.set_xlabel("spindle speed [rpm]")
    ax.set_ylabel("relative error of a_crit [%]")
    ax.set_title(f"Case {ds.attrs['case_name']}: discretization error per speed")
    ax.legend()
    return fig


def slot_figure(ds: xr.Dataset) -> plt.Figure:
    """The slotting case's critical depth by both methods (they must agree: its directional
    matrix is nearly constant)."""
    fig, ax = plt.subplots()
    ax.plot(ds["spindle_rpm"], ds["a_crit_mm"].sel(solver="zoa"), color="0.5", label="ZOA")
    ax.plot(ds["spindle_rpm"], ds["a_crit_mm"].sel(solver="sem"), "k--",
            label="spectral element")
    ax.set_xlabel("spindle speed [rpm]")
    ax.set_ylabel("critical axial depth [mm]")
    ax.legend()
    return fig


def seed_lobes_figure(sim: xr.Dataset) -> plt.Figure:
    """Shagniev 2019's lobes of the closed-loop tool point (``results/chatter/simulation.nc``):
    zero-order (D-partition) and semi-discretization, a* and the two operating points."""
    sp = sim["spindle_rpm"].values
    fig, ax = plt.subplots()
    ax.plot(sp, sim["seed_a_crit_mm"].sel(solver="zoa"), color="0.5", label="ZOA (D-partition)")
    ax.plot(sp, sim["seed_a_crit_mm"].sel(solver="sdm"), "k-", label="SDM")
    ax.axhline(sim.attrs["a_star_mm"], color="b", ls=":", label="a* (stable at every speed)")
    n0 = sim.attrs["spindle_rpm_seed"]
    ax.plot([n0], [sim.attrs["point1_depth_mm"]], "go", label="point 1")
    ax.plot([n0], [sim.attrs["point2_depth_mm"]], "rs", label="point 2")
    ax.set_xlabel("spindle speed n [rpm]")
    ax.set_ylabel("critical axial depth a_cr [mm]")
    ax.legend()
    return fig


def seed_time_figure(sim: xr.Dataset) -> plt.Figure:
    """The tool vibration x_s over time, one panel per run."""
    runs = sim["run"].values
    fig, axes = plt.subplots(len(runs), 1, figsize=(7.5, 8), sharex=True, squeeze=False)
    for ax, run in zip(axes[:, 0], runs, strict=True):
        ax.plot(sim["time"], sim["xs_vib_um"].sel(run=run), lw=0.4)
        ax.set_ylabel("x_s [µm]")
        ax.set_title(str(run))
    axes[-1, 0].set_xlabel("t [s]")
    return fig


def seed_spectra_figure(sim: xr.Dataset, max_hz: float = SPECTRUM_MAX_HZ) -> plt.Figure:
    """The amplitude spectrum of the resultant horizontal force in the last window, per run,
    up to ``max_hz``."""
    fig, ax = plt.subplots()
    for run in sim["run"].values:
        ax.plot(sim["frequency"], sim["spectrum_N"].sel(run=run), lw=0.8, label=str(run))
    ax.set_xlim(0, max_hz)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("amplitude of R [N]")
    ax.set_title("Amplitude spectrum of the resultant horizontal force, last window")
    ax.legend()
    return fig


def detection_figure(sim: xr.Dataset) -> plt.Figure:
    """The chatter indicator per window and run; red dotted: the adaptations of the logic
    block (``attrs.adaptation_times_s``)."""
    fig, ax = plt.subplots()
    for run in sim["run"].values:
        ax.semilogy(sim["window_end"], sim["indicator_N"].sel(run=run), label=str(run))
    for t_a in np.atleast_1d(sim.attrs["adaptation_times_s"]):
        ax.axvline(t_a, color="r", ls=":")
    ax.set_xlabel("end of window [s]")
    ax.set_ylabel("chatter indicator [N]")
    ax.legend()
    return fig


def robot_lobes_figure(lobes: xr.Dataset) -> plt.Figure:
    """The identified robot's lobes per slot direction (``results/chatter/lobes.nc``): ZOA,
    spectral element with its error band; red: the configured depths
    (``attrs.thesis_depths_mm``), dotted: the speed of most of the slot's cuts."""
    dirs = lobes["direction"].values
    fig, axes = plt.subplots(1, len(dirs), figsize=(11, 3.8), sharey=True, squeeze=False)
    for ax, d in zip(axes[0], dirs, strict=True):
        ax.plot(lobes["spindle_rpm"], lobes["a_crit_mm"].sel(direction=d, solver="zoa"), "-",
                label="zoa")
        a_d = lobes["a_crit_mm"].sel(direction=d, solver="sem")
        e_d = lobes["a_crit_error_mm"].sel(direction=d)
        ax.plot(lobes["spindle_rpm"], a_d, "--", label="sem")
        ax.fill_between(lobes["spindle_rpm"], a_d - e_d, a_d + e_d, color="C1", alpha=0.3,
                        label="sem ± error")
        for dep in np.atleast_1d(lobes.attrs["thesis_depths_mm"]):
            ax.axhline(dep, color="r", lw=0.6)
        rpm = (lobes["study_spindle_rpm"].sel(direction=d) if "study_spindle_rpm" in lobes
               else lobes.attrs["thesis_spindle_rpm"])
        ax.axvline(float(rpm), color="0.6", ls=":")
        ax.set_title(f"slot {d}")
        ax.set_xlabel("spindle speed [rpm]")
    axes[0, 0].set_ylabel("critical axial depth [mm]")
    axes[0, 0].legend()
    return fig
