"""The chapter-4 tables from small planted chatter datasets."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from robomill.chatter.tables import coupling_table, onset_table


def test_onset_table_agrees_where_lobes_and_time_domain_agree():
    sim = xr.Dataset({
        "onset_check_rpm": ("check", [1000.0, 1000.0, 2000.0]),
        "onset_depth_fraction": ("check", [0.9, 1.1, 1.2]),
        "onset_a_boundary_mm": ("check", [1.0, 1.0, 2.0]),
        "onset_unstable": ("check", [False, True, False]),
        "onset_indicator_N": ("check", [0.1, 5.0, 0.2]),
        "onset_growth_rate_sdm_1_s": ("check", [-2.0, 3.0, 4.0]),
        "onset_growth_rate_simulated_1_s": ("check", [np.nan, 6.0, np.nan]),
    })
    t = onset_table(sim)
    assert t["lobes say unstable"].tolist() == [False, True, True]
    assert t["agree"].tolist() == [True, True, False]
    assert t["σ sim / SDM"].iloc[1] == pytest.approx(2.0)


def test_coupling_table_interpolates_the_chatter_frequency_at_the_thesis_speed():
    lobes = xr.Dataset(
        {"chatter_hz": (("direction", "solver", "spindle_rpm"),
                        np.array([[[100.0, 200.0]], [[300.0, 500.0]]])),
         "mode_coupling_a_mm": ("direction", [0.5, 0.7]),
         "mode_coupling_hz": ("direction", [61.0, 68.0]),
         "coupled_mode_hz": (("direction", "pair"), [[60.0, 67.0], [67.0, 70.0]]),
         "force_peak_min_hz": ("direction", [60.0, 62.0]),
         "force_peak_max_hz": ("direction", [120.0, 118.0])},
        coords={"direction": ["x", "y"], "solver": ["zoa"], "spindle_rpm": [27000.0, 29000.0]},
        attrs={"thesis_spindle_rpm": 28000.0})
    t = coupling_table(lobes)
    col = "regenerative chatter [Hz] (ZOA, 28 000 rpm)"
    assert t[col].tolist() == pytest.approx([150.0, 400.0])
    assert t["coupled pair [Hz]"].tolist() == ["60.0 & 67.0", "67.0 & 70.0"]
    assert t["force peaks [Hz] (min–max)"].tolist() == ["60–120", "62–118"]
