"""Peak picking on the FRFs by the thesis' criteria (§3.3), and the grouping of the peaks
of every FRF into natural frequencies."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import scipy.signal
import xarray as xr

from robomill import references
from robomill.settings import schema_default

PEAK_COLUMNS = ["output", "input", "f_hz", "f_line_hz", "prominence_db", "imag_extremum_m_N",
                "real_below_m_N", "real_above_m_N", "coherence", "real_sign_change",
                "coherence_ok", "natural_frequency"]
"""Columns of ``results/modal/peak_picking.csv``."""


def interpolated_peak_hz(f_hz: np.ndarray, magnitude: np.ndarray, k: int) -> float:
    """Frequency of a spectral peak at line ``k``, interpolated within the line spacing by a
    parabola through the log magnitudes of lines ``k − 1, k, k + 1``:
    ``δ = ½ (a − c)/(a − 2b + c)``, ``f = f_k + δ Δf`` with ``a, b, c`` the logs of the three
    magnitudes (Gasior & Gonzalez, *Improving FFT frequency measurement resolution by
    parabolic and Gaussian spectrum interpolation*, AIP Conf. Proc. 732, 2004). The line
    frequency itself where a neighbour is missing, not positive, or the top is flat."""
    from robomill.spectra import interpolate_peak

    return interpolate_peak(f_hz, magnitude, k)  # the same vertex, written once


def peak_picking(ds: xr.Dataset, *, band_hz: Sequence[float],
                 coherence_min: float = schema_default("modal", "coherence_min"),
                 prominence: float = 0.05, floor_db: float = 3.0,
                 real_window_hz: float = schema_default("modal", "real_window_hz")) -> pd.DataFrame:
    """Natural-frequency candidates by the thesis' criteria, on each measured FRF.

    A candidate is an extremum of Im H that stands out of its neighbourhood: a local maximum
    of |Im H| (:func:`scipy.signal.find_peaks`) whose prominence is at least ``prominence`` ×
    the largest |Im H| in the band and which rises at least ``floor_db`` above its local
    floor, ``20 log10(|Im H|_peak / floor) ≥ floor_db`` with the floor the higher of the two
    bases of its prominence (the lowest |Im H| on each side before higher ground or the band
    edge). A shoulder on the skirt of a stronger peak is no local maximum, and a ripple on it
    does not rise above its floor: neither is a candidate. Where none qualifies the table has
    no row for that FRF (no rows at all when none does anywhere). ``f_hz`` is interpolated
    within the line spacing (:func:`interpolated_peak_hz` on |Im H|), ``f_line_hz`` is the
    line of the extremum. Criteria (thesis §3.3): ``real_sign_change`` — the nearest local
    extrema of Re H below and above it (within ``real_window_hz``) are a maximum and a
    minimum of opposite signs; ``coherence_ok`` — γ² > ``coherence_min`` at the candidate
    (FRFs imported without coherence: NaN, and the criterion is not applied).
    ``natural_frequency`` = both.

    Returns
    -------
    pandas.DataFrame
        :data:`PEAK_COLUMNS`: ``output, input, f_hz, f_line_hz, prominence_db`` (height over
        the local floor), ``imag_extremum_m_N, real_below_m_N, real_above_m_N, coherence,
        real_sign_change, coherence_ok, natural_frequency``.
    """
    f = ds["frequency"].values
    sel = np.flatnonzero((f >= band_hz[0]) & (f <= band_hz[1]))
    fb = f[sel]
    df = f[1] - f[0]
    w = max(2, int(round(real_window_hz / df)))
    rows = []
    for o in ds["output"].values.tolist():
        for i in ds["input"].values.tolist():
            h = ds["H"].sel(output=o, input=i).values[sel]
            if not np.isfinite(h).any():
                continue  # a pair this layout did not measure
            coh = (ds["coherence"].sel(output=o, input=i).values[sel] if "coherence" in ds
                   else np.full(sel.size, np.nan))
            im, re = h.imag, h.real
            mag = np.abs(im)
            peaks, props = scipy.signal.find_peaks(mag, prominence=prominence
                                                   * np.nanmax(mag))
            floor = np.maximum(mag[props["left_bases"]], mag[props["right_bases"]])
            with np.errstate(divide="ignore"):
                rise_db = 20 * np.log10(mag[peaks] / floor)
            maxima = set(scipy.signal.argrelextrema(re, np.greater)[0])
            minima = set(scipy.signal.argrelextrema(re, np.less)[0])
            extrema = np.array(sorted(maxima | minima))
            for k, db in zip(peaks, rise_db, strict=True):
                if not db >= floor_db:
                    continue
                below = extrema[(extrema < k) & (extrema >= k - w)]
                above = extrema[(extrema > k) & (extrema <= k + w)]
                lo = int(below[-1]) if below.size else None
                hi = int(above[0]) if above.size else None
                sign_change = (lo is not None and hi is not None
                               and ((lo in maxima and hi in minima)
                                    or (lo in minima and hi in maxima))
                               and np.sign(re[lo]) != np.sign(re[hi]))
                rows.append({"output": o, "input": i,
                             "f_hz": interpolated_peak_hz(fb, mag, int(k)),
                             "f_line_hz": float(fb[k]), "prominence_db": float(db),
                             "imag_extremum_m_N": float(im[k]),
                             "real_below_m_N": float(re[lo]) if lo is not None else np.nan,
                             "real_above_m_N": float(re[hi]) if hi is not None else np.nan,
                             "coherence": float(coh[k]),
                             "real_sign_change": bool(sign_change),
                             "coherence_ok": bool(np.isnan(coh[k]) or coh[k] > coherence_min)})
    out = pd.DataFrame(rows, columns=PEAK_COLUMNS[:-1])
    out["natural_frequency"] = (out["real_sign_change"] & out["coherence_ok"]).astype(bool)
    return out


THESIS_NATURAL_HZ = tuple(float(v) for v in
                          references.values("thesis.modal.modes.f_n_hz.mode_").values())
"""The natural frequencies the thesis finds at the tool tip (§3.3, Figs 3.20-3.28) [Hz]:
the entries ``thesis.modal.modes.f_n_hz.mode_<n>`` of ``robomill/data/references.yaml``."""


def group_peaks(peaks: pd.DataFrame, line_hz: float, *,
                reference_hz: Sequence[float] | None = THESIS_NATURAL_HZ,
                gap_lines: float = 3.0) -> pd.DataFrame:
    """Group the thesis-criteria peaks of every FRF into natural frequencies.

    The candidates of :func:`peak_picking` that meet both criteria (``natural_frequency``)
    are sorted by frequency and split where two neighbours are more than ``gap_lines``
    spectral lines (``line_hz`` each) apart; a group's frequency is the median of its
    members' (thesis §3.3: a frequency counts when it meets both criteria on at least one
    FRF).

    Parameters
    ----------
    peaks
        ``results/modal/peak_picking.csv`` (columns ``output, input, f_hz,
        natural_frequency``).
    line_hz
        Spacing of the FRF's frequency lines [Hz].
    reference_hz
        Frequencies to match each group with (nearest); ``None``: no ``reference_hz``
        column values (NaN).
    gap_lines
        Largest gap inside a group, in lines.

    Returns
    -------
    pandas.DataFrame
        ``group`` (1, 2, …), ``f_hz`` (median), ``n_frfs`` (members), ``frfs``
        (``"output/input"`` of each member, comma separated), ``reference_hz`` (nearest
        reference frequency) and ``offset_hz`` (``f_hz − reference_hz``).
    """
    cols = ["group", "f_hz", "n_frfs", "frfs", "reference_hz", "offset_hz"]
    ok = peaks[peaks["natural_frequency"].astype(bool)].sort_values("f_hz", kind="stable")
    if ok.empty:
        return pd.DataFrame(columns=cols)
    gid = (ok["f_hz"].diff() > gap_lines * float(line_hz)).cumsum().to_numpy() + 1
    rows = []
    ref = None if reference_hz is None else np.asarray(reference_hz, float)
    for g in np.unique(gid):
        m = ok[gid == g]
        f_hz = float(np.median(m["f_hz"]))
        near = float(ref[np.argmin(np.abs(ref - f_hz))]) if ref is not None and ref.size \
            else np.nan
        rows.append({"group": int(g), "f_hz": f_hz, "n_frfs": len(m),
                     "frfs": ", ".join(f"{o}/{i}" for o, i in zip(m["output"], m["input"],
                                                                   strict=True)),
                     "reference_hz": near, "offset_hz": f_hz - near})
    return pd.DataFrame(rows, columns=cols)
