"""What the chapter checks against the modes: planted truth (synthetic runs), the misfit of
the FRF synthesized from them, and the coupling of modes near the vibration frequency seen
while cutting (thesis §3.3)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd
import xarray as xr

from robomill.modal.shapes import _mac

COUPLING_TOLERANCE = 0.15
"""A mode is "close" to the vibration frequency within this fraction of it (thesis §3.3)."""


def truth_check(modes: pd.DataFrame, f_true_hz: Sequence[float], zeta_true: Sequence[float],
                k_true_N_m: Sequence[float], shape_true: np.ndarray) -> pd.DataFrame:
    """Identified modes against planted ones (synthetic runs).

    Each planted mode is matched with the identified mode nearest in frequency; errors are
    relative, ``100 (identified/true − 1)`` %, and the shapes are compared by the modal
    assurance criterion ``MAC = |φ_trueᴴ φ|² / (φ_trueᴴ φ_true · φᴴ φ)`` (Allemang & Brown
    1982) of the tool-tip shape ``(shape_x, shape_y, shape_z)``.

    Parameters
    ----------
    modes
        ``results/modal/modes.csv`` (``mode, f_n_hz, zeta, k_modal_N_m, shape_x, shape_y,
        shape_z``).
    f_true_hz, zeta_true, k_true_N_m
        The planted natural frequencies [Hz], damping ratios and modal stiffnesses [N/m].
    shape_true
        ``(n_true, 3)`` planted tool-tip shapes.

    Returns
    -------
    pandas.DataFrame
        ``true_mode, f_true_hz, zeta_true, k_true_N_m, mode, f_n_hz, zeta, f_err_pct,
        zeta_err_pct, k_err_pct, shape_mac``.
    """
    cols = ["true_mode", "f_true_hz", "zeta_true", "k_true_N_m", "mode", "f_n_hz", "zeta",
            "f_err_pct", "zeta_err_pct", "k_err_pct", "shape_mac"]
    shape_true = np.atleast_2d(np.asarray(shape_true, float))
    rows = []
    if len(modes) == 0:
        return pd.DataFrame(columns=cols)
    f_id = modes["f_n_hz"].to_numpy(float)
    for r, (ft, zt, kt) in enumerate(zip(f_true_hz, zeta_true, k_true_N_m, strict=True)):
        m = modes.iloc[int(np.argmin(np.abs(f_id - ft)))]
        phi = m[["shape_x", "shape_y", "shape_z"]].to_numpy(float)
        rows.append({"true_mode": r + 1, "f_true_hz": float(ft), "zeta_true": float(zt),
                     "k_true_N_m": float(kt), "mode": int(m["mode"]),
                     "f_n_hz": float(m["f_n_hz"]), "zeta": float(m["zeta"]),
                     "f_err_pct": 100 * (m["f_n_hz"] / ft - 1),
                     "zeta_err_pct": 100 * (m["zeta"] / zt - 1),
                     "k_err_pct": 100 * (m["k_modal_N_m"] / kt - 1),
                     "shape_mac": _mac(shape_true[r], phi)})
    return pd.DataFrame(rows, columns=cols)


def mode_coupling(modes: pd.DataFrame, vibration_hz: float, *,
                  tolerance: float = COUPLING_TOLERANCE) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Which modes lie near the vibration frequency seen while cutting (thesis §3.3).

    The thesis concludes that two modes close to the cutting vibration frequency, excited
    together with non-parallel shapes, drive an elliptical tool path (mode coupling). A mode
    is close when ``|f_n/f_vib − 1| ≤ tolerance``; for each pair of close modes the angle
    between their unit tool-tip shapes is ``arccos |φ_a · φ_b|`` (0° parallel, 90°
    orthogonal).

    Parameters
    ----------
    modes
        ``results/modal/modes.csv`` (``mode, f_n_hz, shape_x, shape_y, shape_z``).
    vibration_hz
        The dominant vibration frequency while cutting [Hz] (chapter 3.1's median
        ``dominant_hz``).
    tolerance
        Relative distance that counts as close (thesis: ±15 %).

    Returns
    -------
    (pandas.DataFrame, pandas.DataFrame)
        Per mode: ``mode, f_n_hz, vibration_hz, offset_fraction, close``; per pair of
        close modes: ``mode_a, mode_b, f_a_hz, f_b_hz, shape_angle_deg``.
    """
    if not np.isfinite(vibration_hz) or vibration_hz <= 0:
        raise ValueError(f"vibration frequency must be a positive number of Hz, got "
                         f"{vibration_hz!r}")
    f_n = modes["f_n_hz"].to_numpy(float)
    offset = f_n / float(vibration_hz) - 1
    per_mode = pd.DataFrame({"mode": modes["mode"].to_numpy(int), "f_n_hz": f_n,
                             "vibration_hz": float(vibration_hz), "offset_fraction": offset,
                             "close": np.abs(offset) <= tolerance})
    close = modes[per_mode["close"].to_numpy()]
    shapes = close[["shape_x", "shape_y", "shape_z"]].to_numpy(float)
    norms = np.linalg.norm(shapes, axis=1)
    rows = []
    for a in range(len(close)):
        for b in range(a + 1, len(close)):
            cos = abs(float(shapes[a] @ shapes[b])) / (norms[a] * norms[b])
            rows.append({"mode_a": int(close.iloc[a]["mode"]),
                         "mode_b": int(close.iloc[b]["mode"]),
                         "f_a_hz": float(close.iloc[a]["f_n_hz"]),
                         "f_b_hz": float(close.iloc[b]["f_n_hz"]),
                         "shape_angle_deg": float(np.degrees(np.arccos(min(1.0, cos))))})
    pairs = pd.DataFrame(rows, columns=["mode_a", "mode_b", "f_a_hz", "f_b_hz",
                                        "shape_angle_deg"])
    return per_mode, pairs


def synthesis_misfit(ds: xr.Dataset, H_synth: np.ndarray, band_hz: Sequence[float]
                     ) -> pd.DataFrame:
    """Relative misfit ``‖H_synth − H‖₂ / ‖H‖₂`` [%] per FRF over the analysis band.

    The norms run over the frequency lines inside ``band_hz`` where the synthesized FRF is
    finite; a pair the layout did not measure is NaN.

    Returns
    -------
    pandas.DataFrame
        Index ``out <output>``, columns ``in <input>``: the misfit in percent.
    """
    f = ds["frequency"].values
    H = ds["H"].transpose("output", "input", "frequency").values
    Hs = np.asarray(H_synth)
    inb = (f >= band_hz[0]) & (f <= band_hz[1]) & np.isfinite(Hs).any(axis=(0, 1))
    with np.errstate(invalid="ignore", divide="ignore"):
        err = (np.linalg.norm((Hs - H)[..., inb], axis=-1)
               / np.linalg.norm(H[..., inb], axis=-1))
    return pd.DataFrame(100 * err, index=[f"out {o}" for o in ds["output"].values],
                        columns=[f"in {i}" for i in ds["input"].values])
