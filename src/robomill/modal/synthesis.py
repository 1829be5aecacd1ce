"""FRF synthesis from poles and residues: the FRF convention, the residues of a modal model,
and the residues of measured FRFs by LSFD.

Convention (as in sdypy-EMA): ``H(ω) = Σ_r A_r/(jω − p_r) + A_r*/(jω − p_r*)``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr

from robomill.modal.lscf import _frf_rows, _lsfd


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
    """Residues ``(n_output, n_input, n_modes)`` of the measured FRFs at the given (windowed)
    poles by LSFD (sdypy-EMA, lower and upper residuals), and the synthesized FRF
    ``(n_output, n_input, n_freq)`` on the dataset's frequencies (NaN outside the band, at
    DC and for pairs the layout did not measure)."""
    frf, freq, measured = _frf_rows(ds)
    A, H, _, _ = _lsfd(np.asarray(poles, complex), np.nan_to_num(frf), freq, band_hz)
    n_o, n_i = ds.sizes["output"], ds.sizes["input"]
    f_all = ds["frequency"].values
    res = np.full((n_o * n_i, A.shape[1]), np.nan + 0j)
    res[measured] = A
    synth = np.full((n_o * n_i, f_all.size), np.nan + 0j)
    inside = (freq >= band_hz[0]) & (freq <= band_hz[1])
    rows = synth[measured]
    rows[:, np.flatnonzero(f_all > 0)[inside]] = H[:, inside]
    synth[measured] = rows
    return res.reshape(n_o, n_i, -1), synth.reshape(n_o, n_i, -1)
