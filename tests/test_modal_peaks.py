"""Peak picking on FRFs: every candidate is a local maximum of |Im H| that stands
out of its neighbourhood, never a shoulder or a ripple on a stronger mode's skirt; where none
qualifies the table is empty; peak frequencies are interpolated between the lines.

The truth is written independently of the estimator: the FRF is the textbook sum of
single-degree-of-freedom receptances ``1/(k (1 − r² + 2jζr))`` and the true extremum of
Im H is found on a grid 1000 times finer than the FRF's lines.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from robomill.modal.layout import frf_coords
from robomill.modal.peaks import PEAK_COLUMNS, interpolated_peak_hz, peak_picking

LINE_HZ = 0.25


def _receptance(f_hz, modes):
    """Σ 1/(k (1 − r² + 2jζr)) over ``modes`` = [(f_n, ζ, k)]."""
    f_hz = np.asarray(f_hz, float)
    h = np.zeros(f_hz.shape, complex)
    for fn, z, k in modes:
        r = f_hz / fn
        h += 1.0 / (k * (1 - r**2 + 2j * z * r))
    return h


def _ds(h, f_hz):
    """A one-FRF dataset (X/X), without coherence."""
    H = np.full((3, 3, f_hz.size), np.nan + 0j)
    H[0, 0] = h
    return xr.Dataset({"H": (("output", "input", "frequency"), H)}, coords=frf_coords(f_hz))


def _true_extrema_hz(modes, lo, hi):
    """Local maxima of |Im H| on a grid 1000 times finer than the lines."""
    fine = np.arange(lo, hi, LINE_HZ / 1000)
    m = np.abs(_receptance(fine, modes).imag)
    k = np.flatnonzero((m[1:-1] > m[:-2]) & (m[1:-1] > m[2:])) + 1
    return fine[k]


F = np.arange(0, 200 + LINE_HZ / 2, LINE_HZ)
STRONG = (40.1, 0.02, 1.0e6)  # a strong mode, its top between two lines
WEAK = (52.15, 0.02, 8.0e6)  # eight times stiffer: a weak mode beside it, off the lines
SHOULDER = (43.0, 0.08, 3.0e6)  # damped and close: no local maximum of its own


def test_a_weak_mode_beside_a_strong_one_is_found_at_its_interpolated_frequency():
    modes = [STRONG, WEAK]
    truth = _true_extrema_hz(modes, 30, 60)
    assert truth.size == 2
    table = peak_picking(_ds(_receptance(F, modes), F), band_hz=[30, 60])
    assert list(table.columns) == PEAK_COLUMNS
    assert table["f_line_hz"].tolist() == pytest.approx(
        [round(t / LINE_HZ) * LINE_HZ for t in truth])
    # the line alone is 0.1 and 0.1 Hz off; the parabola on log |Im H| a tenth of that
    err = np.abs(table["f_hz"].to_numpy() - truth)
    assert np.all(err < 0.01), err
    assert np.all(np.abs(table["f_line_hz"].to_numpy() - truth) > 0.05)
    assert np.all(table["prominence_db"] >= 3.0)


def test_a_shoulder_on_the_skirt_of_a_strong_mode_is_no_peak():
    modes = [STRONG, SHOULDER]
    assert _true_extrema_hz(modes, 30, 60).size == 1  # precondition: the shoulder has no top
    table = peak_picking(_ds(_receptance(F, modes), F), band_hz=[30, 60], prominence=1e-9,
                         floor_db=0.0)
    assert table["f_line_hz"].tolist() == [40.0]


def test_ripples_on_a_skirt_do_not_rise_above_their_floor():
    """A ±10 % ripple (at most ±0.8 dB) on the skirt makes local maxima; the global
    prominence criterion is switched off, so only the local floor rejects them."""
    h = _receptance(F, [STRONG])
    skirt = (F > 55) & (F < 75)
    h = h * np.where(skirt, 1 + 0.1 * np.sin(2 * np.pi * F / 2.0), 1.0)
    ds = _ds(h, F)
    kept = peak_picking(ds, band_hz=[30, 90], prominence=1e-9, floor_db=3.0)
    assert kept["f_line_hz"].tolist() == [40.0]
    loose = peak_picking(ds, band_hz=[30, 90], prominence=1e-9, floor_db=0.0)
    assert (loose["f_line_hz"] > 55).sum() >= 5  # the ripples are local maxima
    assert loose.loc[loose["f_line_hz"] > 55, "prominence_db"].max() < 20 * np.log10(1.1 / 0.9)


def test_no_peak_in_the_band_gives_an_empty_table():
    table = peak_picking(_ds(_receptance(F, [STRONG, WEAK]), F), band_hz=[120, 200])
    assert table.empty and list(table.columns) == PEAK_COLUMNS


def test_interpolation_is_exact_on_a_gaussian_line():
    """A Gaussian's log is a parabola: the interpolated top is the true one."""
    f = np.arange(0, 20, LINE_HZ)
    for f0 in (10.37, 10.5, 10.62):
        m = np.exp(-((f - f0) ** 2) / (2 * 0.4**2))
        k = int(np.argmax(m))
        assert interpolated_peak_hz(f, m, k) == pytest.approx(f0, abs=1e-9)
    m = np.ones_like(f)
    assert interpolated_peak_hz(f, m, 5) == f[5]  # a flat top stays on its line
    assert interpolated_peak_hz(f, m, 0) == f[0]  # no neighbour below
