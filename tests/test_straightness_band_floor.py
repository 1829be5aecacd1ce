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
    pk = pd.DataFrame({"direction": ["py", "py", "my"], "feed_mm_s": [8.0, 8.0, 10.0],
                       "f_spatial_per_mm": [8.0, 3.0, 7.9]})
    t = band_floor_table(prof, pk, (7.0, 9.0), (17.0, 19.0))
    assert t["peak_to_floor_in_band"].tolist() == pytest.approx([500.0, 1.0])
    assert t["peak_to_floor_noise_band"].tolist() == pytest.approx([1.0, 1.0])
    assert t["peaks_in_band"].tolist() == [1, 1]
    assert t["direction"].tolist() == ["py", "my"]
