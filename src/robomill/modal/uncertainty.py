"""Intervals of the identified modes (natural frequency, damping ratio, modal stiffness) from
the scatter of the hits behind the FRFs, by a parametric bootstrap of the identification.

An FRF averaged over ``n_d`` hits with ordinary coherence γ² has the normalized random error
``ε = √(1 − γ²) / (|γ| √(2 n_d))`` in magnitude and ε radians in phase (Bendat & Piersol
2010, eq. 9.90 and §9.2.3): that is how far another set of ``n_d`` hits would move it. Each
bootstrap replicate draws ``H* = H (1 + ε (u + j v))`` (u, v standard normal, independent per
line and FRF), identifies the poles again at each mode's own model order of the
stabilization chart (LSCF, sdypy-EMA), removes the window's damping, takes the residues at
those poles (LSFD) and the modal stiffness from them (:func:`robomill.modal.tables.
modes_table`). A dataset without coherence (FRFs imported as such) uses the relative
residual of the identified model instead (``|H − H_synth| / |H|`` over the band), i.e. the
scatter the model did not explain. The interval of each parameter is the bias-corrected
bootstrap standard-error interval ``value − b* ± z σ*`` (Efron & Tibshirani 1993, §10.6 and
§13.2: b* = mean of the replicates − value, the estimator's bias under the FRF noise, which
for LSCF poles is not negligible; σ* their standard deviation), z the normal quantile of the
two-sided ``level``, stretched to hold the value itself; damping and stiffness are kept
positive (their low end not below a tenth of the value).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.modal.layout import points
from robomill.modal.lscf import _frf_rows, correct_window_damping, pole_f_zeta
from robomill.modal.synthesis import modal_constants
from robomill.modal.tables import modes_table
from robomill.settings import schema_default

INTERVAL_COLUMNS = ("f_n_hz_low", "f_n_hz_high", "zeta_low", "zeta_high", "k_modal_N_m_low",
                    "k_modal_N_m_high")
"""Interval columns of ``results/modal/modes.csv`` (after :data:`robomill.modal.tables.
MODE_COLUMNS`)."""


def relative_error(ds: xr.Dataset, synth: np.ndarray | None = None) -> np.ndarray:
    """Normalized random error ε of every FRF line ``(output, input, frequency)`` (module
    docstring): from the coherence and the hits averaged, or, without coherence, the rms
    relative residual of the synthesized FRF ``synth`` over its band (one value)."""
    H = ds["H"].transpose("output", "input", "frequency").values
    if "coherence" in ds and np.isfinite(ds["coherence"].values).any():
        g2 = np.clip(ds["coherence"].transpose("output", "input", "frequency").values,
                     1e-6, 1.0)
        nd = (ds["n_hits"].values if "n_hits" in ds else np.ones(H.shape[:2]))
        nd = np.maximum(np.asarray(nd, float), 1.0)[..., None]
        return np.nan_to_num(np.sqrt(1 - g2) / (np.sqrt(g2) * np.sqrt(2 * nd)))
    if synth is None:
        return np.zeros(H.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.abs(H - synth) / np.abs(H)
    r = r[np.isfinite(r)]
    return np.full(H.shape, float(np.sqrt(np.mean(r ** 2))) if r.size else 0.0)


def _poles_at(ds_rep: xr.Dataset, band_hz, orders: np.ndarray, f_ref: np.ndarray,
              tol: float) -> np.ndarray:
    """Poles of the replicate nearest each reference frequency at each mode's own LSCF model
    order (NaN where none lies within ``tol`` relative)."""
    from sdypy import EMA

    frf, freq, _ = _frf_rows(ds_rep)
    model = EMA.Model(frf=np.nan_to_num(frf), freq=freq, lower=band_hz[0], upper=band_hz[1],
                      pol_order_high=int(np.max(orders) // 2), frf_form="receptance")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model.get_poles(method="lscf", show_progress=False)
    out = np.full(len(f_ref), np.nan + 0j)
    for r, (order, f0) in enumerate(zip(orders, f_ref, strict=True)):
        p = np.asarray(model.all_poles[int(order) // 2 - 1], complex)
        p = p[p.imag > 0]
        if p.size == 0:
            continue
        fp, _ = pole_f_zeta(p)
        j = int(np.argmin(np.abs(fp - f0)))
        if abs(fp[j] - f0) <= tol * f0:
            out[r] = p[j]
    return out


def mode_intervals(ds: xr.Dataset, modes: pd.DataFrame, selected: pd.DataFrame, *,
                   band_hz: Sequence[float], synth: np.ndarray | None = None,
                   level: float = schema_default("plan", "interval_level"), n_boot: int = 30,
                   seed: int = 0,
                   tol: float = 0.05) -> pd.DataFrame:
    """``modes`` with :data:`INTERVAL_COLUMNS` from the bootstrap of the module docstring.

    Parameters
    ----------
    ds
        The FRF dataset the modes were identified from (``H``, optional ``coherence`` and
        ``n_hits``; attribute ``window_sigma_per_s``).
    modes
        The identified mode table (:func:`robomill.modal.identification.identify`).
    selected
        The selected poles with their model ``order`` (``Identification.selected``), one row
        per mode in the same order.
    synth
        The synthesized FRF (used only without coherence).
    """
    from scipy import stats

    out = modes.copy()
    for c in INTERVAL_COLUMNS:
        out[c] = np.nan
    if modes.empty:
        return out
    rng = np.random.default_rng(seed)
    eps = relative_error(ds, synth)
    H = ds["H"].transpose("output", "input", "frequency").values
    sigma = float(ds.attrs.get("window_sigma_per_s", 0.0))
    orders = selected["order"].to_numpy(int)
    f0 = pole_f_zeta(selected["pole_real"].to_numpy() + 1j * selected["pole_imag"].to_numpy())[0]
    samples = []
    for _ in range(int(n_boot)):
        noise = rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape)
        rep = ds.copy()
        rep["H"] = (("output", "input", "frequency"), H * (1 + eps * noise))
        p = _poles_at(rep, band_hz, orders, f0, tol)
        ok = np.isfinite(p)
        if not ok.any():
            continue
        res, _ = modal_constants(rep, p[ok], band_hz=band_hz)
        tab, _ = modes_table(correct_window_damping(p[ok], sigma), res,
                             outputs=points(rep, "output"), inputs=points(rep, "input"))
        row = np.full((len(p), 3), np.nan)
        row[ok] = tab[["f_n_hz", "zeta", "k_modal_N_m"]].to_numpy(float)
        samples.append(row)
    if len(samples) < 2:
        return out
    boot = np.array(samples)
    sd = np.nanstd(boot, axis=0, ddof=1)                                   # (modes, 3)
    bias = np.nanmean(boot, axis=0) - out[["f_n_hz", "zeta", "k_modal_N_m"]].to_numpy(float)
    z = float(stats.norm.ppf(0.5 + level / 2))
    for k, name in enumerate(("f_n_hz", "zeta", "k_modal_N_m")):
        v = out[name].to_numpy(float)
        centre = v - bias[:, k]
        lo = np.minimum(centre - z * sd[:, k], v)
        hi = np.maximum(centre + z * sd[:, k], v)
        if name != "f_n_hz":
            lo = np.maximum(lo, 0.1 * v)
        out[f"{name}_low"], out[f"{name}_high"] = lo, hi
    return out
