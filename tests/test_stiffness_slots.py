"""Chapter-5 slot table: mean stiffness per direction beside Table 2.1, and the ±Y spread."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from robomill import stiffness


def test_slot_table_means_and_waviness_and_spread():
    slots = pd.DataFrame({"model": ["combined"] * 4, "direction": ["py", "py", "my", "px"],
                          "k_feed_N_m": [1e6, 3e6, 2e6, 4e6],
                          "k_normal_N_m": [1.1e6, 1.1e6, 1.0e6, 5e6],
                          "k_axial_N_m": [9e6] * 4})
    wav = pd.DataFrame({"s1_px": [0.5, 0.7], "s1_py": [2.0, 4.0], "s2_py": [3.0, 3.0],
                        "s1_my": [1.0, 1.0]}, index=pd.Index([1, 2], name="segment"))
    t = stiffness.slot_stiffness_table(slots, wav)
    assert t.loc[("combined", "py"), "k feed N/µm"] == pytest.approx(2.0)
    assert t.loc[("combined", "py"), "waviness RMS µm (Table 2.1, mean)"] == pytest.approx(3.0)
    assert t.loc[("combined", "px"), "waviness RMS µm (Table 2.1, mean)"] == pytest.approx(0.6)
    kn = t.loc["combined"]["k normal N/µm"]
    assert stiffness.stiffness_spread_pct(kn) == pytest.approx(10.0)
    assert np.isnan(stiffness.stiffness_spread_pct(kn.drop("my")))
    assert np.isnan(stiffness.waviness_by_direction(wav[["s1_px"]])["py"])
