"""The chapter-4 tables, from the chatter artefacts (``simulation.nc``, ``lobes.nc``).

Pure functions of the datasets :mod:`robomill.chatter.seed` and
:mod:`robomill.chatter.slot_lobes` write; the chapter only displays what they return.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr


def onset_table(sim: xr.Dataset) -> pd.DataFrame:
    """Time domain against the lobes at the onset checks (``results/chatter/simulation.nc``).

    For each fixed-setpoint run just below or above the semi-discretization boundary: the
    lobes call the cut unstable when its depth exceeds the boundary (``depth / boundary >
    1``), the time domain when the chatter indicator grows; ``agree`` compares the two. The
    growth rates are the SDM Floquet exponent ``σ = ln ρ/τ`` (ρ the largest monodromy
    eigenvalue modulus, τ the tooth period; Insperger & Stépán 2002) and the simulated
    log-slope of the indicator; ``σ sim / SDM`` is their ratio.

    Returns
    -------
    pandas.DataFrame
        ``spindle_rpm, depth / boundary, boundary [mm], time domain unstable, indicator [N],
        σ SDM [1/s], σ simulated [1/s], σ sim / SDM, lobes say unstable, agree``.
    """
    out = pd.DataFrame({
        "spindle_rpm": sim["onset_check_rpm"].values,
        "depth / boundary": sim["onset_depth_fraction"].values,
        "boundary [mm]": sim["onset_a_boundary_mm"].values,
        "time domain unstable": sim["onset_unstable"].values.astype(bool),
        "indicator [N]": sim["onset_indicator_N"].values,
        "σ SDM [1/s]": sim["onset_growth_rate_sdm_1_s"].values,
        "σ simulated [1/s]": sim["onset_growth_rate_simulated_1_s"].values,
    })
    with np.errstate(divide="ignore", invalid="ignore"):
        out["σ sim / SDM"] = out["σ simulated [1/s]"] / out["σ SDM [1/s]"]
    out["lobes say unstable"] = out["depth / boundary"] > 1
    out["agree"] = out["lobes say unstable"] == out["time domain unstable"]
    return out


def coupling_table(lobes: xr.Dataset) -> pd.DataFrame:
    """Mode coupling and regenerative chatter per slot direction (``results/chatter/lobes.nc``).

    The mode-coupling critical depth ``a_mc`` and frequency of the coupled pair (Tlusty's
    mode-coupling limit, Pan et al. 2006), beside the zero-order regenerative chatter
    frequency linearly interpolated at each slot's spindle speed (``study_spindle_rpm``, the
    speed of most of its cuts; in artefacts without it, the attribute ``thesis_spindle_rpm``)
    and the range of the force peaks of the cuts (thesis §3.1).

    Returns
    -------
    pandas.DataFrame
        ``direction, mode-coupling a_mc [mm], coupling frequency [Hz], coupled pair [Hz],
        regenerative chatter [Hz] (ZOA, <rpm> rpm), force peaks [Hz] (min–max)``.
    """
    dirs = lobes["direction"].values
    rpms = (lobes["study_spindle_rpm"].values.astype(float) if "study_spindle_rpm" in lobes
            else np.full(len(dirs), float(lobes.attrs["thesis_spindle_rpm"])))
    chatter = [float(lobes["chatter_hz"].sel(direction=d, solver="zoa")
                     .interp(spindle_rpm=n)) for d, n in zip(dirs, rpms, strict=True)]
    rpm = rpms[0] if np.all(rpms == rpms[0]) else None
    speed = f"{f'{rpm:,.0f}'.replace(',', ' ')} rpm" if rpm is not None else "each slot's speed"
    return pd.DataFrame({
        "direction": lobes["direction"].values,
        "mode-coupling a_mc [mm]": lobes["mode_coupling_a_mm"].values,
        "coupling frequency [Hz]": lobes["mode_coupling_hz"].values,
        "coupled pair [Hz]": [" & ".join(f"{f:.1f}" for f in p)
                              for p in lobes["coupled_mode_hz"].values],
        f"regenerative chatter [Hz] (ZOA, {speed})": chatter,
        "force peaks [Hz] (min–max)": [f"{a:.0f}–{b:.0f}" for a, b in
                                       zip(lobes["force_peak_min_hz"].values,
                                           lobes["force_peak_max_hz"].values, strict=True)],
    })
