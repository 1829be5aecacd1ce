"""The chapter-3.3 tables the library computes: peak groups, truth check, mode coupling."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from robomill import modal


def _peaks(freqs, ok=None):
    ok = [True] * len(freqs) if ok is None else ok
    return pd.DataFrame({"output": ["X"] * len(freqs), "input": list("XYZXYZXYZ"[:len(freqs)]),
                         "f_hz": freqs, "natural_frequency": ok})


def test_planted_peaks_group_into_their_frequencies():
    # two groups of three FRFs each, 0.25 Hz lines; a peak failing the criteria is ignored
    p = _peaks([20.0, 20.25, 20.5, 35.0, 35.25, 35.0, 50.0],
               ok=[True] * 6 + [False])
    g = modal.group_peaks(p, 0.25)
    assert g["f_hz"].tolist() == [20.25, 35.0]
    assert g["n_frfs"].tolist() == [3, 3]
    assert g["reference_hz"].tolist() == [20.0, 35.0]
    assert g["offset_hz"].tolist() == pytest.approx([0.25, 0.0])
    assert g.loc[0, "frfs"] == "X/X, X/Y, X/Z"


def test_peaks_further_apart_than_the_gap_split():
    g = modal.group_peaks(_peaks([60.0, 61.0]), 0.25, gap_lines=3)  # 4 lines apart
    assert len(g) == 2
    assert len(modal.group_peaks(_peaks([60.0, 60.5]), 0.25, gap_lines=3)) == 1


def test_no_accepted_peak_gives_an_empty_table():
    g = modal.group_peaks(_peaks([20.0], ok=[False]), 0.25)
    assert g.empty and "f_hz" in g.columns


def _modes():
    return pd.DataFrame({"mode": [1, 2, 3], "f_n_hz": [20.2, 60.0, 66.0],
                         "zeta": [0.02, 0.03, 0.011], "k_modal_N_m": [1.1e6, 2e6, 3e6],
                         "shape_x": [1.0, 1.0, 0.0], "shape_y": [0.0, 0.0, 1.0],
                         "shape_z": [0.0, 0.0, 0.0]})


def test_truth_check_matches_nearest_and_measures_errors_and_mac():
    shape_true = np.array([[1.0, 0, 0], [np.sqrt(0.5), np.sqrt(0.5), 0]])
    t = modal.truth_check(_modes(), [20.0, 59.0], [0.02, 0.03], [1e6, 2e6], shape_true)
    assert t["mode"].tolist() == [1, 2]
    assert t["f_err_pct"].tolist() == pytest.approx([1.0, 100 * (60 / 59 - 1)])
    assert t["k_err_pct"].tolist() == pytest.approx([10.0, 0.0])
    assert t["shape_mac"].tolist() == pytest.approx([1.0, 0.5])


def test_mode_coupling_finds_close_modes_and_their_angle():
    per_mode, pairs = modal.mode_coupling(_modes(), 62.0)
    assert per_mode["close"].tolist() == [False, True, True]
    assert per_mode["offset_fraction"].iloc[2] == pytest.approx(66 / 62 - 1)
    assert pairs[["mode_a", "mode_b"]].values.tolist() == [[2, 3]]
    assert pairs["shape_angle_deg"].iloc[0] == pytest.approx(90.0)
    # just outside ±15 %: nothing close
    per_mode, pairs = modal.mode_coupling(_modes(), 80.0, tolerance=0.15)
    assert not per_mode["close"].any() and pairs.empty


def test_mode_coupling_refuses_a_missing_vibration_frequency():
    with pytest.raises(ValueError, match="positive"):
        modal.mode_coupling(_modes(), float("nan"))


def test_misfit_is_zero_for_the_same_frf_and_ten_percent_for_a_scaled_one():
    import xarray as xr

    f = np.linspace(0.0, 100.0, 401)
    H = np.ones((3, 3, f.size), complex) / (1 + 1j * f)
    ds = xr.Dataset({"H": (("output", "input", "frequency"), H)}, coords=modal.frf_coords(f))
    assert np.allclose(modal.synthesis_misfit(ds, H, [10, 90]).to_numpy(), 0.0)
    m = modal.synthesis_misfit(ds, 1.1 * H, [10, 90])
    assert np.allclose(m.to_numpy(), 10.0)
    assert m.index[0] == "out X" and m.columns[2] == "in Z"
