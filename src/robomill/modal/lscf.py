"""Poles by the LSCF stabilization chart: least-squares complex-frequency poles
(common-denominator over all measured FRFs, sdypy-EMA) at model orders 2…2·``max_order``,
their stability between orders, the selection of the physical poles, and the removal of the
exponential window's damping.

A pole is *stable* when the previous order has a pole within ``tol_f`` in frequency,
``tol_zeta`` in damping and with residue vectors (LSFD at each order) of MAC ≥ ``mac_min``;
stable poles are grouped by frequency, and groups of at least ``min_stable`` orders are
physical modes (Peeters et al., *Shock and Vibration* 11, 2004, the PolyMAX/LSCF chart).
A window ``e^{−σt}`` on a free decay ``Σ A_r e^{p_r t}`` shifts every pole to ``p_r − σ``
and leaves the residues unchanged, so the identified poles are corrected by ``+σ``.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.modal.shapes import _mac
from robomill.settings import schema_default


def _frf_rows(ds: xr.Dataset, var: str = "H") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The measured FRFs as rows ``(n_measured, nf)`` (output-major; a pair is measured when
    it has a finite value above DC), their frequencies (DC dropped), and the flat indices of
    the measured pairs in the ``(output, input)`` grid."""
    f = ds["frequency"].values
    h = ds[var].transpose("output", "input", "frequency").values
    h = h.reshape(h.shape[0] * h.shape[1], -1)
    keep = f > 0
    measured = np.flatnonzero(np.isfinite(h[:, keep]).any(axis=1))
    return h[measured][:, keep], f[keep], measured


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


def pole_f_zeta(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequency [Hz] and damping ratio of poles ``p = −ζω_n ± jω_n√(1−ζ²)``."""
    p = np.asarray(poles, complex)
    wn = np.abs(p)
    with np.errstate(divide="ignore", invalid="ignore"):
        return wn / (2 * np.pi), -p.real / wn


def stabilization(ds: xr.Dataset, *, band_hz: Sequence[float],
                  max_order: int = schema_default("modal", "max_order"),
                  tol_f: float = schema_default("modal", "tol_f"),
                  tol_zeta: float = schema_default("modal", "tol_zeta"),
                  mac_min: float = schema_default("modal", "mac_min"),
                  zeta_max: float = schema_default("modal", "zeta_max")) -> pd.DataFrame:
    """Stabilization chart: LSCF poles (sdypy-EMA) at every model order, with their status.

    For each order (denominator degree 2, 4, …, 2·``max_order``) the poles with positive
    imaginary part, frequency in ``band_hz`` and 0 < ζ < ``zeta_max`` are kept; their residues
    over all measured FRFs (any layout: :func:`_frf_rows`) come from LSFD at that order.
    Each pole is compared with the nearest pole of the previous order: status ``new``,
    ``f`` (frequency within ``tol_f`` relative), ``fd`` (and damping within ``tol_zeta``
    relative), ``stable`` (and MAC of the residue vectors ≥ ``mac_min``).

    Returns
    -------
    pandas.DataFrame
        ``order, f_hz, zeta, pole_real, pole_imag, status`` (poles of the windowed FRFs).
    """
    from sdypy import EMA

    frf, freq, _ = _frf_rows(ds)
    frf = np.nan_to_num(frf)
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


def select_poles(stab: pd.DataFrame, *, cluster_tol: float = schema_default("modal", "cluster_tol"),
                 min_stable: int = schema_default("modal", "min_stable")) -> pd.DataFrame:
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
