"""Chapter 3.2's peak-to-floor table on a planted spectrum."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.straightness import band_floor_table


def test_a_planted_line_stands_out_in_its_band_only():
    f = np.linspace(0.0, 20.0, 2001)
    power = np.ones((2, f.size))
    power[0, np.argmin(np.abs(f - 8.0))] = 500.0  # a line at 8 mm^-1 in run 0
    power[1, 0] = np.nan
    prof = xr.Dataset({"power_um2": (("run", "f"), power)},
                      coords={"run": ["a", "b"], "f": f,
                              "direction": ("run", ["py", "my"]),
                              "feed_mm_s": ("run", [8.0, 10.0])})
    pk = pd.DataFrame({"run": ["a", "a", "b"], "f_spatial_per_mm": [8.0, 3.0, 7.9]})
    t = band_floor_table(prof, pk, (7.0, 9.0), (17.0, 19.0))
    assert t["peak_to_floor_in_band"].tolist() == pytest.approx([500.0, 1.0])
    assert t["peak_to_floor_noise_band"].tolist() == pytest.approx([1.0, 1.0])
    assert t["peaks_in_band"].tolist() == [1, 1]
    assert t["direction"].tolist() == ["py", "my"]


def test_a_line_at_the_band_edge_is_judged_on_its_upper_side():
    """Just above ``fmin`` the neighbourhood below holds what the removed trend leaks: a
    strong line there stands only on its upper side. Judged on both sides it is refused; with
    ``one_sided_below=fmin`` it is found, and a bump on the leakage's own falling skirt (no
    line) is still refused."""
    from robomill import spectra

    f = np.arange(0.0, 2.0, 0.005)
    leak = 200.0 * np.exp(-f / 0.03)  # the trend's leakage, falling from f = 0
    line = 21.0 * np.exp(-0.5 * ((f - 0.095) / 0.008) ** 2)
    power = leak + line + 8.0  # above a noise floor of 8
    kw = dict(fmin=0.066, fmax=2.0, n=5, prominence_ratio=3.0, local_ratio=2.0,
              halfwidth_points=40, search_from=0.056)
    assert spectra.find_peaks_spectrum(f, power, **kw) == []
    found = spectra.find_peaks_spectrum(f, power, one_sided_below=0.066, **kw)
    assert len(found) == 1 and abs(found[0][0] - 0.095) <= 0.005
    assert spectra.find_peaks_spectrum(f, leak + 8.0, one_sided_below=0.066, **kw) == []


def test_a_line_on_the_leakage_skirt_above_fmin_is_judged_on_its_upper_side():
    """The removed trend's leakage can peak below ``fmin`` and still fall across it: a line
    on that skirt has a higher point on its left *above* ``fmin``, but climbing from it the
    left side reaches its summit below ``fmin``: it is judged on its upper side (found). A
    side lobe beside a strong line of the band climbs to that line instead: both sides
    (refused)."""
    from robomill import spectra

    f = np.arange(0.0, 2.0, 0.005)
    leak = 40.0 * np.exp(-0.5 * ((f - 0.045) / 0.03) ** 2)  # summit below fmin = 0.066
    line = 12.0 * np.exp(-0.5 * ((f - 0.095) / 0.006) ** 2)
    power = leak + line + 8.0
    kw = dict(fmin=0.066, fmax=2.0, n=5, prominence_ratio=3.0, local_ratio=2.0,
              halfwidth_points=40, search_from=0.056)
    assert power[np.searchsorted(f, 0.072)] > power[np.searchsorted(f, 0.095)]  # the case
    assert spectra.find_peaks_spectrum(f, power, **kw) == []
    found = spectra.find_peaks_spectrum(f, power, one_sided_below=0.066, **kw)
    assert len(found) == 1 and abs(found[0][0] - 0.095) <= 0.005
    # a strong line just above fmin with a side bump on its upper skirt: only the line
    strong = 400.0 * np.exp(-0.5 * ((f - 0.1) / 0.006) ** 2)
    bump = 12.0 * np.exp(-0.5 * ((f - 0.125) / 0.004) ** 2)
    got = spectra.find_peaks_spectrum(f, strong + bump + 8.0, one_sided_below=0.066, **kw)
    assert [round(x, 3) for x, _ in got] == [0.1]
