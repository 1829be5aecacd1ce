"""The tables chapter 3.3 shows, built from the modal stage's artefacts (the chapter loads,
plots and renders; it builds nothing itself)."""

from __future__ import annotations

from collections.abc import Sequence

import pandas as pd
import xarray as xr

from robomill.modal.checks import synthesis_misfit

MODE_ROUNDING = {"f_n_hz": 3, "zeta": 4, "zeta_windowed": 4, "k_modal_N_m": 0, "m_modal_kg": 3,
                 "shape_x": 3, "shape_y": 3, "shape_z": 3, "rank1": 3, "coherence": 3}
"""Decimals of each column of the mode table as chapter 3.3 shows it (Table 3.13)."""

HIT_COLUMNS_SHOWN = ["direction", "hit", "accepted", "reason", "peak_force_N"]
"""The columns of ``hits.csv`` chapter 3.3 shows (Table 3.11)."""


def shown_hits(hits: pd.DataFrame) -> pd.DataFrame:
    """Table 3.11: each recorded hit, accepted or rejected and why (empty: FRFs imported)."""
    return hits[HIT_COLUMNS_SHOWN] if len(hits) else hits


def shown_modes(modes: pd.DataFrame) -> pd.DataFrame:
    """Table 3.13: ``modes.csv`` rounded (:data:`MODE_ROUNDING`)."""
    return modes.round(MODE_ROUNDING)


def shown_peak_groups(groups: pd.DataFrame) -> pd.DataFrame:
    """Table 3.12: the peak groups (``peak_groups.csv``) of this study, rounded; the nearest
    reference frequency of the thesis and the offset from it (``reference_hz``,
    ``offset_hz``) are left to the chapter's "Against the thesis" (its comparison rows)."""
    return groups.drop(columns=["reference_hz", "offset_hz"], errors="ignore").round(2)


def misfit_table(ds: xr.Dataset, synth: xr.Dataset, band_hz: Sequence[float]) -> pd.DataFrame:
    """Table 3.15: the relative misfit ‖H_synth − H‖/‖H‖ [%] of each measured FRF over the
    band (:func:`robomill.modal.checks.synthesis_misfit`), rounded to 0.01 %."""
    return synthesis_misfit(ds, synth["H_synth"].values, band_hz).round(2)
