"""The identification chain on an FRF dataset: stabilization chart → selected poles →
residues (LSFD) → window-corrected modes, shapes over the measured points, MAC matrix."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr

from robomill.modal.layout import points
from robomill.modal.lscf import correct_window_damping, pole_f_zeta, select_poles, stabilization
from robomill.modal.shapes import ModeShapes, mac_matrix
from robomill.modal.synthesis import modal_constants
from robomill.modal.tables import modes_table
from robomill.settings import schema_default


def coherence_at(ds: xr.Dataset, f_hz: Sequence[float]) -> np.ndarray:
    """Mean coherence of the measured FRFs at the lines nearest ``f_hz`` (NaN where the
    dataset has no coherence)."""
    if "coherence" not in ds:
        return np.full(len(f_hz), np.nan)
    f = ds["frequency"].values
    c = ds["coherence"].transpose("output", "input", "frequency").values
    c = c.reshape(-1, f.size)
    out = []
    for fr in f_hz:
        k = int(np.argmin(np.abs(f - fr)))
        col = c[:, k]
        out.append(float(np.nanmean(col)) if np.isfinite(col).any() else np.nan)
    return np.array(out)


@dataclass
class Identification:
    """Everything :func:`identify` finds."""

    stabilization: pd.DataFrame
    selected: pd.DataFrame
    modes: pd.DataFrame
    residues: np.ndarray
    H_synth: np.ndarray
    shapes: ModeShapes | None = None
    mac: np.ndarray | None = None


def identify(ds: xr.Dataset, *, band_hz: Sequence[float],
             max_order: int = schema_default("modal", "max_order"),
             tol_f: float = schema_default("modal", "tol_f"),
             tol_zeta: float = schema_default("modal", "tol_zeta"),
             mac_min: float = schema_default("modal", "mac_min"),
             zeta_max: float = schema_default("modal", "zeta_max"),
             cluster_tol: float = schema_default("modal", "cluster_tol"),
             min_stable: int = schema_default("modal", "min_stable"),
             coherence_min: float = schema_default("modal", "coherence_min")) -> Identification:
    """Stabilization chart over all measured FRFs → selected poles → residues (LSFD) →
    window-corrected modes, shapes over the measured points, MAC matrix, sanity flags."""
    stab = stabilization(ds, band_hz=band_hz, max_order=max_order, tol_f=tol_f,
                         tol_zeta=tol_zeta, mac_min=mac_min, zeta_max=zeta_max)
    sel = select_poles(stab, cluster_tol=cluster_tol, min_stable=min_stable)
    if sel.empty:
        raise ValueError("no stable pole in the band: lower min_stable or raise max_order")
    p_meas = sel["pole_real"].to_numpy() + 1j * sel["pole_imag"].to_numpy()
    residues, synth = modal_constants(ds, p_meas, band_hz=band_hz)
    p_true = correct_window_damping(p_meas, ds.attrs.get("window_sigma_per_s", 0.0))
    modes, shapes = modes_table(p_true, residues, poles_measured=p_meas,
                                n_stable=sel["n_stable"].to_numpy(),
                                outputs=points(ds, "output"), inputs=points(ds, "input"),
                                coherence=coherence_at(ds, pole_f_zeta(p_meas)[0]),
                                coherence_min=coherence_min)
    return Identification(stab, sel, modes, residues, synth, shapes,
                          mac_matrix(shapes.shapes))
