"""Intervals of the identified modes from the scatter of the hits (parametric bootstrap)."""

import numpy as np
import xarray as xr

from robomill.modal.identification import identify
from robomill.modal.layout import frf_coords
from robomill.modal.synthesis import modal_residues, synthesize_frf
from robomill.modal.uncertainty import INTERVAL_COLUMNS, mode_intervals

TRUE_F = np.array([30.0, 55.0])
TRUE_Z = np.array([0.04, 0.03])
TRUE_K = np.array([1.0e6, 2.0e6])
SHAPES = np.array([[1.0, 0.3, 0.1], [0.2, 1.0, 0.3]])
SHAPES = SHAPES / np.linalg.norm(SHAPES, axis=1, keepdims=True)


def dataset(coherence, seed=0):
    """A 3×3 tool-tip receptance FRF of two planted modes, with the random error of an
    average over 5 hits at the given coherence written independently: magnitude and phase
    scatter of standard deviation √(1−γ²)/(γ√10) (one draw)."""
    f = np.arange(0, 200.25, 0.25)
    p, A = modal_residues(TRUE_F, TRUE_Z, TRUE_K, SHAPES)
    H = synthesize_frf(p, A, f)
    rng = np.random.default_rng(seed)
    e = np.sqrt(1 - coherence) / (np.sqrt(coherence) * np.sqrt(10))
    H = H * (1 + e * (rng.standard_normal(H.shape) + 1j * rng.standard_normal(H.shape)))
    ds = xr.Dataset({"H": (("output", "input", "frequency"), H),
                     "coherence": (("output", "input", "frequency"),
                                   np.full(H.shape, coherence)),
                     "n_hits": (("output", "input"), np.full((3, 3), 5))},
                    coords=frf_coords(f))
    ds.attrs["window_sigma_per_s"] = 0.0
    return ds


def intervals(coherence):
    ds = dataset(coherence)
    idn = identify(ds, band_hz=[10.0, 100.0], max_order=12, min_stable=3)
    return mode_intervals(ds, idn.modes, idn.selected, band_hz=[10.0, 100.0], n_boot=25)


def test_intervals_bracket_the_value_and_grow_with_the_hits_scatter():
    clean, noisy = intervals(0.999), intervals(0.97)
    assert len(noisy) == 2 and set(INTERVAL_COLUMNS) <= set(noisy.columns)
    for name in ("f_n_hz", "zeta", "k_modal_N_m"):
        lo, hi, v = (noisy[f"{name}_low"].to_numpy(), noisy[f"{name}_high"].to_numpy(),
                     noisy[name].to_numpy())
        assert np.all(lo < v) and np.all(v < hi)
        w_clean = (clean[f"{name}_high"] - clean[f"{name}_low"]).to_numpy()
        assert np.all(hi - lo > 2 * w_clean)
    # the intervals are of the size of the planted error: within 1 % of f, 15 % of zeta
    assert np.all(np.abs(noisy["f_n_hz"] - TRUE_F) < 0.01 * TRUE_F)
    assert np.all(noisy["zeta_high"] - noisy["zeta_low"] < 0.15 * TRUE_Z)
    assert np.all(np.abs(noisy["zeta"] - TRUE_Z) < 0.15 * TRUE_Z)
