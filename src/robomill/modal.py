"""Impact-test modal identification of the tool tip (thesis §3.3, and beyond it).

The chain, each step a pure function on arrays:

1. :func:`check_hit` — automatic rejection of a hit: a **double hit** (the force rises above
   ``double_hit_fraction`` of its peak in two separate pulses) or an **overload** (a channel
   stays at its extreme value for ``overload_samples`` samples or more: a clipped,
   saturated channel). The reason is returned in words.
2. :func:`impact_windows` — a force window (1 from the record start to ``force_window_s``
   after the trigger, then a half-Hann taper) and an exponential window
   ``w(t) = exp(−σ (t − t_trig))`` after the trigger, ``σ = ln(1/end)/T`` (the window reaches
   ``end`` one record length T after the trigger). A window ``e^{−σt}`` on a free decay
   ``Σ A_r e^{p_r t}`` shifts every pole to ``p_r − σ`` and leaves the residues unchanged, so
   the identified poles are corrected by ``+σ`` (:func:`correct_window_damping`): the
   damping the window adds, ``Δζ ≈ σ/ω_n``, is removed.
3. :func:`frf_matrix` — per hit direction, the windowed hits go to :class:`pyFRF.FRF`, which
   averages the cross and auto spectra over the accepted hits and returns H1 = S_xf/S_ff,
   H2 = S_xx/S_fx and the coherence γ² = |S_xf|²/(S_ff S_xx): the full 3×3 receptance matrix
   H[output, input] (m/N) over frequency.
4. :func:`peak_picking` — the thesis' criteria on every FRF: the imaginary part has an
   extremum; the real part has a local maximum and a local minimum of opposite signs on
   either side; the coherence there exceeds 0.75.
5. :func:`stabilization` and :func:`select_poles` — poles by the least-squares
   complex-frequency (LSCF, common-denominator over all nine FRFs) method of sdypy-EMA for
   model orders 2…2·``max_order``; a pole is *stable* when the previous order has a pole
   within ``tol_f`` in frequency, ``tol_zeta`` in damping and with residue vectors of MAC ≥
   ``mac_min`` (residues by LSFD at each order). Stable poles are grouped by frequency;
   groups of at least ``min_stable`` orders are physical modes.
6. :func:`modal_constants` and :func:`modes_table` — residues by LSFD (sdypy-EMA, with lower
   and upper residual terms), the FRF synthesized from them, and per mode the residue matrix
   ``A_r = φ_r φ_rᵀ/(2jω_d m_r)`` turned into a unit shape φ_r, a modal mass m_r and a modal
   stiffness ``k_r = m_r ω_r²`` at the tool tip — the same definitions as the virtual cell
   (:meth:`robomill.synth.cell.VirtualCell.receptance_m_per_N`).

FRF convention (as in sdypy-EMA): ``H(ω) = Σ_r A_r/(jω − p_r) + A_r*/(jω − p_r*)``
(:func:`synthesize_frf`).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
import scipy.signal
import xarray as xr

AXES = ("X", "Y", "Z")
"""Output (accelerometer) and input (hammer) directions, base axes."""
CHANNELS = ("force_N", "ax_ms2", "ay_ms2", "az_ms2")
"""Channels of an impact record."""
COMPLEX_VARS = ("H", "H2", "H_synth")
"""Complex FRF variables, stored in netCDF as ``<name>_real`` and ``<name>_imag``."""


# ---- 1. hit rejection -------------------------------------------------------------------------
@dataclass(frozen=True)
class HitCheck:
    """Outcome of :func:`check_hit`: accepted or not, why, and the trigger sample."""

    accepted: bool
    reason: str
    trigger_index: int


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Start and end (exclusive) of every run of True in a boolean array."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1), strict=True))


def check_hit(force_N: np.ndarray, accel_ms2: np.ndarray, fs_hz: float, *,
              trigger_fraction: float = 0.05, double_hit_fraction: float = 0.1,
              overload_samples: int = 3, flat_rtol: float = 1e-4,
              force_range_N: float | None = None,
              accel_range_ms2: float | None = None) -> HitCheck:
    """Accept or reject one hit (thesis §3.3: double hits and overloads are rejected).

    Parameters
    ----------
    force_N
        Hammer force ``(n,)``.
    accel_ms2
        Accelerations ``(n, 3)`` (X, Y, Z).
    fs_hz
        Sampling rate.
    trigger_fraction
        The trigger is the first sample whose force exceeds this fraction of the peak.
    double_hit_fraction
        Force pulses are the runs above this fraction of the peak; more than one is a double
        hit.
    overload_samples
        A channel whose |value| stays within ``flat_rtol`` of its maximum for this many
        consecutive samples is clipped (overload).
    force_range_N, accel_range_ms2
        Measurement ranges of the channels, when known: a sample reaching its range (within
        ``flat_rtol``) is an overload even if too short to show a flat top.

    Returns
    -------
    HitCheck
        ``reason`` is ``"ok"`` or a sentence naming the defect.
    """
    force = np.asarray(force_N, float)
    acc = np.asarray(accel_ms2, float).reshape(force.size, -1)
    peak = float(np.max(force))
    if peak <= 0:
        return HitCheck(False, "no impact: the force never rises above zero", 0)
    trigger = int(np.argmax(force > trigger_fraction * peak))
    ranges = [force_range_N] + [accel_range_ms2] * acc.shape[1]
    for name, x, rng in zip(CHANNELS, [force, *acc.T], ranges, strict=False):
        ax = np.abs(x)
        top = ax.max()
        if top == 0:
            continue
        if rng is not None and top >= (1 - flat_rtol) * rng:
            n_at = int(np.sum(ax >= (1 - flat_rtol) * rng))
            return HitCheck(False, f"overload: channel {name} reaches its range ±{rng:.4g} "
                                   f"({n_at} samples)", trigger)
        longest = max((e - s for s, e in _runs(ax >= (1 - flat_rtol) * top)), default=0)
        if longest >= overload_samples:
            return HitCheck(False, f"overload: channel {name} is clipped at ±{top:.4g} for "
                                   f"{longest} consecutive samples", trigger)
    pulses = _runs(force > double_hit_fraction * peak)
    if len(pulses) > 1:
        s2, e2 = pulses[1]
        second = float(force[s2:e2].max())
        dt_ms = 1e3 * (s2 - pulses[0][1]) / fs_hz
        return HitCheck(False, f"double hit: a second impact of {second:.1f} N "
                               f"({second / peak:.2f} of the first) {dt_ms:.1f} ms after the "
                               "first pulse ends", trigger)
    return HitCheck(True, "ok", trigger)


# ---- 2. windows ---------------------------------------------------------------------------------
def exponential_window_rate(n: int, fs_hz: float, end_value: float) -> float:
    """Decay rate σ [1/s] of the exponential window: ``e^{−σT} = end_value``, T = n/fs."""
    return float(np.log(1.0 / end_value) / (n / fs_hz))


def impact_windows(n: int, fs_hz: float, trigger_index: int, *, force_window_s: float,
                   exponential_end: float,
                   taper_s: float | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Force and exponential windows for one hit record of ``n`` samples.

    The force window is 1 up to ``force_window_s`` after the trigger, then a half-Hann taper
    of ``taper_s`` (default ``force_window_s/4``), then 0. The exponential window is 1 before
    the trigger and ``exp(−σ (t − t_trig))`` after it (:func:`scipy.signal.windows.exponential`),
    σ from :func:`exponential_window_rate`. Apply the exponential window to force and response
    alike.

    Returns
    -------
    w_force, w_exp, sigma
    """
    sigma = exponential_window_rate(n, fs_hz, exponential_end)
    n_on = min(n, trigger_index + int(round(force_window_s * fs_hz)))
    n_taper = max(2, int(round((taper_s if taper_s is not None else force_window_s / 4)
                               * fs_hz)))
    w_force = np.zeros(n)
    w_force[:n_on] = 1.0
    taper = scipy.signal.windows.hann(2 * n_taper, sym=False)[n_taper:]
    m = min(n_taper, n - n_on)
    w_force[n_on:n_on + m] = taper[:m]
    w_exp = np.ones(n)
    tau = fs_hz / sigma  # decay constant in samples
    w_exp[trigger_index:] = scipy.signal.windows.exponential(n - trigger_index, center=0,
                                                              tau=tau, sym=False)
    return w_force, w_exp, sigma


# ---- 3. FRF matrix ------------------------------------------------------------------------------
def frf_matrix(hits: dict[str, list[tuple[np.ndarray, np.ndarray, int]]], fs_hz: int, *,
               force_window_s: float, exponential_end: float) -> xr.Dataset:
    """The 3×3 receptance FRF matrix from accepted hits, by :class:`pyFRF.FRF`.

    Parameters
    ----------
    hits
        Per input direction (``"X"``, ``"Y"``, ``"Z"``), the accepted hits as
        ``(force_N (n,), accel_ms2 (n, 3), trigger_index)``; all records of equal length.
    fs_hz
        Sampling rate (an integer, as pyFRF requires).

    Returns
    -------
    xr.Dataset
        ``H`` (H1) and ``H2`` complex [m/N], ``coherence`` [1] over ``output, input,
        frequency``; ``n_hits`` per input; attribute ``window_sigma_per_s``.
    """
    import pyFRF

    fs_hz = int(fs_hz)
    n = None
    out: dict[str, np.ndarray] = {}
    n_hits = []
    sigma = np.nan
    for j, d in enumerate(AXES):
        group = hits.get(d, [])
        if not group:
            raise ValueError(f"no accepted hit in direction {d}: the FRF column cannot be "
                             "estimated")
        exc, resp = [], []
        for force, acc, trig in group:
            n = force.size
            w_f, w_e, sigma = impact_windows(n, fs_hz, trig, force_window_s=force_window_s,
                                             exponential_end=exponential_end)
            exc.append((force * w_f * w_e)[None, :])
            resp.append((np.asarray(acc, float) * w_e[:, None]).T)
        frf = pyFRF.FRF(fs_hz, exc=np.array(exc), resp=np.array(resp), exc_type="f",
                        resp_type="a", window="none", frf_estimator="H1")
        with np.errstate(divide="ignore", invalid="ignore"):
            h1 = frf.get_FRF(frf_estimator="H1", frf_form="receptance")[:, 0, :]
            h2 = frf.get_FRF(frf_estimator="H2", frf_form="receptance")[:, 0, :]
            coh = np.real(frf.get_coherence())
        if not out:
            freq = frf.get_f_axis()
            out = {"H": np.full((3, 3, freq.size), np.nan + 0j),
                   "H2": np.full((3, 3, freq.size), np.nan + 0j),
                   "coherence": np.full((3, 3, freq.size), np.nan)}
        out["H"][:, j], out["H2"][:, j], out["coherence"][:, j] = h1, h2, coh
        n_hits.append(len(group))
    dims = ("output", "input", "frequency")
    ds = xr.Dataset(
        {"H": (dims, out["H"], {"units": "m/N", "long_name": "receptance FRF, H1 estimator"}),
         "H2": (dims, out["H2"], {"units": "m/N", "long_name": "receptance FRF, H2 estimator"}),
         "coherence": (dims, out["coherence"], {"units": "1",
                                                "long_name": "ordinary coherence"}),
         "n_hits": ("input", np.array(n_hits), {"units": "1",
                                                "long_name": "accepted hits averaged"})},
        coords=frf_coords(freq))
    ds.attrs["window_sigma_per_s"] = float(sigma)
    ds.attrs["fs_hz"] = fs_hz
    ds.attrs["record_samples"] = int(n)
    return ds


def frf_coords(freq_hz: np.ndarray) -> dict:
    """Labelled coordinates ``output, input, frequency`` of an FRF dataset."""
    return {"output": ("output", list(AXES), {"units": "1",
                                              "long_name": "response direction (base axis)"}),
            "input": ("input", list(AXES), {"units": "1",
                                            "long_name": "hammer direction (base axis)"}),
            "frequency": ("frequency", np.asarray(freq_hz, float),
                          {"units": "Hz", "long_name": "frequency"})}


def split_complex(ds: xr.Dataset) -> xr.Dataset:
    """Complex variables → ``<name>_real`` and ``<name>_imag`` (netCDF4 has no complex type)."""
    ds = ds.copy()
    for name in list(ds.data_vars):
        if np.iscomplexobj(ds[name].values):
            attrs = dict(ds[name].attrs)
            for part, fn in (("real", np.real), ("imag", np.imag)):
                ds[f"{name}_{part}"] = ds[name].copy(data=fn(ds[name].values)).assign_attrs(
                    {**attrs, "long_name": f"{part} part of {attrs.get('long_name', name)}"})
            ds = ds.drop_vars(name)
    return ds


def join_complex(ds: xr.Dataset) -> xr.Dataset:
    """Inverse of :func:`split_complex`: ``<name>_real`` + ``<name>_imag`` → complex ``name``."""
    ds = ds.copy()
    for name in [v[:-5] for v in ds.data_vars if str(v).endswith("_real")]:
        if f"{name}_imag" in ds:
            attrs = dict(ds[f"{name}_real"].attrs)
            attrs["long_name"] = attrs.get("long_name", name).removeprefix("real part of ")
            ds[name] = (ds[f"{name}_real"] + 1j * ds[f"{name}_imag"]).assign_attrs(attrs)
            ds = ds.drop_vars([f"{name}_real", f"{name}_imag"])
    return ds


# ---- 4. thesis peak picking -------------------------------------------------------------------
def peak_picking(ds: xr.Dataset, *, band_hz: Sequence[float], coherence_min: float = 0.75,
                 prominence: float = 0.05, real_window_hz: float = 3.0) -> pd.DataFrame:
    """Natural-frequency candidates by the thesis' criteria, on each of the 9 FRFs.

    A candidate is an extremum of Im H (a peak of |Im H| with prominence at least
    ``prominence`` × its largest value in the band). Criteria (thesis §3.3):
    ``real_sign_change`` — the nearest local extrema of Re H below and above it (within
    ``real_window_hz``) are a maximum and a minimum of opposite signs; ``coherence_ok`` —
    γ² > ``coherence_min`` at the candidate. ``natural_frequency`` = both.

    Returns
    -------
    pandas.DataFrame
        ``output, input, f_hz, imag_extremum_m_N, real_below_m_N, real_above_m_N, coherence,
        real_sign_change, coherence_ok, natural_frequency``.
    """
    f = ds["frequency"].values
    sel = np.flatnonzero((f >= band_hz[0]) & (f <= band_hz[1]))
    df = f[1] - f[0]
    w = max(2, int(round(real_window_hz / df)))
    rows = []
    for o in AXES:
        for i in AXES:
            h = ds["H"].sel(output=o, input=i).values[sel]
            coh = ds["coherence"].sel(output=o, input=i).values[sel]
            im, re = h.imag, h.real
            peaks, _ = scipy.signal.find_peaks(np.abs(im), prominence=prominence
                                               * np.nanmax(np.abs(im)))
            maxima = set(scipy.signal.argrelextrema(re, np.greater)[0])
            minima = set(scipy.signal.argrelextrema(re, np.less)[0])
            extrema = np.array(sorted(maxima | minima))
            for k in peaks:
                below = extrema[(extrema < k) & (extrema >= k - w)]
                above = extrema[(extrema > k) & (extrema <= k + w)]
                lo = int(below[-1]) if below.size else None
                hi = int(above[0]) if above.size else None
                sign_change = (lo is not None and hi is not None
                               and ((lo in maxima and hi in minima)
                                    or (lo in minima and hi in maxima))
                               and np.sign(re[lo]) != np.sign(re[hi]))
                rows.append({"output": o, "input": i, "f_hz": float(f[sel][k]),
                             "imag_extremum_m_N": float(im[k]),
                             "real_below_m_N": float(re[lo]) if lo is not None else np.nan,
                             "real_above_m_N": float(re[hi]) if hi is not None else np.nan,
                             "coherence": float(coh[k]),
                             "real_sign_change": bool(sign_change),
                             "coherence_ok": bool(coh[k] > coherence_min)})
    out = pd.DataFrame(rows, columns=["output", "input", "f_hz", "imag_extremum_m_N",
                                      "real_below_m_N", "real_above_m_N", "coherence",
                                      "real_sign_change", "coherence_ok"])
    out["natural_frequency"] = out["real_sign_change"] & out["coherence_ok"]
    return out


# ---- 5. poles: LSCF stabilization chart ---------------------------------------------------------
def _frf_rows(ds: xr.Dataset, var: str = "H") -> tuple[np.ndarray, np.ndarray]:
    """The 9 FRFs as rows ``(9, nf)`` (output-major) and their frequencies, DC dropped."""
    f = ds["frequency"].values
    h = ds[var].transpose("output", "input", "frequency").values.reshape(9, -1)
    keep = f > 0
    return h[:, keep], f[keep]


def _lsfd(poles: np.ndarray, frf: np.ndarray, freq: np.ndarray, band_hz: Sequence[float]):
    """Residues (n_frf, n_poles) and reconstructed FRF by sdypy-EMA's LSFD in the band."""
    from sdypy.EMA.EMA import LSFD

    lo = int(np.searchsorted(freq, band_hz[0]))
    hi = int(np.searchsorted(freq, band_hz[1], side="right"))
    with warnings.catch_warnings(), np.errstate(divide="ignore", invalid="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        A, H, LR, UR = LSFD(np.asarray(poles), frf, freq, True, True, lo, hi,
                            frf_form="receptance")
    return A, H, LR, UR


def _mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion of two complex vectors (sdypy-EMA's ``MAC``)."""
    from sdypy.EMA import MAC

    with warnings.catch_warnings():  # MAC stores |a^H b|^2/(a^H a b^H b) in a real array
        warnings.simplefilter("ignore", np.exceptions.ComplexWarning)
        return float(np.real(MAC(a, b)))


def pole_f_zeta(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequency [Hz] and damping ratio of poles ``p = −ζω_n ± jω_n√(1−ζ²)``."""
    p = np.asarray(poles, complex)
    wn = np.abs(p)
    with np.errstate(divide="ignore", invalid="ignore"):
        return wn / (2 * np.pi), -p.real / wn


def stabilization(ds: xr.Dataset, *, band_hz: Sequence[float], max_order: int = 40,
                  tol_f: float = 0.01, tol_zeta: float = 0.05, mac_min: float = 0.95,
                  zeta_max: float = 0.2) -> pd.DataFrame:
    """Stabilization chart: LSCF poles (sdypy-EMA) at every model order, with their status.

    For each order (denominator degree 2, 4, …, 2·``max_order``) the poles with positive
    imaginary part, frequency in ``band_hz`` and 0 < ζ < ``zeta_max`` are kept; their residues
    over the 9 FRFs come from LSFD at that order. Each pole is compared with the nearest pole of
    the previous order: status ``new``, ``f`` (frequency within ``tol_f`` relative), ``fd``
    (and damping within ``tol_zeta`` relative), ``stable`` (and MAC of the residue vectors
    ≥ ``mac_min``).

    Returns
    -------
    pandas.DataFrame
        ``order, f_hz, zeta, pole_real, pole_imag, status`` (poles of the windowed FRFs).
    """
    from sdypy import EMA

    frf, freq = _frf_rows(ds)
    model = EMA.Model(frf=frf, freq=freq, lower=band_hz[0], upper=band_hz[1],
                      pol_order_high=int(max_order), frf_form="receptance")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model.get_poles(method="lscf", show_progress=False)
    rows = []
    prev = None
    for idx, poles in enumerate(model.all_poles):
        order = 2 * (idx + 1)
        fp, zp = pole_f_zeta(poles)
        keep = ((poles.imag > 0) & (fp >= band_hz[0]) & (fp <= band_hz[1]) & (zp > 0)
                & (zp < zeta_max))
        p = poles[keep]
        if p.size == 0:
            prev = None
            continue
        A, *_ = _lsfd(p, model.frf, model.freq, band_hz)
        fk, zk = pole_f_zeta(p)
        for m in range(p.size):
            status = "new"
            if prev is not None:
                pf, pz, pA = prev
                j = int(np.argmin(np.abs(pf - fk[m])))
                if abs(pf[j] - fk[m]) <= tol_f * fk[m]:
                    status = "f"
                    if abs(pz[j] - zk[m]) <= tol_zeta * zk[m]:
                        status = "fd"
                        if _mac(A[:, m], pA[:, j]) >= mac_min:
                            status = "stable"
            rows.append({"order": order, "f_hz": fk[m], "zeta": zk[m],
                         "pole_real": p[m].real, "pole_imag": p[m].imag, "status": status})
        prev = (fk, zk, A)
    return pd.DataFrame(rows, columns=["order", "f_hz", "zeta", "pole_real", "pole_imag",
                                       "status"])


def select_poles(stab: pd.DataFrame, *, cluster_tol: float = 0.01,
                 min_stable: int = 5) -> pd.DataFrame:
    """Physical poles from a stabilization chart.

    Stable poles are sorted by frequency and split into groups where consecutive
    frequencies differ by more than ``cluster_tol`` (relative); a group with poles at
    ``min_stable`` or more distinct orders is a mode. Its representative is the pole of the
    group nearest the group's median frequency and median damping (highest order on ties).

    Returns
    -------
    pandas.DataFrame
        ``f_hz, zeta, pole_real, pole_imag, order, n_stable`` per mode, by frequency.
    """
    st = stab[stab["status"] == "stable"].sort_values("f_hz").reset_index(drop=True)
    if st.empty:
        return pd.DataFrame(columns=["f_hz", "zeta", "pole_real", "pole_imag", "order",
                                     "n_stable"])
    f = st["f_hz"].to_numpy()
    breaks = np.flatnonzero(np.diff(f) > cluster_tol * f[1:]) + 1
    out = []
    for g in np.split(np.arange(len(st)), breaks):
        grp = st.iloc[g]
        n_orders = grp["order"].nunique()
        if n_orders < min_stable:
            continue
        fm, zm = grp["f_hz"].median(), grp["zeta"].median()
        score = np.abs(grp["f_hz"] - fm) / fm + np.abs(grp["zeta"] - zm) / zm
        best = grp.assign(score=score).sort_values(["score", "order"],
                                                   ascending=[True, False]).iloc[0]
        out.append({"f_hz": best["f_hz"], "zeta": best["zeta"],
                    "pole_real": best["pole_real"], "pole_imag": best["pole_imag"],
                    "order": int(best["order"]), "n_stable": int(n_orders)})
    return pd.DataFrame(out)


def correct_window_damping(poles: np.ndarray, sigma_per_s: float) -> np.ndarray:
    """Remove the exponential window's decay from identified poles: ``p + σ``.

    The window ``e^{−σt}`` (from the trigger) turns every term ``A e^{pt}`` of the impulse
    response into ``A e^{(p−σ)t}``, i.e. adds ``Δζ ≈ σ/ω_n`` of damping.
    """
    return np.asarray(poles, complex) + float(sigma_per_s)


# ---- 6. residues, mode shapes, modal mass and stiffness ------------------------------------------
def synthesize_frf(poles: np.ndarray, residues: np.ndarray, f_hz: np.ndarray) -> np.ndarray:
    """FRF from poles and residues: ``H(ω) = Σ_r A_r/(jω − p_r) + A_r*/(jω − p_r*)``.

    ``residues`` has shape ``(..., n_modes)`` (e.g. ``(3, 3, n_modes)``); returns
    ``(..., len(f_hz))``.
    """
    jw = 2j * np.pi * np.asarray(f_hz, float)
    p = np.asarray(poles, complex)
    A = np.asarray(residues, complex)
    return (np.einsum("...r,rf->...f", A, 1.0 / (jw[None, :] - p[:, None]))
            + np.einsum("...r,rf->...f", A.conj(), 1.0 / (jw[None, :] - p.conj()[:, None])))


def modal_residues(f_hz: Sequence[float], zeta: Sequence[float], k_N_m: Sequence[float],
                   shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Poles and residue matrices of the cell's modal model (unit shapes, modal stiffness).

    ``p_r = −ζ_r ω_r + jω_r√(1−ζ_r²)``, ``A_r = φ_r φ_rᵀ/(2jω_d m_r)``, ``m_r = k_r/ω_r²``,
    so that :func:`synthesize_frf` equals ``Σ φφᵀ/(k(1 − r² + 2jζr))``.

    Returns
    -------
    poles (n_modes,), residues (3, 3, n_modes)
    """
    wn = 2 * np.pi * np.asarray(f_hz, float)
    z = np.asarray(zeta, float)
    wd = wn * np.sqrt(1 - z**2)
    m = np.asarray(k_N_m, float) / wn**2
    phi = np.asarray(shapes, float)
    A = np.einsum("ri,rj->ijr", phi, phi) / (2j * wd * m)
    return -z * wn + 1j * wd, A


def modal_constants(ds: xr.Dataset, poles: np.ndarray, *,
                    band_hz: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """Residue matrices ``(3, 3, n_modes)`` of the measured FRFs at the given (windowed)
    poles by LSFD (sdypy-EMA, lower and upper residuals), and the synthesized FRF
    ``(3, 3, n_freq)`` on the dataset's frequencies (NaN outside the band and at DC)."""
    frf, freq = _frf_rows(ds)
    A, H, _, _ = _lsfd(np.asarray(poles, complex), frf, freq, band_hz)
    f_all = ds["frequency"].values
    synth = np.full((9, f_all.size), np.nan + 0j)
    inside = (freq >= band_hz[0]) & (freq <= band_hz[1])
    synth[:, np.flatnonzero(f_all > 0)[inside]] = H[:, inside]
    return A.reshape(3, 3, -1), synth.reshape(3, 3, -1)


def modes_table(poles: np.ndarray, residues: np.ndarray, *,
                poles_measured: np.ndarray | None = None,
                n_stable: Sequence[int] | None = None) -> pd.DataFrame:
    """Modal parameters at the tool tip from (window-corrected) poles and residue matrices.

    For each mode, ``R = 2jω_d A_r`` ≈ ``φφᵀ/m`` (real, symmetric, rank one for a
    proportionally damped mode); its largest eigenpair ``(λ, v)`` of the symmetric real part
    gives the unit shape ``φ = v`` (largest component positive), ``m = 1/λ`` and
    ``k = m ω_n²``. ``rank1`` = λ / Σ|eigenvalues| (1 for a clean single mode).

    Returns
    -------
    pandas.DataFrame
        ``mode, f_n_hz, zeta, k_modal_N_m, m_modal_kg, shape_x, shape_y, shape_z,
        zeta_windowed, rank1, n_stable``.
    """
    f, z = pole_f_zeta(poles)
    rows = []
    for r, p in enumerate(np.asarray(poles, complex)):
        R = 2j * p.imag * residues[:, :, r]
        S = np.real(R + R.T) / 2
        lam, vec = np.linalg.eigh(S)
        i = int(np.argmax(np.abs(lam)))
        v = vec[:, i] * np.sign(vec[np.argmax(np.abs(vec[:, i])), i])
        m = 1.0 / lam[i]
        wn = 2 * np.pi * f[r]
        row = {"mode": r + 1, "f_n_hz": f[r], "zeta": z[r], "k_modal_N_m": m * wn**2,
               "m_modal_kg": m, "shape_x": v[0], "shape_y": v[1], "shape_z": v[2]}
        row["zeta_windowed"] = (pole_f_zeta(poles_measured)[1][r]
                                if poles_measured is not None else z[r])
        row["rank1"] = float(np.abs(lam[i]) / np.sum(np.abs(lam)))
        row["n_stable"] = int(n_stable[r]) if n_stable is not None else 0
        rows.append(row)
    return pd.DataFrame(rows, columns=["mode", "f_n_hz", "zeta", "k_modal_N_m", "m_modal_kg",
                                       "shape_x", "shape_y", "shape_z", "zeta_windowed",
                                       "rank1", "n_stable"])


@dataclass
class Identification:
    """Everything :func:`identify` finds."""

    stabilization: pd.DataFrame
    selected: pd.DataFrame
    modes: pd.DataFrame
    residues: np.ndarray
    H_synth: np.ndarray


def identify(ds: xr.Dataset, *, band_hz: Sequence[float], max_order: int = 40,
             tol_f: float = 0.01, tol_zeta: float = 0.05, mac_min: float = 0.95,
             zeta_max: float = 0.2, cluster_tol: float = 0.01,
             min_stable: int = 5) -> Identification:
    """Stabilization chart → selected poles → residues (LSFD) → window-corrected modes."""
    stab = stabilization(ds, band_hz=band_hz, max_order=max_order, tol_f=tol_f,
                         tol_zeta=tol_zeta, mac_min=mac_min, zeta_max=zeta_max)
    sel = select_poles(stab, cluster_tol=cluster_tol, min_stable=min_stable)
    if sel.empty:
        raise ValueError("no stable pole in the band: lower min_stable or raise max_order")
    p_meas = sel["pole_real"].to_numpy() + 1j * sel["pole_imag"].to_numpy()
    residues, synth = modal_constants(ds, p_meas, band_hz=band_hz)
    p_true = correct_window_damping(p_meas, ds.attrs.get("window_sigma_per_s", 0.0))
    modes = modes_table(p_true, residues, poles_measured=p_meas,
                        n_stable=sel["n_stable"].to_numpy())
    return Identification(stab, sel, modes, residues, synth)
