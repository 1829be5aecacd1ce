"""Chapter 3.1's tables (robomill.forces.tables) from planted artefacts: the peak table with
'none' for an empty peak and the nearest mode, the harmonics' medians per tooth-passing
frequency, the coefficients against the planted values and each cut's process."""

import numpy as np
import pandas as pd
import pytest

from robomill.forces.tables import (
    coefficient_table,
    direction_text,
    harmonic_table,
    peak_table,
    process_table,
)

PEAKS = pd.DataFrame({"cut": ["a", "b"], "dominant_hz": [61.0, np.nan],
                      "kinematic_per_mm": [np.nan, 0.5]})
MEANS = pd.DataFrame({"cut": ["a", "b"], "feed_mm_s": [1.0, 2.0], "depth_mm": [0.5, 0.5],
                      "direction": ["py", "px"], "F_feed_N": [-1.0, -2.0],
                      "F_cross_feed_N": [1.0, 2.0], "F_axial_N": [0.1, 0.2]})
MODES = pd.DataFrame({"mode": [1, 2], "f_n_hz": [20.0, 60.0]})


def test_peak_table_thesis_and_levels():
    thesis = peak_table(PEAKS, MEANS, MODES, levels=False)
    assert thesis.loc[0, "kinematic_per_mm"] == "none" and thesis.loc[1, "dominant_hz"] == "none"
    assert thesis.loc[0, "nearest_mode_hz"] == 60.0 and thesis.loc[0, "offset_hz"] == 1.0
    assert {"feed_mm_s", "depth_mm", "direction"} <= set(thesis.columns)
    levels = peak_table(PEAKS, MEANS, None, levels=True)
    assert list(levels.columns) == ["cut", "dominant_hz", "kinematic_per_mm", "F_feed_N",
                                    "F_cross_feed_N", "F_axial_N"]


def test_harmonic_medians_per_tooth_passing_frequency():
    """Cuts a, b at 1000 Hz tooth passing, c at 1500 Hz: one block per frequency; the power
    is the sum over the axes (6 and 12 at 1000 Hz: median 9; 15 at 1500 Hz)."""
    hm = pd.DataFrame({"cut": ["a", "b", "c"], "harmonic": [1, 1, 1],
                       "f_hz": [1000.0, 1000.0, 1500.0], "Fx_power_N2": [1.0, 2.0, 5.0],
                       "Fy_power_N2": [2.0, 4.0, 5.0], "Fz_power_N2": [3.0, 6.0, 5.0]})
    cuts = pd.DataFrame({"cut": ["a", "b", "c"], "tooth_passing_hz": [1000.0, 1000.0, 1500.0]})
    t = harmonic_table(hm, cuts)
    assert t.loc[(1000.0, 1), "power_N2"] == pytest.approx(9.0)
    assert t.loc[(1500.0, 1), "power_N2"] == pytest.approx(15.0)
    one = harmonic_table(hm[hm.cut != "c"], cuts)
    assert list(one.index) == [1]


def test_coefficients_against_planted_and_process_defaults():
    coef = pd.DataFrame({"name": ["Ktc", "Kte"], "value": [110.0, 9.0], "ci_low": [0, 0],
                         "ci_high": [0, 0], "unit": ["N/mm^2", "N/mm"]})
    t = coefficient_table(coef, {"Ktc": 100.0, "Kte": 10.0})
    assert t.loc["Ktc", "error_pct"] == pytest.approx(10.0)
    assert t.loc["Kte", "error_pct"] == pytest.approx(-10.0)
    assert "planted" not in coefficient_table(coef, {}).columns
    p = process_table(MEANS.assign(radial_immersion=[1.0, 0.5]), {"flutes": 3})
    assert p["flutes"].tolist() == [3, 3] and p["milling"].tolist() == ["slot", "down"]
    assert process_table(MEANS, None)["flutes"].tolist() == [2, 2]
    assert direction_text("my") == "−Y" and direction_text("45 deg") == "45°"
